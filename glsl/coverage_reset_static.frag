#version 450
// Coverage map, third pass, exact construction, static draws: both nodes of the texel.
#include "shared.glsl"
#include "coverage_reset.glsl"
#include "static_prism.glsl"

layout(push_constant) uniform Push { MapDrawPush pc; };

void main() {
    if (static_prism_culled()) return;
    MsShadowMap map = MsShadowMap(pc.map);
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    uint p = pixel.y * map.size.x + pixel.x;
    reset_coverage(map, p, in_depth, 0.0, in_id, SURFACE_CAP0);
    reset_coverage(map, p, in_depth, 1.0, in_id, SURFACE_CAP1);
}
