// frame.glsl: the deferred host's per-frame constants and vertices, read by device address
// (no descriptor), shared by its G-buffer and shading shaders.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_buffer_reference : require

layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer Frame {
    mat4 view_proj;     // world -> clip (Vulkan: y down, depth in [0, 1])
    mat4 inv_view_proj; // clip -> world
    vec4 eye;           // xyz: camera position
    uvec4 info;         // x, y: image size; z: lights
    vec4 ambient;       // radiance += ambient * albedo
};

// The engine's vertex (`Vertex` in world.rs): 24 bytes, object space.
struct Vertex {
    float position[3];
    float normal[3];
};
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer Vertices {
    Vertex v[];
};
