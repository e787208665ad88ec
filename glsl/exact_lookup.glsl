// The exact lookup (issue 35, docs/src/exact-lookups.md): the fraction of the shutter a
// receiver sees the light, from its shadow ray tested against the triangles its texels'
// ranges name, their corners at t = 0 and t = 1 (exact_shadow.glsl): no texels, no receiver
// offset, no depth bias. Reads a map built with the exact lookup (LightView::lookup =
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

// The size the directional light's self-shadow epsilon is relative to (ms_exact_s_min): the
// map's width in the world, which holds every caster it names.
float ms_exact_scene_size(MsMap map) {
    return map.light.bias.z * float(max(map.size.x, map.size.y));
}

// The time of the window w during which a triangle named in `texel` (other than `own`)
// blocks the shadow ray of the receiver moving from p0 (t = 0) to p1 (t = 1): the length of
// the union of their shadowed intervals. Each range's own times narrow the window (the
// conservative collection gives the whole shutter). A triangle that shadows all of the window
// ends the walk of the list.
float ms_exact_texel_shadow(MsMap map, uint texel, vec3 p0, vec3 p1, vec2 w, uint own) {
    bool spot = map.light.position.w != 0.0;
    vec3 light = spot ? map.light.position.xyz : map.light.direction.xyz;
    float s_min = ms_exact_s_min(spot, ms_exact_scene_size(map));
    ms_exact_Union shadowed = ms_exact_union_empty();
    for (uint r = MsUints(map.range_heads).v[texel]; r != MS_END_OF_LIST;) {
        ++ms_loop_iterations;
        MsRange range = ms_range(map.ranges, r);
        r = range.next;
        if (range.id == own) continue;
        float w0 = max(w.x, clamp(range.t_s, 0.0, 1.0));
        float w1 = min(w.y, clamp(range.t_e, 0.0, 1.0));
        if (!(w1 > w0)) continue;
        vec3 at0[3], at1[3];
        ms_exact_triangle(map.triangles, range.id, at0, at1);
        vec2 iv[MS_EXACT_MAX_INTERVALS];
        int n = ms_exact_shadowed_intervals(p0, p1, spot, light, s_min, at0, at1, w0, w1, iv);
        for (int i = 0; i < n; ++i) ms_exact_union_add(shadowed, iv[i]);
        if (ms_exact_union_covers(shadowed, w.x, w.y)) return w.y - w.x;
    }
    return min(ms_exact_union_length(shadowed), w.y - w.x);
}

// The fraction of the shutter [0, 1] during which a receiver moving linearly from p0 (t = 0)
// to p1 (t = 1), on triangle `own` (MS_NO_TRIANGLE for none), sees the light. Its path is cut
// where its projection crosses texel boundaries (as ms_lit_fraction_moving does); while it is
// in a texel, whatever blocks it then covers a point of that texel, so is named there: each
// texel's triangles are tested over that sub-window. The sub-windows are disjoint, so their
// shadowed times add up. Time outside the light's view is lit. Without triangle records (a map
// not built for the exact lookup): 1. Walked from `walk` (see MsWalk) until done or, with a
// loop `budget` (0: none), stopped between two texels.
void ms_walk_exact(MsMap map, vec3 p0, vec3 p1, uint own, uint budget, inout MsWalk walk) {
    MsLightPath path;
    if (map.triangles == 0UL || !ms_path_start(map.light, map.size, p0, p1, path)) {
        walk.state = MS_WALK_DONE;
        walk.sum = 1.0;
        return;
    }
    float shadowed = 0.0;
    if (walk.state == MS_WALK_RESUME) {
        path.t = walk.t;
        path.texel = walk.texel;
        shadowed = walk.sum;
    }
    uint stop_count = ms_walk_stop_count(budget);
    bool stopped = false;
    for (uint crossed = 0u; path.t < path.hi && crossed <= map.size.x + map.size.y; ++crossed) {
        if (ms_walk_stops(walk, stop_count)) {
            stopped = true;
            break;
        }
        ++ms_loop_iterations;
        uint at = uint(path.texel.y) * map.size.x + uint(path.texel.x);
        float t = path.t, exit;
        bool inside = ms_path_advance(path, map.size, exit);
        shadowed += ms_exact_texel_shadow(map, at, p0, p1, vec2(t, exit), own);
        ++walk.walked;
        path.t = exit;
        if (!inside) break;
    }
    ms_walk_end(walk, budget, stopped, path.t, path.texel, shadowed, 1.0 - min(shadowed, 1.0));
}

float ms_lit_fraction_exact_moving(MsMap map, vec3 p0, vec3 p1, uint own) {
    MsWalk walk = ms_walk_start();
    ms_walk_exact(map, p0, p1, own, 0u, walk);
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

#endif
