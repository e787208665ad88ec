// motion_shadows/receiver_path.glsl: a receiver that moves during the shutter, its path walked
// texel by texel through the light's map: ms_lit_fraction_moving and the resumable walk.
//
// Part of the public include motion_shadows.glsl, which includes its parts in order (each
// uses the ones before it) and is what a shader includes; GLSL_INCLUDE is the parts
// concatenated. Every name starts with ms_ / Ms / MS_.

// ---- receivers that move during the shutter ----

// Narrows [lo, hi] to the times t at which g0 + t * dg >= 0.
void ms_clip_times(float g0, float dg, inout float lo, inout float hi) {
    if (dg > 0.0) {
        lo = max(lo, -g0 / dg);
    } else if (dg < 0.0) {
        hi = min(hi, -g0 / dg);
    } else if (g0 < 0.0) {
        hi = lo;
    }
}

// The time at which the linear clip-space path c0 + t * dc crosses the texel boundary at
// normalized coordinate `edge` on axis `axis` (x/w = edge: linear in t even for a spot
// light's projection); 2 where it never does.
float ms_boundary_time(vec4 c0, vec4 dc, int axis, float edge) {
    float den = dc[axis] - edge * dc.w;
    return den != 0.0 ? -(c0[axis] - edge * c0.w) / den : 2.0;
}

// A point's linear path as the light's map sees it: its clip position c0 + t dc, the times
// [lo, hi] it spends inside the light's view (x/w and y/w in [-1, 1], w > 0), and the texel it
// is in from `t` on, walked texel by texel (ms_path_advance) in the one direction of travel
// per axis (the sign of d(x/w)/dt is that of dx w0 - x0 dw, fixed for the whole shutter).
// Each boundary crossing solves a linear equation, for both light kinds. Shared by the
// depth-line and the exact moving lookups.
struct MsLightPath {
    vec4 c0;
    vec4 dc;
    float lo;
    float hi;
    ivec2 dir;
    ivec2 texel;
    float t;
};

// False where the path never enters the light's view.
bool ms_path_start(MsLight light, uvec2 size, vec3 p0, vec3 p1, out MsLightPath path) {
    mat4 to_clip = light.proj * light.view;
    path.c0 = to_clip * vec4(p0, 1.0);
    path.dc = to_clip * vec4(p1, 1.0) - path.c0;
    vec4 c0 = path.c0, dc = path.dc;
    path.lo = 0.0;
    path.hi = 1.0;
    ms_clip_times(c0.w, dc.w, path.lo, path.hi);
    ms_clip_times(c0.w + c0.x, dc.w + dc.x, path.lo, path.hi);
    ms_clip_times(c0.w - c0.x, dc.w - dc.x, path.lo, path.hi);
    ms_clip_times(c0.w + c0.y, dc.w + dc.y, path.lo, path.hi);
    ms_clip_times(c0.w - c0.y, dc.w - dc.y, path.lo, path.hi);
    path.dir = ivec2(sign(vec2(dc.x * c0.w - c0.x * dc.w, dc.y * c0.w - c0.y * dc.w)));
    vec4 start = c0 + path.lo * dc;
    path.texel = clamp(ivec2(floor((start.xy / start.w * 0.5 + 0.5) * vec2(size))), ivec2(0),
                       ivec2(size) - 1);
    path.t = path.lo;
    return path.hi > path.lo;
}

// The time the path leaves its current texel (at most hi), then steps it into the next one;
// false once it has stepped past the map's border (by rounding only: hi is where it leaves
// the view).
bool ms_path_advance(inout MsLightPath path, uvec2 size, out float exit) {
    vec2 fsize = vec2(size);
    float tx = 2.0, ty = 2.0;
    if (path.dir.x != 0) {
        float edge = float(path.texel.x + max(path.dir.x, 0)) / fsize.x * 2.0 - 1.0;
        tx = ms_boundary_time(path.c0, path.dc, 0, edge);
    }
    if (path.dir.y != 0) {
        float edge = float(path.texel.y + max(path.dir.y, 0)) / fsize.y * 2.0 - 1.0;
        ty = ms_boundary_time(path.c0, path.dc, 1, edge);
    }
    exit = clamp(min(min(tx, ty), path.hi), path.t, path.hi);
    if (tx <= ty) {
        path.texel.x += path.dir.x;
    } else {
        path.texel.y += path.dir.y;
    }
    return all(greaterThanEqual(path.texel, ivec2(0))) && all(lessThan(path.texel, ivec2(size)));
}

// A moving lookup's walk along its path, resumable between two texels (issue 35): the texels'
// time windows are disjoint and their shares add up, so a walk may stop before any texel and
// go on later, in another invocation, from the time and texel it reached and its sum so far.
// On a device that leaves loops after a fixed count (lavapipe), the visibility mask cuts a
// long walk into pieces that each fit one invocation's budget.
const uint MS_WALK_START = 0u;      // in: from the path's start
const uint MS_WALK_RESUME = 1u;     // in: from t, texel and sum
const uint MS_WALK_DONE = 2u;       // out: sum is the lit fraction
const uint MS_WALK_STOPPED = 3u;    // out: stopped before `texel` at time t: resume from there
const uint MS_WALK_PAST = 4u;       // out: past the budget at texel `walked`: nothing is sure
const uint MS_WALK_NO_LIMIT = 0xffffffffu;

