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
        // A signed minimum: lavapipe (Mesa 22.3) loses most 32-bit unsigned atomicMin writes
        // made through a buffer reference (found when TSM's maps came out nearly empty). Bits
        // of non-negative floats order the same as signed ints, and the map is cleared to
        // 0x7fffffff (a NaN: no occluder), so the result is the same on every driver.
        atomicMin(IntArray(map.depths).v[p], int(depth_bits));
    } else {
        atomicMin(Uint64Array(map.depths).v[p], (uint64_t(depth_bits) << 32) | uint64_t(in_id));
    }
}
