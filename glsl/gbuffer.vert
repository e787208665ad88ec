#version 450
// The deferred frame's G-buffer, vertex stage: the draws of a DrawList (fetched by address,
// as every pass of the library reads them) at one shutter time, seen from the camera. Each
// vertex carries its world position at that time and its displacement over the shutter
// (p1 - p0): interpolated over the triangle they give every point's own position and motion
// (a point with fixed barycentrics on a linearly moving triangle moves linearly).
#include "shared.glsl"

#include "image_push.glsl"
layout(push_constant) uniform Push { GBufferPush pc; };

layout(location = 0) out vec3 out_world;
layout(location = 1) out vec3 out_motion;
layout(location = 2) flat out vec3 out_albedo;
layout(location = 3) flat out uint out_id;

void main() {
    DrawRecord d = load_draw(pc.draws, pc.draw_index);
    uint prim = uint(gl_VertexIndex) / 3u;
    out_albedo = d.albedo_flags.rgb;
    out_id = d.first_id + prim;
    if (!triangle_valid(d, prim)) {
        // Outside the clip volume: the triangle is dropped (the shadow passes count it).
        out_world = vec3(0.0);
        out_motion = vec3(0.0);
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        return;
    }
    vec3 p0, p1;
    fetch_corner(d, prim, uint(gl_VertexIndex) % 3u, p0, p1);
    out_world = mix(p0, p1, pc.time);
    out_motion = p1 - p0;
    gl_Position = pc.view_proj * vec4(out_world, 1.0);
}
