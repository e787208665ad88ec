#version 450
// Copies the lighting pass's accumulated radiance (RGBA32F per pixel, alpha the share of
// samples seeing a moving triangle) into a host's storage image of any four-channel format,
// so an engine can use the papers' stochastic lighting pass as one of its own passes.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_buffer_reference : require

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0) writeonly uniform image2D target;

layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer Radiance {
    vec4 v[];
};

#include "image_push.glsl"
layout(push_constant) uniform Push { RadiancePush pc; };

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(pixel, pc.size))) return;
    imageStore(target, ivec2(pixel), Radiance(pc.radiance).v[pixel.y * pc.size.x + pixel.x]);
}
