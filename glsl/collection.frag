#version 450
// Collection sub-pass, the papers' construction: each fragment of a prism's caps and
// triangulated sides is one node of its texel's list.
#include "shared.glsl"
#include "collection_append.glsl"

layout(push_constant) uniform Push { MapDrawPush pc; };

layout(location = 0) in float in_depth;
layout(location = 1) in float in_time;
layout(location = 2) flat in uint in_id;
layout(location = 3) flat in uint in_surface;

void main() {
    MsShadowMap map = MsShadowMap(pc.map);
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    append_fragment(map, pixel.y * map.size.x + pixel.x, in_depth, in_time, in_id, in_surface);
}
