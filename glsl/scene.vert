#version 450
// Fetches a vertex's two world positions from the host's draw (its index, its position
// streams and its object transforms at t = 0 and t = 1); the geometry shaders transform them
// for their view. Drawn non-indexed with 3 vertices per triangle: vertex i is corner i % 3 of
// the draw's triangle i / 3, which works the same with or without the draw's index stream.
#include "shared.glsl"

layout(push_constant) uniform Push { DrawPush pc; };  // every pass's prefix

layout(location = 0) out vec3 out_p0;
layout(location = 1) out vec3 out_p1;
// 0 when an index of the vertex's triangle is past the draw's vertex count: the geometry
// shader then drops the triangle and counts it.
layout(location = 2) out float out_valid;

void main() {
    DrawRecord d = load_draw(pc.draws, pc.draw_index);
    uint prim = uint(gl_VertexIndex) / 3u;
    bool valid = triangle_valid(d, prim);
    out_valid = valid ? 1.0 : 0.0;
    fetch_corner(d, prim, uint(gl_VertexIndex) % 3u, out_p0, out_p1);
    gl_Position = vec4(0.0, 0.0, 0.0, 1.0);
}
