// The exact lookup (issue 35, docs/src/exact-lookups.md): the fraction of the shutter a
// receiver sees the light, from its shadow ray tested against the triangles its texels'
// ranges name, their corners at t = 0 and t = 1 (exact_shadow.glsl): no texels, no receiver
// offset, no depth bias; and whether it sees the light at one time (ms_visible_exact, the
// lighting pass's samples). Reads a map built with the exact lookup (LightView::lookup =
// Lookup::Exact): its conservative collection names, in every texel, each triangle whose
// swept shadow touches the texel's area during the shutter, and writes each triangle's
// record. Include after motion_shadows.glsl.
#ifndef MS_EXACT_LOOKUP_GLSL
#define MS_EXACT_LOOKUP_GLSL
#include "exact_shadow.glsl"

// Per global triangle id, six vec4: the world corners 0, 1, 2 at t = 0, then at t = 1.
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer MsTriangles {
    vec4 v[];
};

void ms_exact_triangle(uint64_t triangles, uint id, out vec3 at0[3], out vec3 at1[3]) {
    MsTriangles records = MsTriangles(triangles);
    for (uint k = 0u; k < 3u; ++k) {
        at0[k] = records.v[6u * id + k].xyz;
        at1[k] = records.v[6u * id + 3u + k].xyz;
    }
}

// The static name lists (the map's static_names; written by collection_append.glsl's
// append_static_name): a count, a capacity, two unused words, then per texel the index + 1
// of its first name (0: none), then the names as (triangle id, index + 1 of the next) pairs.
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer MsStaticNames {
    uint count;
    uint capacity;
    uint unused[2];
    uint v[];
};

// Index + 1 of the first static name of `texel` (0: none), in a map with static name lists.
uint ms_static_names_head(MsMap map, uint texel) {
    return MsStaticNames(map.static_names).v[texel];
}

// The triangle static name r (index + 1) names; r becomes the texel's next one (0: none).
uint ms_static_name(MsMap map, inout uint r) {
    MsStaticNames names = MsStaticNames(map.static_names);
    uint at = map.size.x * map.size.y + 2u * (r - 1u);
    r = names.v[at + 1u];
    return names.v[at];
}

// A still triangle's corners (its record's t = 0 ones: the t = 1 ones are the same): half the
// loads, which a CPU device makes lane by lane.
void ms_exact_still_triangle(uint64_t triangles, uint id, out vec3 at[3]) {
    MsTriangles records = MsTriangles(triangles);
    for (uint k = 0u; k < 3u; ++k) at[k] = records.v[6u * id + k].xyz;
}

// The size the directional light's self-shadow epsilon is relative to (ms_exact_s_min): the
// map's width in the world, which holds every caster it names.
float ms_exact_scene_size(MsMap map) {
    return map.light.bias.z * float(max(map.size.x, map.size.y));
}

// A turning light (issue 38), set by the caller as ms_exact_light_motion is: MsLightEnd's
// frame, which takes a receiver's t = 1 point into the t = 0 view's world (ms_walk_exact).
bool ms_exact_light_turning = false;
mat4 ms_exact_light_frame = mat4(1.0);

// Where in a texel's list the exact walk goes on (MsWalk.cursor): from the list's start, or
// from a static name (its index + 1, flagged) or a range (its index + 1) of it.
const uint MS_EXACT_CURSOR_START = 0u;
const uint MS_EXACT_CURSOR_STATIC = 0x80000000u;

// How many undecided triangles a texel walk gathers before it asks them (ms_exact_texel_walk).
#define MS_EXACT_ASKED_TOGETHER 4

// Puts triangle `id` (at cursor `here` in the lists, over window w) into slot `asked` of the
// gathered ones (held in vectors with constant indices rather than arrays, which lavapipe
// keeps in memory).
void ms_exact_gather(inout int asked, inout uvec4 ids, inout uvec4 at, inout vec4 w0s,
                     inout vec4 w1s, uint id, uint here, vec2 w) {
    bvec4 slot = equal(ivec4(0, 1, 2, 3), ivec4(asked));
    ids = mix(ids, uvec4(id), slot);
    at = mix(at, uvec4(here), slot);
    w0s = mix(w0s, vec4(w.x), slot);
    w1s = mix(w1s, vec4(w.y), slot);
    ++asked;
}

