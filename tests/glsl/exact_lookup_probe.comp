#version 450
// Test-only (tests/gpu/exact_lookup.rs compiles it): glsl/exact_lookup.glsl's
// ms_lit_fraction_exact_moving on a map built with the exact lookup, for receivers the host
// lists: per receiver two vec4, (p0, own as bits) and (p1, time); one float each back. A time
// in [0, 1] asks ms_visible_exact at that time instead, for the receiver at p0 (1 lit, 0 not).
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "motion_shadows.glsl"
#include "exact_lookup.glsl"

layout(local_size_x = 16) in;

layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer Receivers {
    vec4 v[];
};
layout(buffer_reference, std430, buffer_reference_align = 4) buffer Out { float v[]; };

layout(push_constant) uniform Push {
    uint64_t map;
    uint64_t receivers;
    uint64_t results;
    uint count;
} pc;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    Receivers receivers = Receivers(pc.receivers);
    vec4 a = receivers.v[2u * i], b = receivers.v[2u * i + 1u];
    uint own = floatBitsToUint(a.w);
    MsShadowMap map = MsShadowMap(pc.map);
    Out(pc.results).v[i] = b.w >= 0.0 ? (ms_visible_exact(map, a.xyz, b.w, own) ? 1.0 : 0.0)
                                      : ms_lit_fraction_exact_moving(map, a.xyz, b.xyz, own);
}
