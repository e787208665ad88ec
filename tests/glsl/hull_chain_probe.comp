#version 450
// Test-only (tests/gpu/footprint_hull_ties.rs compiles it): the footprint hull of
// glsl/convex_hull.glsl (merge and chain, no growth) on point sets the host makes, its
// vertices as the chain returns them.
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require

#define HULL_MAX_POINTS 6
#include "convex_hull.glsl"

layout(local_size_x = 64) in;

layout(buffer_reference, std430, buffer_reference_align = 8) readonly buffer Points { vec2 p[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) buffer Out { float v[]; };

layout(push_constant) uniform Push {
    uint64_t points;  // six per set
    uint64_t results; // 32 per set: h, then the hull's h points (x, y)
    uint count;
} pc;

void main() {
    uint set = gl_GlobalInvocationID.x;
    if (set >= pc.count) return;
    vec2 p[HULL_MAX_POINTS];
    for (int i = 0; i < 6; ++i) p[i] = Points(pc.points).p[set * 6u + uint(i)];
    vec2 hull[2 * HULL_MAX_POINTS];
    int h = convex_hull(p, 6, hull_merge_distance(p, 6), hull);
    Out out_ = Out(pc.results);
    uint base = set * 32u;
    out_.v[base] = float(h);
    for (int i = 0; i < 2 * HULL_MAX_POINTS; ++i) {
        out_.v[base + 1u + 2u * uint(i)] = i < h ? hull[i].x : 0.0;
        out_.v[base + 2u + 2u * uint(i)] = i < h ? hull[i].y : 0.0;
    }
}
