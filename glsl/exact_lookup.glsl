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

// Adds to `shadowed` the times of the window w during which a triangle named in `texel`
// (other than `own`) blocks the shadow ray of the receiver moving from p0 (t = 0) to p1
// (t = 1). Each range's own times narrow the window (the conservative collection gives the
// whole shutter).
void ms_exact_texel_shadow(MsMap map, uint texel, vec3 p0, vec3 p1, vec2 w, uint own,
                           inout ms_exact_Union shadowed) {
    bool spot = map.light.position.w != 0.0;
    vec3 light = spot ? map.light.position.xyz : map.light.direction.xyz;
    float s_min = ms_exact_s_min(spot, ms_exact_scene_size(map));
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
    }
}

// The fraction of the shutter [0, 1] during which a receiver moving linearly from p0 (t = 0)
// to p1 (t = 1), on triangle `own` (MS_NO_TRIANGLE for none), sees the light. Its path is cut
// where its projection crosses texel boundaries (as ms_lit_fraction_moving does); while it is
// in a texel, whatever blocks it then covers a point of that texel, so is named there: each
// texel's triangles are tested over that sub-window, and every interval goes into one union
// (a triangle named in several texels counts once). Time outside the light's view is lit.
// Without triangle records (a map not built for the exact lookup): 1.
float ms_lit_fraction_exact_moving(MsMap map, vec3 p0, vec3 p1, uint own) {
    if (map.triangles == 0UL) return 1.0;
    MsLight light = map.light;
    mat4 to_clip = light.proj * light.view;
    vec4 c0 = to_clip * vec4(p0, 1.0), dc = to_clip * vec4(p1, 1.0) - c0;
    float lo = 0.0, hi = 1.0;
    ms_clip_times(c0.w, dc.w, lo, hi);
    ms_clip_times(c0.w + c0.x, dc.w + dc.x, lo, hi);
    ms_clip_times(c0.w - c0.x, dc.w - dc.x, lo, hi);
    ms_clip_times(c0.w + c0.y, dc.w + dc.y, lo, hi);
    ms_clip_times(c0.w - c0.y, dc.w - dc.y, lo, hi);
    if (!(hi > lo)) return 1.0;
    vec2 size = vec2(map.size);
    ivec2 dir = ivec2(sign(vec2(dc.x * c0.w - c0.x * dc.w, dc.y * c0.w - c0.y * dc.w)));
    vec4 start = c0 + lo * dc;
    ivec2 texel = clamp(ivec2(floor((start.xy / start.w * 0.5 + 0.5) * size)), ivec2(0),
                        ivec2(map.size) - 1);
    ms_exact_Union shadowed = ms_exact_union_empty();
    float t = lo;
    for (uint crossed = 0u; t < hi && crossed <= map.size.x + map.size.y; ++crossed) {
        ++ms_loop_iterations;
        float tx = 2.0, ty = 2.0;
        if (dir.x != 0) {
            float edge = float(texel.x + max(dir.x, 0)) / size.x * 2.0 - 1.0;
            tx = ms_boundary_time(c0, dc, 0, edge);
        }
        if (dir.y != 0) {
            float edge = float(texel.y + max(dir.y, 0)) / size.y * 2.0 - 1.0;
            ty = ms_boundary_time(c0, dc, 1, edge);
        }
        float exit = clamp(min(min(tx, ty), hi), t, hi);
        uint at = uint(texel.y) * map.size.x + uint(texel.x);
        ms_exact_texel_shadow(map, at, p0, p1, vec2(t, exit), own, shadowed);
        if (tx <= ty) {
            texel.x += dir.x;
        } else {
            texel.y += dir.y;
        }
        t = exit;
        if (any(lessThan(texel, ivec2(0))) || any(greaterThanEqual(texel, ivec2(map.size)))) {
            break;
        }
    }
    return 1.0 - min(ms_exact_union_length(shadowed), 1.0);
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
