// frame.glsl: the deferred host's per-frame constants, one buffer per frame in flight read by
// device address (no descriptor), shared by its G-buffer and shading shaders.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_buffer_reference : require

const uint MAX_LIGHTS = 2u;

struct Light {
    vec4 position;      // xyz; w = 1 for a spot light, 0 for a directional light
    vec4 direction;     // xyz unit, the way the light travels; w = cos(cone half angle)
    vec4 emission;      // intensity in W/sr (spot) or irradiance in W/m^2 (directional)
};

layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer Frame {
    mat4 view_proj;     // world -> clip (Vulkan: y down, depth in [0, 1])
    mat4 inv_view_proj; // clip -> world
    vec4 eye;           // xyz: camera position
    uvec4 info;         // x, y: image size; z: lights
    vec4 shading;       // x: ambient radiance factor (radiance += ambient * albedo)
    Light lights[MAX_LIGHTS];
};
