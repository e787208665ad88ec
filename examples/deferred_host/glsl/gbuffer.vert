#version 450
// The deferred host's G-buffer pass, vertex stage. Ordinary vertex input: the position, the
// normal and last frame's position come from three vertex bindings whose buffers, offsets
// and strides each draw binds (24-byte static vertices under this and last frame's model, or
// the 48-byte per-frame vertices of a CPU-deformed mesh). The positions are the current
// frame's (shutter time t = 1); last frame's are the shutter's start (t = 0).
#include "frame.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec3 in_previous;

// Per draw: object -> world at t = 1 and at t = 0, each as three rows of an affine matrix,
// and the albedo.
layout(push_constant) uniform Draw {
    vec4 model[3];
    vec4 previous_model[3];
    vec4 albedo;
    uint first_id;  // the mesh's first global triangle id (its shadow draw's)
} draw;

layout(location = 0) out vec3 out_world;
layout(location = 1) out vec3 out_normal;
// World displacement over the shutter, p(1) - p(0): linear in the triangle's barycentrics,
// as the shadow pass's linearly moving vertices are.
layout(location = 2) out vec3 out_motion;

vec3 transform(vec4 rows[3], vec3 v, float w) {
    vec4 p = vec4(v, w);
    return vec3(dot(rows[0], p), dot(rows[1], p), dot(rows[2], p));
}

void main() {
    out_world = transform(draw.model, in_position, 1.0);
    // Rigid transforms (rotation and translation) only, so the normal takes the same rows.
    out_normal = transform(draw.model, in_normal, 0.0);
    out_motion = out_world - transform(draw.previous_model, in_previous, 1.0);
    gl_Position = frame.view_proj * vec4(out_world, 1.0);
}
