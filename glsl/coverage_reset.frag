#version 450
// Coverage map, third pass, the papers' construction: every fragment of every prism.
#include "shared.glsl"
#include "coverage_reset.glsl"

layout(push_constant) uniform Push { MapDrawPush pc; };

layout(location = 0) in float in_depth;
layout(location = 1) in float in_time;
layout(location = 2) flat in uint in_id;
layout(location = 3) flat in uint in_surface;

void main() {
    MsShadowMap map = MsShadowMap(pc.map);
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    reset_coverage(map, pixel.y * map.size.x + pixel.x, in_depth, in_time, in_id, in_surface);
}
