#version 450
// The deferred frame's G-buffer, fragment stage: the surface's world normal (its plane's,
// from the derivatives of the world position: every point of the 2x2 quad lies on the
// triangle's plane; turned toward the camera, as the lighting pass shades two-sided), its
// albedo, its world displacement over the shutter, its triangle's id and its world position. Depth goes to the D32 attachment.
#include "shared.glsl"

#include "image_push.glsl"
layout(push_constant) uniform Push { GBufferPush pc; };

layout(location = 0) in vec3 in_world;
layout(location = 1) in vec3 in_motion;
layout(location = 2) flat in vec3 in_albedo;
layout(location = 3) flat in uint in_id;

layout(location = 0) out vec4 out_normal;   // RGBA16F: xyz signed
layout(location = 1) out vec4 out_albedo;   // RGBA8 unorm
layout(location = 2) out vec4 out_motion;   // RGBA32F: xyz = p(1) - p(0)
layout(location = 3) out uint out_id;       // R32_UINT: the triangle's global id
layout(location = 4) out vec4 out_position; // RGBA32F: xyz = the world position

void main() {
    vec3 n = cross(dFdx(in_world), dFdy(in_world));
    n = dot(n, n) > 0.0 ? normalize(n) : vec3(0.0, 1.0, 0.0);
    if (dot(n, pc.eye.xyz - in_world) < 0.0) n = -n;
    out_normal = vec4(n, 0.0);
    out_albedo = vec4(in_albedo, 1.0);
    out_motion = vec4(in_motion, 0.0);
    out_id = in_id;
    out_position = vec4(in_world, 1.0);
}