struct MsWalk {
    uint state;
    float t;
    ivec2 texel;
    float sum;      // so far: the lit time (depth lines), the shadowed time (exact)
    uint limit;     // texels (exact: loop iterations) it may walk (MS_WALK_NO_LIMIT: any)
    uint walked;    // texels this invocation has walked (exact: its loop iterations)
    uint cursor;    // exact walks: where in `texel`'s list it goes on (0: the list's start)
};

MsWalk ms_walk_start() {
    return MsWalk(MS_WALK_START, 0.0, ivec2(0), 0.0, MS_WALK_NO_LIMIT, 0u, 0u);
}

// The count a walk stops at, before its next texel, to go on with a fresh budget: half of
// `budget` (the other half for the texel it is in, which may be long); never with budget 0
// (no loop limit).
uint ms_walk_stop_count(uint budget) {
    return budget == 0u ? 0xffffffffu : budget / 2u;
}

// Whether the walk stops before its next texel (past its stop count or its texel limit).
// Tested at the top of the walk's loop: a caller that passes a budget of 0 known when the
// shader is compiled has it folded away (a test left there made the visibility mask 1.3x
// slower on lavapipe).
bool ms_walk_stops(MsWalk walk, uint stop_count) {
    return ms_loop_iterations > stop_count || walk.walked >= walk.limit;
}

// The walk's state once its loop is left: past `budget` (the last texel walked ran past it:
// nothing this invocation did is sure; `walked` is that texel's number), stopped before the
// texel at t (resume there with `sum`), or done (`sum` is the lit fraction).
void ms_walk_end(inout MsWalk walk, uint budget, bool stopped, float t, ivec2 texel, float sum,
                 float lit) {
    if (budget != 0u && ms_loop_iterations > budget) {
        walk.state = MS_WALK_PAST;
        walk.walked -= 1u;
    } else if (stopped) {
        walk.state = MS_WALK_STOPPED;
        walk.t = t;
        walk.texel = texel;
        walk.sum = sum;
    } else {
        walk.state = MS_WALK_DONE;
        walk.sum = lit;
    }
}

// A receiver's normal at time t in the world a turning light's map sees (light_motion.glsl's
// ms_light_frame_end): that world is the real one taken through (1 - t) I + t F, F the frame
// from the t = 1 view to the t = 0 view, whose linear part L(t) = (1 - t) I + t turn
// (turn: F's rotation) carries a plane's normal n to L(t)^-T n, here as its cofactor matrix
// times n (the same direction), unit. Not the blend of n and turn n: L(t) shrinks across the
// turn's axis (by cos(a / 2) at mid-shutter for a turn a), which tips planes the other way.
vec3 ms_turned_normal(mat3 turn, vec3 n, float t) {
    mat3 l = mat3(1.0) + t * (turn - mat3(1.0));
    return normalize(cross(l[1], l[2]) * n.x + cross(l[2], l[0]) * n.y
                     + cross(l[0], l[1]) * n.z);
}

// The lit time of texel `at` over the window w of a path: the offset receiver moving from q0
// to q1 (light depths `depths` at its ends), unit normals na and nb at the window's ends. One
// function for ms_walk_moving_turned and ms_walk_moving_still, so that a still receiver's walk
// computes the general walk's values with the same expressions.
float ms_path_texel_lit(MsMap map, uvec2 at, vec3 q0, vec3 q1, vec2 depths, vec3 na, vec3 nb,
                        vec2 w, uint own) {
    float da = ms_tested_depth(map.light, map.size, at, mix(q0, q1, w.x), na,
                               mix(depths.x, depths.y, w.x));
    float db = ms_tested_depth(map.light, map.size, at, mix(q0, q1, w.y), nb,
                               mix(depths.x, depths.y, w.y));
    return ms_texel_lit_span(map, at.y * map.size.x + at.x, w, vec2(da, db), own);
}

