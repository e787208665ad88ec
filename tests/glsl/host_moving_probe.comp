#version 450
// A host's probe of moving receivers: ms_lit_fraction_moving of a temporal shadow map for
// receivers moving linearly over the shutter. Each invocation takes two queries (the probe's
// 32-byte query records): the receiver at t = 0 (position, normal, own id) and at t = 1
// (position; the rest unused), and writes one lit fraction.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_buffer_reference : require
#include "motion_shadows.glsl"

layout(local_size_x = 64) in;

struct Query {
    vec3 position;
    float time;         // unused
    vec3 normal;        // unit, on the side facing the light
    uint own;           // the receiver's triangle id, or MS_NO_TRIANGLE
};

layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer Queries {
    Query q[];
};
layout(buffer_reference, std430, buffer_reference_align = 4) writeonly buffer Results {
    float v[];
};

layout(push_constant) uniform Push {
    uint64_t map;       // TemporalShadowMap::header_address()
    uint64_t queries;
    uint64_t results;
    uint count;         // invocations (receivers)
} pc;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    Query start = Queries(pc.queries).q[2u * i];
    Query end = Queries(pc.queries).q[2u * i + 1u];
    Results(pc.results).v[i] = ms_lit_fraction_moving(MsShadowMap(pc.map), start.position,
                                                      end.position, start.normal, start.own);
}
