#version 450
// An ordinary shadow map at one time (pc.time): the scene at that time, seen from the light.
// Used by the brute-force reference (one map per slice), time-dependent shadow maps (one
// depth-only map per time stratum) and the plain method.
#include "shared.glsl"

layout(push_constant) uniform Push { PassConstants pc; };

layout(location = 0) out float out_depth;
layout(location = 1) flat out uint out_id;

void main() {
    DrawRecord d = DrawTable(pc.draws).draws[pc.draw_index];
    MsLight light = PlainHeader(pc.map).light;
    uint prim = uint(gl_VertexIndex) / 3u;
    out_id = d.first_id + prim;
    if (!triangle_valid(d, prim)) {
        // Every corner of the triangle lands on one point outside the view: nothing is
        // rasterized. (The lighting pass counts such triangles.)
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        out_depth = 0.0;
        return;
    }
    vec3 p0, p1;
    fetch_corner(d, prim, uint(gl_VertexIndex) % 3u, p0, p1);
    vec3 view = (light.view * vec4(mix(p0, p1, pc.time), 1.0)).xyz;
    gl_Position = light.proj * vec4(view, 1.0);
    out_depth = -view.z;
}
