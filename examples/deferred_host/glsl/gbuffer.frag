#version 450
// The deferred host's G-buffer pass, fragment stage: a world-space normal (RGBA16F, signed),
// an albedo (RGBA8 unorm), the world motion over the shutter (RGBA16F) and the triangle id. Depth goes to the
// D32_SFLOAT attachment.
#include "frame.glsl"

layout(push_constant) uniform Draw {
    vec4 model[3];
    vec4 previous_model[3];
    vec4 albedo;
    uint first_id;  // the mesh's first global triangle id (its shadow draw's)
} draw;

layout(location = 0) in vec3 in_world;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec3 in_motion;

layout(location = 0) out vec4 out_normal;
layout(location = 1) out vec4 out_albedo;
layout(location = 2) out vec4 out_motion;
// R32_UINT: the triangle's global id, as the shadow pass numbers it (the draw's first id plus
// the primitive's index): the mask skips a receiver's own triangle.
layout(location = 3) out uint out_id;

void main() {
    vec3 n = normalize(in_normal);
    // Two-sided surfaces (the ground, the bent slab): store the side the camera sees.
    if (dot(n, frame.eye.xyz - in_world) < 0.0) n = -n;
    out_normal = vec4(n, 0.0);
    out_albedo = vec4(draw.albedo.rgb, 1.0);
    out_motion = vec4(in_motion, 0.0);
    out_id = draw.first_id + uint(gl_PrimitiveID);
}
