#version 450
// Fetches a vertex's two positions; the geometry shaders transform them for their view.
#include "shared.glsl"

layout(std430, set = 0, binding = 1) readonly buffer Vertices { SceneVertex vertices[]; };

layout(location = 0) out vec3 out_p0;
layout(location = 1) out vec3 out_p1;

void main() {
    SceneVertex v = vertices[gl_VertexIndex];
    out_p0 = v.p0.xyz;
    out_p1 = v.p1.xyz;
}