// One step of a texel walk through its static names, from r (index + 1 of the next): false
// at their end (in_static is then false and r the texel's first range) or when the
// invocation's loop iterations are past `stop` (stopped; cursor says where to go on); true
// with the next name's triangle `id` and its cursor `here`, r moved past it.
bool ms_exact_static_next(MsMap map, uint texel, uint stop, inout uint r, inout bool in_static,
                          inout uint cursor, inout bool stopped, out uint here, out uint id) {
    here = 0u;
    id = 0u;
    if (r == 0u) {
        in_static = false;
        r = MsUints(map.range_heads).v[texel];
        return false;
    }
    if (ms_loop_iterations > stop) {
        cursor = r | MS_EXACT_CURSOR_STATIC;
        stopped = true;
        return false;
    }
    ++ms_loop_iterations;
    here = r | MS_EXACT_CURSOR_STATIC;
    id = ms_static_name(map, r);
    return true;
}

// Adds to `shadowed` the times of the window w during which the triangles named in `texel`
// (other than `own`), from `cursor` on, block the shadow ray of the receiver moving from p0
// (t = 0) to p1 (t = 1): the union of their shadowed intervals. Each range's own times narrow
// the window (the conservative collection gives the whole shutter). True when done: the
// list's end, or triangles shadowing all of the window (which ends the walk of the list).
// False when it stopped before the entry `cursor` then names, the invocation's loop
// iterations (ms_loop_iterations, the exact test's own included) being past `stop`: a later
// invocation goes on from there with the same union. Tests at least one triangle before it
// stops where the count is below `stop` when it is called.
//
// The static names first (most of a level's casters: one that shadows the whole window, a
// wall, spares the walk of the moving ones), then the ranges. Their loops decide each
// triangle with the cheap half of the test (a still receiver's static names: the test on
// constants; a moving receiver's, and the ranges: ms_exact_classify) and gather those they
// cannot decide, up to
// MS_EXACT_ASKED_TOGETHER, for a third loop that asks them the whole test: on llvmpipe a
// loop's body costs its whole code per iteration of the SIMD group, taken or not, and the
// root finding is most of it while most triangles are decided without it.
//
// `known_still`: the caller knows, when the shader is compiled, that the receiver and the
// light stand still (ms_walk_exact_still): the moving receivers' loop and the moving ray's
// terms fold away. `static_only` (with known_still, also known when compiled): the walk ends
// with the static names, and the loops of the ranges fold away (ms_walk_exact_still).
bool ms_exact_texel_walk(MsMap map, uint texel, vec3 p0, vec3 p1, vec2 w, uint own, uint stop,
                         bool known_still, bool static_only, inout uint cursor,
                         inout ms_exact_Union shadowed) {
    bool spot = map.light.position.w != 0.0;
    vec3 light = spot ? map.light.position.xyz : map.light.direction.xyz;
    float s_min = ms_exact_s_min(spot, ms_exact_scene_size(map));
    bool still = known_still || p0 == p1;
    bool from_start = cursor == MS_EXACT_CURSOR_START;
    bool in_static =
        map.static_names != 0UL && (from_start || (cursor & MS_EXACT_CURSOR_STATIC) != 0u);
    uint r;
    if (in_static) {
        r = from_start ? ms_static_names_head(map, texel) : cursor & ~MS_EXACT_CURSOR_STATIC;
    } else {
        r = from_start ? MsUints(map.range_heads).v[texel] : cursor;
    }
    bool stopped = false;
    bool listed = true;
    while (listed && !stopped) {
        // The undecided triangles: their ids and windows (ms_exact_gather).
        uvec4 asked_id = uvec4(0u);
        // Where each is in the lists (a cursor): a walk stopped before asking it goes on there.
        uvec4 asked_at = uvec4(0u);
        vec4 asked_w0 = vec4(0.0);
        vec4 asked_w1 = vec4(0.0);
        int asked = 0;
        // The static names against a still receiver: decided on the constants, so this loop
        // holds that test alone.
        while (in_static && still && asked < MS_EXACT_ASKED_TOGETHER) {
            uint here, id;
            if (!ms_exact_static_next(map, texel, stop, r, in_static, cursor, stopped, here, id)) {
                break;
            }
            if (id == own) continue;
            vec3 at[3];
            ms_exact_still_triangle(map.triangles, id, at);
            if (ms_exact_blocks_still_at(p0, spot, light, s_min, at)) {
                ms_exact_union_add(shadowed, w);
                if (ms_exact_union_covers(shadowed, w.x, w.y)) return true;
            }
        }
        if (static_only) break;
        // Against a moving receiver, the cheap half first (ms_exact_classify): counted on
        // game-level, 99% of the static names a moving receiver asked found nothing. A loop of
        // its own, so that a group of still receivers runs none of its code.
        while (in_static && !still && asked < MS_EXACT_ASKED_TOGETHER) {
            uint here, id;
            if (!ms_exact_static_next(map, texel, stop, r, in_static, cursor, stopped, here, id)) {
                break;
            }
            if (id == own) continue;
            vec3 at[3];
            ms_exact_still_triangle(map.triangles, id, at);
            if (ms_exact_classify(p0, p1, spot, light, s_min, at, at, w.x, w.y, true, false)
                == MS_EXACT_ASK) {
                ms_exact_gather(asked, asked_id, asked_at, asked_w0, asked_w1, id, here, w);
            }
        }
        while (!in_static && !stopped && asked < MS_EXACT_ASKED_TOGETHER) {
            if (r == MS_END_OF_LIST) {
                listed = false;
                break;
            }
            if (ms_loop_iterations > stop) {
                cursor = r;
                stopped = true;
                break;
            }
            ++ms_loop_iterations;
            uint here = r;
            MsRange range = ms_range(map.ranges, r);
            r = range.next;
            float w0 = max(w.x, clamp(range.t_s, 0.0, 1.0));
            float w1 = min(w.y, clamp(range.t_e, 0.0, 1.0));
            if (range.id == own || !(w1 > w0)) continue;
            vec3 at0[3], at1[3];
            ms_exact_triangle(map.triangles, range.id, at0, at1);
            if (ms_exact_classify(p0, p1, spot, light, s_min, at0, at1, w0, w1, false,
                                  known_still)
                == MS_EXACT_ASK) {
                ms_exact_gather(asked, asked_id, asked_at, asked_w0, asked_w1, range.id, here,
                                vec2(w0, w1));
            }
        }
        for (int i = 0; i < asked; ++i) {
            // Past the budget after one test at least: the next invocation goes on from this
            // one and walks what came after it again (a union takes the same interval twice
            // without change).
            if (i > 0 && ms_loop_iterations > stop) {
                cursor = asked_at[i];
                stopped = true;
                break;
            }
            vec3 at0[3], at1[3];
            ms_exact_triangle(map.triangles, asked_id[i], at0, at1);
            vec2 iv[MS_EXACT_MAX_INTERVALS];
            int n = ms_exact_shadowed_intervals(p0, p1, spot, light, s_min, at0, at1,
                                                asked_w0[i], asked_w1[i], known_still, iv);
            ms_loop_iterations += ms_exact_iterations;
            ms_exact_iterations = 0u;
            for (int k = 0; k < n; ++k) ms_exact_union_add(shadowed, iv[k]);
            if (ms_exact_union_covers(shadowed, w.x, w.y)) return true;
        }
    }
    return !stopped;
}

