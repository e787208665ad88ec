#version 450
// Test-only (tests/gpu/footprint_hull.rs compiles it): the footprint hull of
// glsl/convex_hull.glsl (merge, chain, growth) on point sets the host makes, with every turn
// test computed as a compiler that fuses one product into a multiply-add computes it (NVIDIA
// does; lavapipe never does, so without this the chain's behaviour under fusion could not
// be tested here).
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require

// The rounding error of a * b (Dekker's product): what a fused a * b - c keeps that the
// unfused one drops.
precise float two_product_error(float a, float b) {
    precise float p = a * b;
    precise float ac = a * 4097.0;
    precise float ah = ac - (ac - a);
    precise float al = a - ah;
    precise float bc = b * 4097.0;
    precise float bh = bc - (bc - b);
    precise float bl = b - bh;
    precise float e = ((ah * bh - p) + ah * bl + al * bh) + al * bl;
    return e;
}
#define HULL_FUSED_RESIDUAL(x, y) two_product_error(x, y)
#define HULL_MAX_POINTS 6
#include "convex_hull.glsl"

layout(local_size_x = 64) in;

layout(buffer_reference, std430, buffer_reference_align = 8) readonly buffer Points { vec2 p[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) buffer Out { float v[]; };

layout(push_constant) uniform Push {
    uint64_t points;  // six per set: the corners at t = 0, then at t = 1
    uint64_t results; // 32 per set: h, merge, the grown hull's h points (x, y)
    uint count;
    float grow;       // the growth past the merge's share (the collection's DILATION_TEXELS)
} pc;

void main() {
    uint set = gl_GlobalInvocationID.x;
    if (set >= pc.count) return;
    vec2 p[HULL_MAX_POINTS];
    for (int i = 0; i < 6; ++i) p[i] = Points(pc.points).p[set * 6u + uint(i)];
    float merge = hull_merge_distance(p, 6);
    vec2 hull[2 * HULL_MAX_POINTS];
    int h = convex_hull(p, 6, merge, hull);
    if (h >= 3) h = hull_grow(hull, h, pc.grow + 1.5 * merge);
    Out out_ = Out(pc.results);
    uint base = set * 32u;
    out_.v[base] = float(h);
    out_.v[base + 1u] = merge;
    for (int i = 0; i < 2 * HULL_MAX_POINTS; ++i) {
        out_.v[base + 2u + 2u * uint(i)] = i < h ? hull[i].x : 0.0;
        out_.v[base + 3u + 2u * uint(i)] = i < h ? hull[i].y : 0.0;
    }
}
