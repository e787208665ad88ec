#version 450
// The deferred host's G-buffer pass, vertex stage. Ordinary vertex input: the position and the
// normal come from two vertex bindings whose buffers, offsets and strides each draw binds
// (24-byte static vertices or the 48-byte per-frame vertices of a CPU-deformed mesh). The
// positions are the current frame's (shutter time t = 1).
#include "frame.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;

// Per draw: object -> world at t = 1 as three rows of an affine matrix, and the albedo.
layout(push_constant) uniform Draw {
    vec4 model[3];
    vec4 albedo;
} draw;

layout(location = 0) out vec3 out_world;
layout(location = 1) out vec3 out_normal;

void main() {
    vec4 p = vec4(in_position, 1.0);
    out_world = vec3(dot(draw.model[0], p), dot(draw.model[1], p), dot(draw.model[2], p));
    // Rigid transforms (rotation and translation) only, so the normal takes the same rows.
    out_normal = vec3(dot(draw.model[0].xyz, in_normal), dot(draw.model[1].xyz, in_normal),
                      dot(draw.model[2].xyz, in_normal));
    gl_Position = frame.view_proj * vec4(out_world, 1.0);
}
