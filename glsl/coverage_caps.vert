#version 450
// Coverage map, the caps: the scene at t = 0 or t = 1 (pc.time), seen from the temporal
// map's light, with each fragment's light-view depth and triangle id for coverage.frag.
#include "shared.glsl"

layout(push_constant) uniform Push { MapDrawPush pc; };

layout(location = 0) out float out_depth;
layout(location = 1) flat out uint out_id;

void main() {
    ordinary_map_vertex(pc.draw, pc.time, MsShadowMap(pc.map).light,
                        uint(gl_VertexIndex), gl_Position, out_depth, out_id);
}
