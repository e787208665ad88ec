#version 450
// Coverage map, third pass, exact construction: the same nodes the collection stored for
// this triangle and texel (exact_prism.glsl), each tested as a fragment.
#include "shared.glsl"
#include "coverage_reset.glsl"
#include "exact_prism.glsl"

layout(push_constant) uniform Push { PassConstants pc; };

layout(location = 0) flat in vec4 in_at0[3];
layout(location = 3) flat in vec4 in_at1[3];
layout(location = 6) flat in uint in_id;

void main() {
    MsShadowMap map = MsShadowMap(pc.map);
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    uint p = pixel.y * map.size.x + pixel.x;
    if (UintArray(map.coverage).v[p] == NO_TRIANGLE) return;
    vec2 ndc = gl_FragCoord.xy / vec2(map.size.xy) * 2.0 - 1.0;
    ExactCorner corners[3];
    for (int k = 0; k < 3; ++k) corners[k] = ExactCorner(in_at0[k], in_at1[k]);
    ExactNodes nodes = exact_prism_nodes(corners, ndc);
    for (int i = 0; i < nodes.count; ++i) {
        reset_coverage(map, p, nodes.depth[i], nodes.time[i], in_id,
                       exact_surface(nodes.time[i]));
    }
}
