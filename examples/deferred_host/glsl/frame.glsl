// frame.glsl: the deferred host's per-frame constants (one uniform buffer per frame in
// flight, set 0 binding 0), shared by its G-buffer and shading shaders. This is the host's
// own header; the library's (motion_shadows.glsl) comes from the same include callback.

const uint MAX_LIGHTS = 2u;

struct Light {
    vec4 position;      // xyz; w = 1 for a spot light, 0 for a directional light
    vec4 direction;     // xyz unit, the way the light travels; w = cos(cone half angle)
    vec4 emission;      // x = intensity in W/sr (spot) or irradiance in W/m^2 (directional)
};

layout(set = 0, binding = 0, std140) uniform Frame {
    mat4 view_proj;     // world -> clip (Vulkan: y down, depth in [0, 1])
    mat4 inv_view_proj; // clip -> world
    vec4 eye;           // xyz: camera position
    uvec4 info;         // x, y: image size; z: lights
    vec4 shading;       // x: ambient radiance factor (radiance += ambient * albedo)
    Light lights[MAX_LIGHTS];
} frame;
