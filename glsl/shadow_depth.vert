#version 450
// An ordinary shadow map at one time (pc.time): the scene at that time, seen from the light. Used as the static reference and by time-dependent shadow maps.
#include "shared.glsl"

layout(std140, set = 0, binding = 0) uniform FrameBlock { FrameParams frame; };
layout(std430, set = 0, binding = 1) readonly buffer Vertices { SceneVertex vertices[]; };
layout(push_constant) uniform Push { PassConstants pc; };

layout(location = 0) out float out_depth;
layout(location = 1) flat out uint out_id;

void main() {
    SceneVertex v = vertices[gl_VertexIndex];
    float t = pc.time;
    vec3 view = (frame.light_view * vec4(mix(v.p0.xyz, v.p1.xyz, t), 1.0)).xyz;
    gl_Position = frame.light_proj * vec4(view, 1.0);
    out_depth = -view.z;
    out_id = pc.first_triangle + uint(gl_VertexIndex) / 3u;
}
