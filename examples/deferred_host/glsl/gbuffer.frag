#version 450
// The deferred host's G-buffer pass, fragment stage: a world-space normal (RGBA16F, signed),
// an albedo (RGBA8 unorm) and the world motion over the shutter (RGBA16F). Depth goes to the
// D32_SFLOAT attachment.
#include "frame.glsl"

layout(push_constant) uniform Draw {
    vec4 model[3];
    vec4 previous_model[3];
    vec4 albedo;
} draw;

layout(location = 0) in vec3 in_world;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec3 in_motion;

layout(location = 0) out vec4 out_normal;
layout(location = 1) out vec4 out_albedo;
layout(location = 2) out vec4 out_motion;

void main() {
    vec3 n = normalize(in_normal);
    // Two-sided surfaces (the ground, the bent slab): store the side the camera sees.
    if (dot(n, frame.eye.xyz - in_world) < 0.0) n = -n;
    out_normal = vec4(n, 0.0);
    out_albedo = vec4(draw.albedo.rgb, 1.0);
    out_motion = vec4(in_motion, 0.0);
}
