#version 450
// Keeps the nearest depth per shadow-map pixel of layer pc.first_sample: with the triangle id
// (DEPTH_AND_ID, 8 bytes) or alone (DEPTH_ONLY, 4 bytes, the papers' time-dependent maps).
#extension GL_EXT_shader_atomic_int64 : require
#include "shared.glsl"

layout(push_constant) uniform Push { PassConstants pc; };

layout(location = 0) in float in_depth;
layout(location = 1) flat in uint in_id;

void main() {
    PlainHeader map = PlainHeader(pc.map);
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    uint layer_size = map.size.x * map.size.y;
    uint p = pc.first_sample * layer_size + pixel.y * map.size.x + pixel.x;
    uint depth_bits = floatBitsToUint(max(in_depth, 0.0));
    if (pc.mode == DEPTH_ONLY) {
        atomicMin(UintArray(map.depths).v[p], depth_bits);
    } else {
        atomicMin(Uint64Array(map.depths).v[p], (uint64_t(depth_bits) << 32) | uint64_t(in_id));
    }
}
