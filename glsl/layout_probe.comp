#version 450
// Test-only (tests/gpu/layout.rs): checks that the Rust mirrors in technique::gpu_types have
// the layouts of the GLSL structs. The host writes every struct it sends to shaders with
// distinct values; this shader reads them field by field, in declaration order, and dumps the
// scalars into a flat array that the host compares with its own fields. For the structs
// shaders write (Node, MsRange, Counters), it writes known values the host reads back.
#include "shared.glsl"

layout(local_size_x = 1) in;

layout(push_constant) uniform Push { PassConstants pc; };

// pc.map points at the addresses of: the inputs (temporal and plain map headers, a draw
// record, camera parameters) and the outputs (the flat dump, a Node, an MsRange, Counters).
layout(buffer_reference, std430, buffer_reference_align = 8) readonly buffer ProbeTable {
    uint64_t shadow_header;
    uint64_t plain_header;
    uint64_t draw;
    uint64_t camera;
    uint64_t dump;
    uint64_t node;
    uint64_t range;
    uint64_t counters;
};
layout(buffer_reference, std430, buffer_reference_align = 4) buffer Dump { uint v[]; };
layout(buffer_reference, std430, buffer_reference_align = 8) readonly buffer DrawOne {
    DrawRecord d;
};

Dump dump;
uint n = 0u;

void put(uint x) { dump.v[n++] = x; }
void put(float x) { put(floatBitsToUint(x)); }
void put(uint64_t x) { put(uint(x & 0xffffffffUL)); put(uint(x >> 32)); }
void put(vec4 x) { for (int i = 0; i < 4; ++i) put(x[i]); }
void put(uvec4 x) { for (int i = 0; i < 4; ++i) put(x[i]); }
void put(mat4 m) { for (int c = 0; c < 4; ++c) put(m[c]); }
void put(MsLight l) {
    put(l.view); put(l.proj); put(l.position); put(l.direction); put(l.emission); put(l.bias);
}

void main() {
    ProbeTable table = ProbeTable(pc.map);
    dump = Dump(table.dump);

    MsShadowMap m = MsShadowMap(table.shadow_header);
    put(m.light); put(m.size); put(m.range_heads); put(m.ranges); put(m.coverage);
    put(m.cover_depth); put(m.heads); put(m.nodes); put(m.counters); put(m.long_pixels);
    put(m.nearest); put(m.static_nearest); put(m.tiles);

    PlainHeader p = PlainHeader(table.plain_header);
    put(p.light); put(p.size); put(p.depths); put(p.ids);

    DrawRecord d = DrawOne(table.draw).d;
    put(d.positions0); put(d.positions1); put(d.indices); put(d.stride0); put(d.stride1);
    put(d.index_kind); put(d.vertex_count); put(d.first_id); put(d.triangle_count);
    put(d.albedo_flags);
    for (int i = 0; i < 3; ++i) put(d.model0[i]);
    for (int i = 0; i < 3; ++i) put(d.model1[i]);

    CameraParams c = TargetHeader(table.camera).camera;
    put(c.view_proj); put(c.position); put(c.forward); put(c.ray00); put(c.ray_dx);
    put(c.ray_dy); put(c.image); put(c.shading); put(c.visibility); put(c.radiance);
    put(c.counters); put(c.reserved);

    put(pc.map); put(pc.draws); put(pc.target); put(pc.draw_index); put(pc.draw_count);
    put(pc.first_sample); put(pc.sample_count); put(pc.mode); put(pc.time); put(pc.flags);
    put(pc.reserved);

    NodeArray(table.node).nodes[1] = Node(1.5, 0.25, 7u, 9u);
    RangeArray(table.range).ranges[1] = MsRange(0.125, 0.75, 2.5, 3.5, 11u, 13u);
    CounterRef(table.counters).c = Counters(21u, 22u, 23u, 24u, 31u, 32u, 33u, 34u, 35u, 36u,
                                                  37u, 38u);
}
