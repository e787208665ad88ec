#version 450
// Keeps the nearest depth per shadow-map pixel of layer pc.first_sample: with the triangle id
// (DEPTH_AND_ID, 8 bytes) or alone (DEPTH_ONLY, 4 bytes, the papers' time-dependent maps).
#extension GL_EXT_shader_atomic_int64 : require
#include "shared.glsl"

layout(std140, set = 0, binding = 0) uniform FrameBlock { FrameParams frame; };
layout(std430, set = 0, binding = 3) buffer Depths { uint64_t depths[]; };
layout(std430, set = 0, binding = 4) buffer DepthsOnly { uint depths_only[]; };
layout(push_constant) uniform Push { PassConstants pc; };

layout(location = 0) in float in_depth;
layout(location = 1) flat in uint in_id;

void main() {
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    uint layer_size = frame.sizes.x * frame.sizes.y;
    uint p = pc.first_sample * layer_size + pixel.y * frame.sizes.x + pixel.x;
    uint depth_bits = floatBitsToUint(max(in_depth, 0.0));
    if (pc.mode == DEPTH_ONLY) {
        atomicMin(depths_only[p], depth_bits);
    } else {
        atomicMin(depths[p], (uint64_t(depth_bits) << 32) | uint64_t(in_id));
    }
}