// The fraction of the shutter [0, 1] during which a receiver moving linearly from p0 (t = 0)
// to p1 (t = 1), on triangle `own` (MS_NO_TRIANGLE for none), sees the light. Its path is cut
// where its projection crosses texel boundaries (as ms_lit_fraction_moving does); while it is
// in a texel, whatever blocks it then covers a point of that texel, so is named there: each
// texel's triangles are tested over that sub-window. The sub-windows are disjoint, so their
// shadowed times add up. Time outside the light's view is lit. Without triangle records (a map
// not built for the exact lookup): 1.
//
// Walked from `walk` (see MsWalk) until done or, with a loop `budget` (0: none), stopped
// between two texels or between two triangles of a texel's list, past half the budget or
// past walk.limit iterations (what a caller whose loops were cut asks for): walk.cursor then
// says where in the texel's list it goes on, and `texel_union` holds that texel's shadowed
// intervals so far, which the caller hands to the walk's next invocation (as `texel_union`,
// with walk.cursor; it is read only where walk.cursor is not MS_EXACT_CURSOR_START). Its
// count of loop iterations (the exact test's included) ends in walk.walked.
//
// A translating light (ms_exact_light_motion set): the path is walked in the light's moving
// frame, its t = 1 end moved by the light's motion the other way (the t = 0 view then sees
// the receiver at each time where the light at that time does: ms_light_frame_end's frame
// for a translation); the shadow rays are tested in the world, toward the light at each time.
// A turning light (ms_exact_light_turning): the t = 1 end taken through ms_exact_light_frame
// (MsLightEnd's frame); for a receiver standing still the blended view then sees it at each
// time where the walk does, and the blended view of a still point is linear in t.
void ms_walk_exact(MsMap map, vec3 p0, vec3 p1, uint own, uint budget, inout MsWalk walk,
                   inout ms_exact_Union texel_union) {
    MsLightPath path;
    vec3 p1_in_frame = ms_exact_light_turning ? (ms_exact_light_frame * vec4(p1, 1.0)).xyz
        : ms_exact_light_motion == vec3(0.0)  ? p1
                                              : p1 - ms_exact_light_motion;
    if (map.triangles == 0UL || !ms_path_start(map.light, map.size, p0, p1_in_frame, path)) {
        walk.state = MS_WALK_DONE;
        walk.sum = 1.0;
        return;
    }
    float shadowed = 0.0;
    uint cursor = MS_EXACT_CURSOR_START;
    if (walk.state == MS_WALK_RESUME) {
        path.t = walk.t;
        path.texel = walk.texel;
        shadowed = walk.sum;
        cursor = walk.cursor;
    }
    if (cursor == MS_EXACT_CURSOR_START) texel_union = ms_exact_union_empty();
    uint stop = min(ms_walk_stop_count(budget), walk.limit);
    bool stopped = false;
    for (uint crossed = 0u; path.t < path.hi && crossed <= map.size.x + map.size.y; ++crossed) {
        if (ms_loop_iterations > stop) {
            stopped = true;
            break;
        }
        ++ms_loop_iterations;
        uint at = uint(path.texel.y) * map.size.x + uint(path.texel.x);
        float t = path.t, exit;
        ivec2 here = path.texel;
        bool inside = ms_path_advance(path, map.size, exit);
        if (!ms_exact_texel_walk(map, at, p0, p1, vec2(t, exit), own, stop, false, false,
                                 cursor, texel_union)) {
            // Within the texel: its next invocation goes on there, with the union so far.
            path.t = t;
            path.texel = here;
            stopped = true;
            break;
        }
        shadowed += min(ms_exact_union_length(texel_union), exit - t);
        texel_union = ms_exact_union_empty();
        cursor = MS_EXACT_CURSOR_START;
        path.t = exit;
        if (!inside) break;
    }
    walk.cursor = cursor;
    ms_walk_end(walk, budget, stopped, path.t, path.texel, shadowed, 1.0 - min(shadowed, 1.0));
    walk.walked = ms_loop_iterations;
}

