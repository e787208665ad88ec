#version 450
// Test-only (app/tests/gpu/exact_shadow.rs compiles it): glsl/exact_shadow.glsl on
// configurations the host makes: one receiver, one light, up to 12 moving triangles and a
// window of the shutter each; writes every triangle's shadowed intervals and their union.
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "exact_shadow.glsl"

#define PROBE_TRIANGLES 12
// vec4s per configuration: p0, p1, light (w: 1 spot), (scene size, w0, w1, triangles), then six
// corners per triangle (t = 0, then t = 1).
#define PROBE_CONFIG_VEC4S (4 + 6 * PROBE_TRIANGLES)
// floats per result: union length, gaps joined, union count, 16 spans (x, y), then per
// triangle its count and 8 intervals (x, y).
#define PROBE_RESULT_FLOATS (3 + 2 * MS_EXACT_UNION_CAPACITY + PROBE_TRIANGLES * (1 + 2 * MS_EXACT_MAX_INTERVALS))

layout(local_size_x = 16) in;

layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer Configs { vec4 v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) buffer Out { float v[]; };

layout(push_constant) uniform Push {
    uint64_t configs;
    uint64_t results;
    uint count;
} pc;

void main() {
    uint id = gl_GlobalInvocationID.x;
    if (id >= pc.count) return;
    Configs cfg = Configs(pc.configs);
    uint base = id * uint(PROBE_CONFIG_VEC4S);
    vec3 p0 = cfg.v[base].xyz;
    vec3 p1 = cfg.v[base + 1u].xyz;
    vec4 light = cfg.v[base + 2u];
    vec4 params = cfg.v[base + 3u];
    int triangles = int(params.w);
    Out out_ = Out(pc.results);
    uint o = id * uint(PROBE_RESULT_FLOATS);
    ms_exact_Union shadow = ms_exact_union_empty();
    for (int k = 0; k < PROBE_TRIANGLES; ++k) {
        uint slot = o + uint(3 + 2 * MS_EXACT_UNION_CAPACITY + k * (1 + 2 * MS_EXACT_MAX_INTERVALS));
        int n = 0;
        vec2 iv[MS_EXACT_MAX_INTERVALS];
        for (int i = 0; i < MS_EXACT_MAX_INTERVALS; ++i) iv[i] = vec2(0.0);
        if (k < triangles) {
            uint c = base + 4u + uint(6 * k);
            vec3 at0[3] = vec3[3](cfg.v[c].xyz, cfg.v[c + 1u].xyz, cfg.v[c + 2u].xyz);
            vec3 at1[3] = vec3[3](cfg.v[c + 3u].xyz, cfg.v[c + 4u].xyz, cfg.v[c + 5u].xyz);
            bool spot = light.w > 0.5;
            n = ms_exact_shadowed_intervals(p0, p1, spot, light.xyz, ms_exact_s_min(spot, params.x),
                                            at0, at1, params.y, params.z, iv);
            for (int i = 0; i < n; ++i) ms_exact_union_add(shadow, iv[i]);
        }
        out_.v[slot] = float(n);
        for (int i = 0; i < MS_EXACT_MAX_INTERVALS; ++i) {
            out_.v[slot + 1u + 2u * uint(i)] = iv[i].x;
            out_.v[slot + 2u + 2u * uint(i)] = iv[i].y;
        }
    }
    out_.v[o] = ms_exact_union_length(shadow);
    out_.v[o + 1u] = shadow.joined_gaps ? 1.0 : 0.0;
    // Every slot, empty ones included (MS_EXACT_EMPTY): the union keeps no order.
    out_.v[o + 2u] = float(MS_EXACT_UNION_CAPACITY);
    for (int i = 0; i < MS_EXACT_UNION_CAPACITY; ++i) {
        vec2 span = ms_exact_union_slot(shadow, i);
        out_.v[o + 3u + 2u * uint(i)] = span.x;
        out_.v[o + 4u + 2u * uint(i)] = span.y;
    }
}
