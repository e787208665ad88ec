#version 450
// The deferred host's G-buffer pass, vertex stage: positions and normals read from the
// engine's vertex buffer by address (gl_VertexIndex: the index plus the draw's base vertex),
// drawn at the current frame (shutter time t = 1); last frame's position is the shutter's
// start (t = 0).
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


layout(location = 0) out vec3 out_world;
layout(location = 1) out vec3 out_normal;
// World displacement over the shutter, p(1) - p(0): linear over the triangle, as the shadow
// pass's linearly moving vertices are.
layout(location = 2) out vec3 out_motion;

vec3 transform(vec4 rows[3], vec3 v, float w) {
    vec4 p = vec4(v, w);
    return vec3(dot(rows[0], p), dot(rows[1], p), dot(rows[2], p));
}

void main() {
    Vertex v = Vertices(draw.vertices).v[gl_VertexIndex];
    vec3 in_position = vec3(v.position[0], v.position[1], v.position[2]);
    vec3 in_normal = vec3(v.normal[0], v.normal[1], v.normal[2]);
    out_world = transform(draw.model, in_position, 1.0);
    // Rigid transforms only, so the normal takes the same rows.
    out_normal = transform(draw.model, in_normal, 0.0);
    out_motion = out_world - transform(draw.previous_model, in_position, 1.0);
    gl_Position = Frame(draw.frame).view_proj * vec4(out_world, 1.0);
}