// ms_walk_exact for a receiver that stands still at p under a still light, walked from its
// start without a loop budget (a device without a loop limit; on lavapipe, the visibility
// mask's round 0, whose probe hands a pixel whose loops were cut to the general walk): the
// same texel, window, triangles and union, so the same answer bit for bit, without the
// path's texel stepping or the moving receivers' loop, whose code llvmpipe runs (masked) for
// every SIMD group that reaches it. Called from a pipeline of its own (the visibility mask's
// STILL_FIRST round 0, which leaves moving receivers to round 1): beside the general walk in
// one shader, even behind a subgroupAll branch, it measured slower than the general walk
// alone on lavapipe.
//
// `static_only` (known when compiled; a map with static name lists): the texel's static
// names alone. False, the walk not done, where the texel names moving triangles too (ranges)
// and no static one blocks the receiver: the general walk (round 1) then asks them all. The
// loops of the ranges hold the cheap half of the moving test, which llvmpipe runs for every
// SIMD group (taken or not), while on game-level 2% of the receivers have a range in their
// texel. Otherwise true, the walk done.
bool ms_walk_exact_still(MsMap map, vec3 p, uint own, bool static_only, inout MsWalk walk,
                         inout ms_exact_Union texel_union) {
    MsLightPath path;
    walk.state = MS_WALK_DONE;
    walk.sum = 1.0;
    if (map.triangles == 0UL || !ms_path_start(map.light, map.size, p, p, path)) return true;
    texel_union = ms_exact_union_empty();
    uint cursor = MS_EXACT_CURSOR_START;
    ++ms_loop_iterations;
    uint at = uint(path.texel.y) * map.size.x + uint(path.texel.x);
    // The window ms_path_advance gives a path that does not move: the time it is in view.
    float exit = clamp(path.hi, path.t, path.hi);
    ms_exact_texel_walk(map, at, p, p, vec2(path.t, exit), own, 0xffffffffu, true,
                        static_only, cursor, texel_union);
    if (static_only && !ms_exact_union_covers(texel_union, path.t, exit)
        && MsUints(map.range_heads).v[at] != MS_END_OF_LIST) {
        return false;
    }
    // 0 + the texel's share, as the general walk adds it (the same float).
    float shadowed = 0.0;
    shadowed += min(ms_exact_union_length(texel_union), exit - path.t);
    walk.sum = 1.0 - min(shadowed, 1.0);
    walk.walked = ms_loop_iterations;
    return true;
}

