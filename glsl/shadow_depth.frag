#version 450
// Keeps the nearest (depth, triangle id) per shadow-map pixel of layer pc.first_sample.
#extension GL_EXT_shader_atomic_int64 : require
#include "shared.glsl"

layout(std140, set = 0, binding = 0) uniform FrameBlock { FrameParams frame; };
layout(std430, set = 0, binding = 3) buffer Depths { uint64_t depths[]; };
layout(push_constant) uniform Push { PassConstants pc; };

layout(location = 0) in float in_depth;
layout(location = 1) flat in uint in_id;

void main() {
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    uint layer_size = frame.sizes.x * frame.sizes.y;
    uint p = pc.first_sample * layer_size + pixel.y * frame.sizes.x + pixel.x;
    atomicMin(depths[p], (uint64_t(floatBitsToUint(max(in_depth, 0.0))) << 32) | uint64_t(in_id));
}
