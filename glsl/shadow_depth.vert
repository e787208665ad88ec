#version 450
// An ordinary shadow map at one time (pc.time): the scene at that time, seen from the light,
// depth-tested into a depth attachment. Used by the brute-force reference (one map per
// slice), time-dependent shadow maps (one depth-only map per time stratum, drawn without a
// fragment shader) and the plain method.
#include "shared.glsl"

layout(push_constant) uniform Push { MapDrawPush pc; };

layout(location = 0) flat out uint out_id;

void main() {
    float depth;
    // A moving light where it is at the layer's time (shared.glsl's PlainHeader).
    MsLight light =
        ms_light_at(PlainHeader(pc.map).light, pc.map + PLAIN_LIGHT_END_OFFSET, pc.time);
    ordinary_map_vertex(pc.draw, pc.time, light, uint(gl_VertexIndex), gl_Position, depth,
                        out_id);
}
