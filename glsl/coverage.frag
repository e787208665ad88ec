#version 450
// Coverage map, second pass of the 2017 paper's extension: the triangles at t = 0 and at
// t = 1. A pixel is marked with a triangle's id when that triangle is the nearest map's
// occluder there through its cap at the OTHER time: it covers the pixel at both ends of the
// frame. The mark keeps the triangle's depth at the pixel at t = 0 and t = 1, for the reset.
#extension GL_EXT_shader_atomic_int64 : require
#include "shared.glsl"

layout(push_constant) uniform Push { MapDrawPush pc; };

layout(location = 0) in float in_depth;
layout(location = 1) flat in uint in_id;

void main() {
    MsShadowMap map = MsShadowMap(pc.map);
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    uint p = pixel.y * map.size.x + pixel.x;
    uint64_t n = Uint64Array(map.nearest).v[p];
    if (n == NEAREST_EMPTY) return;
    uint packed_low = uint(n & 0xffffffffUL);
    uint id = packed_low & NEAREST_ID_MASK;
    uint surface = packed_low >> 30;
    uint other_cap = pc.time == 0.0 ? SURFACE_CAP1 : SURFACE_CAP0;
    if (id != in_id || surface != other_cap) return;
    // Only one fragment per pixel gets here: the nearest map holds one specific cap.
    UintArray(map.coverage).v[p] = in_id;
    float other_depth = uintBitsToFloat(uint(n >> 32));
    Vec2Array(map.cover_depth).v[p] = pc.time == 0.0 ? vec2(in_depth, other_depth) : vec2(other_depth, in_depth);
}
