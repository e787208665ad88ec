// The exact construction's collection fragment shader (collection_exact.frag stores nodes,
// collection_ranges.frag ranges): the texel's covered runs of this triangle, solved in
// closed form (exact_prism.glsl). A run is what the generation pass pairs from its start and
// end nodes, so where the lists are not needed for anything else (no coverage map: the
// collection with the static layer) it goes straight to the texel's range list and the
// generation pass has nothing left to do.
#include "shared.glsl"
#include "collection_append.glsl"
#include "exact_prism.glsl"

layout(push_constant) uniform Push { MapDrawPush pc; };

layout(location = 0) flat in vec4 in_at0[3];
layout(location = 3) flat in vec4 in_at1[3];
layout(location = 6) flat in uint in_id;
#ifndef CONSERVATIVE_COLLECTION
// (The conservative collection's ranges span the whole shutter: it needs no cuts.)
layout(location = 7) flat in vec3 in_cuts;
#endif

void main() {
    MsShadowMap map = MsShadowMap(pc.map);
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    vec2 ndc = gl_FragCoord.xy / vec2(map.size.xy) * 2.0 - 1.0;
    ExactCorner corners[3];
    for (int k = 0; k < 3; ++k) corners[k] = ExactCorner(in_at0[k], in_at1[k]);
    uint p = pixel.y * map.size.x + pixel.x;
#ifdef CONSERVATIVE_COLLECTION
    {
        // The exact lookup reads a range's triangle and window only: the whole shutter (it
        // bounds every time the triangle may cover some point of the texel) and the
        // triangle's depths over it.
        float near = in_at0[0].w, far = in_at0[0].w;
        for (int k = 0; k < 3; ++k) {
            near = min(near, min(in_at0[k].w, in_at1[k].w));
            far = max(far, max(in_at0[k].w, in_at1[k].w));
        }
        if ((pc.flags & STATIC_NAMES) != 0u) {
            append_static_name(map, p, in_id);
        } else {
            append_named_range(map, p, vec2(near, far), in_id);
        }
    }
#else
    vec2 a[3], d[3];
    ExactRuns runs = exact_prism_runs(corners, ndc, in_cuts, a, d);
    for (int i = 0; i < runs.count; ++i) {
        vec2 times, depths;
        exact_run_nodes(a, d, corners, runs, i, times, depths);
#ifdef COLLECT_RANGES
        append_range(map, p, times, depths, in_id);
#else
        append_fragment(map, p, depths.x, times.x, in_id, exact_surface(times.x));
        append_fragment(map, p, depths.y, times.y, in_id, exact_surface(times.y));
#endif
    }
#endif
}
