#version 450
// Test-only: the lighting pass's per-texel test of a pixel's samples (glsl/temporal_samples.glsl,
// ms_samples_shadowed) against ms_texel_shadowed per sample, on the same receivers: one
// invocation per group of SHADE_SAMPLES queries, both answers written per query (1 shadowed).
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_control_flow_attributes : require
#include "motion_shadows.glsl"
const uint SHADE_SAMPLES = 8u;
#include "temporal_samples.glsl"

layout(local_size_x = 16) in;

struct Query {
    vec3 position;
    float time;
    vec3 normal;
    uint own;
};

layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer Queries {
    Query q[];
};
layout(buffer_reference, std430, buffer_reference_align = 4) writeonly buffer Results {
    float v[];
};

layout(push_constant) uniform Push {
    uint64_t map;
    uint64_t queries;
    uint64_t results;
    uint groups;
} pc;

void main() {
    uint group = gl_GlobalInvocationID.x;
    if (group >= pc.groups) return;
    MsMap map = ms_load(MsShadowMap(pc.map));
    uint texel[SHADE_SAMPLES], own[SHADE_SAMPLES];
    float depth[SHADE_SAMPLES], t[SHADE_SAMPLES];
    uint seen = 0u;
    for (uint j = 0u; j < SHADE_SAMPLES; ++j) {
        Query q = Queries(pc.queries).q[group * SHADE_SAMPLES + j];
        t[j] = q.time;
        own[j] = q.own;
        if (ms_receiver(map, q.position, q.normal, texel[j], depth[j])) seen |= 1u << j;
    }
    uint grouped = ms_samples_shadowed(map, seen, texel, depth, t, own);
    Results results = Results(pc.results);
    for (uint j = 0u; j < SHADE_SAMPLES; ++j) {
        bool alone = (seen & (1u << j)) != 0u
                     && ms_texel_shadowed(map, texel[j], depth[j], t[j], own[j]);
        uint at = 2u * (group * SHADE_SAMPLES + j);
        results.v[at] = (grouped & (1u << j)) != 0u ? 1.0 : 0.0;
        results.v[at + 1u] = alone ? 1.0 : 0.0;
    }
}