// The fraction of the shutter [0, 1] during which a receiver moving linearly from p0 (at
// t = 0) to p1 (at t = 1), unit normal n (on the side facing the light; taken as constant),
// on triangle `own`, sees the light: each range tested where the point is when it holds.
// Exact for a receiver that translates (any linear motion of the point), with the same
// receiver offset, bias and own-triangle rule as ms_lit_fraction, to which it reduces when
// p0 == p1.
//
// The point's path is cut where it crosses texel boundaries (its projection x/w is monotonic
// in t, and each crossing time solves a linear equation, for both light kinds); within one
// texel its light depth, and its tangent plane's depth at the texel centre, are linear in t,
// so every range shadows it during one interval (ms_texel_lit_span). Time spent outside the
// light's view is lit. The cost is one list walk per texel crossed. Walked from `walk` (see
// MsWalk) until done or, with a loop `budget` (0: none), stopped between two texels.
//
// Under a light that turns (`turns`), p1 is the receiver's t = 1 point taken into the t = 0
// view's world (ms_light_frame_end) and `turn` the rotation that took it there: the normal is
// carried through the same frame (ms_turned_normal at each end of every texel's window), for
// the offset at t = 1 and the plane test; a still or translating light passes false.
void ms_walk_moving_turned(MsMap map, vec3 p0, vec3 p1, vec3 n, bool turns, mat3 turn,
                           uint own, uint budget, inout MsWalk walk) {
    MsLight light = map.light;
    // The normal offset is linear in the point's light depth, so the offset point moves
    // linearly too (under a turning light, from the offset along n to the offset along the
    // turned normal: off a line by a fraction of the offset's own length).
    vec3 q0 = ms_offset_receiver(light, p0, n);
    vec3 q1 = ms_offset_receiver(light, p1, turns ? turn * n : n);
    MsLightPath path;
    if (!ms_path_start(light, map.size, q0, q1, path)) {
        walk.state = MS_WALK_DONE;
        walk.sum = 1.0;
        return;
    }
    float lit = 1.0 - (path.hi - path.lo);    // outside the light's view
    if (walk.state == MS_WALK_RESUME) {
        path.t = walk.t;
        path.texel = walk.texel;
        lit = walk.sum;
    }
    float depth0 = -(light.view * vec4(q0, 1.0)).z, depth1 = -(light.view * vec4(q1, 1.0)).z;
    uint stop_count = ms_walk_stop_count(budget);
    bool stopped = false;
    for (uint crossed = 0u; path.t < path.hi && crossed <= map.size.x + map.size.y; ++crossed) {
        if (ms_walk_stops(walk, stop_count)) {
            stopped = true;
            break;
        }
        ++ms_loop_iterations;
        uvec2 at = uvec2(path.texel);
        float t = path.t, exit;
        bool inside = ms_path_advance(path, map.size, exit);
        vec3 na = turns ? ms_turned_normal(turn, n, t) : n;
        vec3 nb = turns ? ms_turned_normal(turn, n, exit) : n;
        lit += ms_path_texel_lit(map, at, q0, q1, vec2(depth0, depth1), na, nb, vec2(t, exit),
                                 own);
        ++walk.walked;
        path.t = exit;
        // Past the map's border by rounding only: the sliver left is counted lit, as outside.
        if (!inside) {
            lit += path.hi - path.t;
            break;
        }
    }
    ms_walk_end(walk, budget, stopped, path.t, path.texel, lit, min(lit, 1.0));
}

// ms_walk_moving, from its start without a loop budget, for a receiver that stands still at
// p0 under a still light, known when the shader is compiled: its one texel, with the same
// values (the path's ends, depths and window computed by the same expressions on equal
// inputs) and so the same answer bit for bit, without the texel stepping, whose code llvmpipe
// runs (masked) for every SIMD group that reaches it. The visibility mask's first round on a
// device with follow-up rounds (STILL_FIRST), which leaves moving receivers to them.
void ms_walk_moving_still(MsMap map, vec3 p0, vec3 n, uint own, inout MsWalk walk) {
    MsLight light = map.light;
    vec3 q0 = ms_offset_receiver(light, p0, n);
    MsLightPath path;
    walk.state = MS_WALK_DONE;
    walk.sum = 1.0;
    if (!ms_path_start(light, map.size, q0, q0, path)) return;
    float lit = 1.0 - (path.hi - path.lo);
    float depth0 = -(light.view * vec4(q0, 1.0)).z;
    if (path.t < path.hi) {
        ++ms_loop_iterations;
        uvec2 at = uvec2(path.texel);
        float t = path.t;
        // Where ms_path_advance leaves a path that does not move: when it leaves the view.
        float exit = clamp(path.hi, t, path.hi);
        lit += ms_path_texel_lit(map, at, q0, q0, vec2(depth0), n, n, vec2(t, exit), own);
        ++walk.walked;
    }
    walk.sum = min(lit, 1.0);
}

// The walk under a still or translating light (the receiver's normal as it is all shutter).
void ms_walk_moving(MsMap map, vec3 p0, vec3 p1, vec3 n, uint own, uint budget,
                    inout MsWalk walk) {
    ms_walk_moving_turned(map, p0, p1, n, false, mat3(1.0), own, budget, walk);
}

float ms_lit_fraction_moving(MsMap map, vec3 p0, vec3 p1, vec3 n, uint own) {
    MsWalk walk = ms_walk_start();
    ms_walk_moving(map, p0, p1, n, own, 0u, walk);
    return walk.sum;
}

float ms_lit_fraction_moving(MsShadowMap header, vec3 p0, vec3 p1, vec3 n, uint own) {
    return ms_lit_fraction_moving(ms_load(header), p0, p1, n, own);
}