float ms_lit_fraction_exact_moving(MsMap map, vec3 p0, vec3 p1, uint own) {
    MsWalk walk = ms_walk_start();
    ms_exact_Union texel_union = ms_exact_union_empty();
    ms_walk_exact(map, p0, p1, own, 0u, walk, texel_union);
    return walk.sum;
}

// The same for a receiver that stands at p all shutter long: its one texel's triangles.
float ms_lit_fraction_exact(MsMap map, vec3 p, uint own) {
    return ms_lit_fraction_exact_moving(map, p, p, own);
}

float ms_lit_fraction_exact(MsShadowMap header, vec3 p, uint own) {
    return ms_lit_fraction_exact(ms_load(header), p, own);
}

float ms_lit_fraction_exact_moving(MsShadowMap header, vec3 p0, vec3 p1, uint own) {
    return ms_lit_fraction_exact_moving(ms_load(header), p0, p1, own);
}

// Whether the triangle with corners at0 (t = 0) and at1 (t = 1), where it is at time t,
// blocks the shadow ray from p along u (ms_exact_blocks: the same sign rule, plane and range
// of s as the shutter-long test).
bool ms_exact_blocks_at(vec3 p, vec3 u, vec3 at0[3], vec3 at1[3], float t, bool spot,
                        float s_min) {
    ms_exact_Linear corner[3];
    for (int k = 0; k < 3; ++k) {
        // at0 + t (at1 - at0), not mix(): a corner that does not move is at0 exactly at
        // every time, as in the triangles that share it (the edges' canonical order and
        // values then agree, and no light passes between them).
        precise vec3 at = at0[k] + t * (at1[k] - at0[k]);
        corner[k] = ms_exact_Linear(at - p, vec3(0.0));
    }
    // Frozen at t, triangle and ray stand still: the constants' test.
    return ms_exact_blocks_still(ms_exact_Linear(u, vec3(0.0)), corner, spot, s_min, length(p));
}

// Whether a receiver at p at time t (its position then), on triangle `own` (MS_NO_TRIANGLE
// for none), sees the light at that time: its shadow ray against every triangle but `own`
// named in the texel p falls in (the same projection as the depth-line lookups', without
// their receiver offset), each where it is at t. Whatever blocks the ray at t covers p's
// projection then, so it is named in that texel (the conservative collection names each
// triangle in every texel its swept shadow touches). No normal, offset or bias. Outside the
// light's view, or without triangle records (a map not built for the exact lookup): lit.
bool ms_visible_exact(MsMap map, vec3 p, float t, uint own) {
    if (map.triangles == 0UL) return true;
    uint texel;
    float depth;
    if (!ms_project(map.light, map.size, p, texel, depth)) return true;
    bool spot = map.light.position.w != 0.0;
    vec3 u = spot ? map.light.position.xyz - p : -normalize(map.light.direction.xyz);
    float s_min = ms_exact_s_min(spot, ms_exact_scene_size(map));
    // The still triangles named in the texel (the static name lists), then the moving ones.
    if (map.static_names != 0UL) {
        for (uint r = ms_static_names_head(map, texel); r != 0u;) {
            ++ms_loop_iterations;
            uint id = ms_static_name(map, r);
            // The sample's own still triangle.
            if (own == id) continue;
            vec3 at[3];
            ms_exact_still_triangle(map.triangles, id, at);
            if (ms_exact_blocks_at(p, u, at, at, t, spot, s_min)) return false;
        }
    }
    for (uint r = MsUints(map.range_heads).v[texel]; r != MS_END_OF_LIST;) {
        ++ms_loop_iterations;
        MsRange range = ms_range(map.ranges, r);
        r = range.next;
        // The sample's own triangle: its ray leaves from it. A range's times bound those at
        // which its triangle may cover a point of the texel: outside them it blocks nothing.
        if (own == range.id || t < range.t_s || t > range.t_e) continue;
        vec3 at0[3], at1[3];
        ms_exact_triangle(map.triangles, range.id, at0, at1);
        if (ms_exact_blocks_at(p, u, at0, at1, t, spot, s_min)) return false;
    }
    return true;
}

bool ms_visible_exact(MsShadowMap header, vec3 p, float t, uint own) {
    return ms_visible_exact(ms_load(header), p, t, own);
}

#endif
