#version 450
// The deferred host's G-buffer pass, fragment stage: a world-space normal (RGBA16F, signed),
// the albedo (RGBA8), the world motion over the shutter (RGBA16F) and the triangle's global id
// (R32_UINT, as the shadow pass numbers it: the mask skips a receiver's own triangle).
#include "frame.glsl"

// The G-buffer pass's push constants (DrawConstants in pipelines.rs): 128 bytes.
layout(push_constant) uniform Draw {
    uint64_t frame;         // the frame's constants, by address
    uint64_t vertices;      // the engine's vertex buffer, by address (vertex pulling)
    vec4 model[3];          // object -> world at t = 1 (three rows of an affine matrix)
    vec4 previous_model[3]; // ... and at t = 0 (last frame's)
    vec3 albedo;
    uint first_id;          // the mesh's first global triangle id (its shadow draw's)
} draw;

layout(location = 0) in vec3 in_world;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec3 in_motion;

layout(location = 0) out vec4 out_normal;
layout(location = 1) out vec4 out_albedo;
layout(location = 2) out vec4 out_motion;
layout(location = 3) out uint out_id;

void main() {
    vec3 n = normalize(in_normal);
    // Two-sided surfaces (the ground): store the side the camera sees.
    if (dot(n, Frame(draw.frame).eye.xyz - in_world) < 0.0) n = -n;
    out_normal = vec4(n, 0.0);
    out_albedo = vec4(draw.albedo, 1.0);
    out_motion = vec4(in_motion, 0.0);
    out_id = draw.first_id + uint(gl_PrimitiveID);
}
