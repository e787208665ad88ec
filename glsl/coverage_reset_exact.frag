#version 450
// Coverage map, third pass, exact construction: the same nodes the collection stored for
// this triangle and texel (exact_prism.glsl), each tested as a fragment.
#include "shared.glsl"
#include "coverage_reset.glsl"
#include "exact_prism.glsl"

layout(push_constant) uniform Push { MapDrawPush pc; };

layout(location = 0) flat in vec4 in_at0[3];
layout(location = 3) flat in vec4 in_at1[3];
layout(location = 6) flat in uint in_id;
layout(location = 7) flat in vec3 in_cuts;

void main() {
    MsShadowMap map = MsShadowMap(pc.map);
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    uint p = pixel.y * map.size.x + pixel.x;
    if (UintArray(map.coverage).v[p] == NO_TRIANGLE) return;
    vec2 ndc = gl_FragCoord.xy / vec2(map.size.xy) * 2.0 - 1.0;
    ExactCorner corners[3];
    for (int k = 0; k < 3; ++k) corners[k] = ExactCorner(in_at0[k], in_at1[k]);
    vec2 a[3], d[3];
    ExactRuns runs = exact_prism_runs(corners, ndc, in_cuts, a, d);
    for (int i = 0; i < runs.count; ++i) {
        vec2 times, depths;
        exact_run_nodes(a, d, corners, runs, i, times, depths);
        reset_coverage(map, p, depths.x, times.x, in_id, exact_surface(times.x));
        reset_coverage(map, p, depths.y, times.y, in_id, exact_surface(times.y));
    }
}
