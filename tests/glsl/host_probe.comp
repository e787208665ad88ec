#version 450
// A host's debugging probe: ms_visibility of a temporal shadow map at given world points,
// normals, shutter times and receiver triangle ids, one query per invocation. Everything is
// reached by device address (the map's header, the queries, the results), so the pipeline
// has no descriptor set at all.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_buffer_reference : require
#include "motion_shadows.glsl"

layout(local_size_x = 64) in;

struct Query {
    vec3 position;      // world
    float time;         // shutter time in [0, 1]; negative: the lit fraction (no time)
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
    uint count;
} pc;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    Query q = Queries(pc.queries).q[i];
    // A negative time asks for the lit fraction of the whole shutter instead.
    MsShadowMap map = MsShadowMap(pc.map);
    Results(pc.results).v[i] = q.time < 0.0
                                   ? ms_lit_fraction(map, q.position, q.normal, q.own)
                                   : ms_visibility(map, q.position, q.normal, q.time, q.own);
}
