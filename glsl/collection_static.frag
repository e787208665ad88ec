#version 450
// Collection sub-pass, exact construction, static draws: both nodes of the texel.
#include "shared.glsl"
#include "collection_append.glsl"
#include "static_prism.glsl"

layout(push_constant) uniform Push { PassConstants pc; };

void main() {
    if (static_prism_culled()) return;
    MsShadowMap map = MsShadowMap(pc.map);
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    uint p = pixel.y * map.size.x + pixel.x;
    append_fragment(map, p, in_depth, 0.0, in_id, SURFACE_CAP0);
    append_fragment(map, p, in_depth, 1.0, in_id, SURFACE_CAP1);
}
