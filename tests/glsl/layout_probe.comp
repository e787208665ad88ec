#version 450
// Test-only (tests/gpu/layout.rs compiles it): checks that the Rust mirrors in
// technique::gpu_types and technique::push_constants have the layouts of the GLSL structs. The host writes every struct it sends to shaders with
// distinct values; this shader reads them field by field, in declaration order, and dumps the
// scalars into a flat array that the host compares with its own fields. For the structs
// shaders write (Node, MsRange, Counters), it writes known values the host reads back.
#include "shared.glsl"
#include "image_push.glsl"

layout(local_size_x = 1) in;

// The generation's block (MapPush) is pushed for real; the other passes' blocks are read from
// buffers with the same std430 layout that push-constant blocks take.
layout(push_constant) uniform Push { MapPush pc; };

// pc.map points at the addresses of: the inputs (temporal and plain map headers, a draw
// record, camera parameters, the push blocks, a long-pixel list header) and the outputs (the
// flat dump, a Node, an MsRange, Counters).
layout(buffer_reference, std430, buffer_reference_align = 8) readonly buffer ProbeTable {
    uint64_t shadow_header;
    uint64_t plain_header;
    uint64_t draw;
    uint64_t camera;
    uint64_t dump;
    uint64_t node;
    uint64_t range;
    uint64_t counters;
    uint64_t map_draw_push;
    uint64_t raster_push;
    uint64_t shade_push;
    uint64_t long_list;
    uint64_t mask_push;
    uint64_t tsm_mask_push;
    uint64_t gbuffer_push;
    uint64_t radiance_push;
};
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer MaskPushRef {
    MaskPush v;
};
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer TsmMaskPushRef {
    TsmMaskPush v;
};
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer GBufferPushRef {
    GBufferPush v;
};
layout(buffer_reference, std430, buffer_reference_align = 8) readonly buffer RadiancePushRef {
    RadiancePush v;
};
layout(buffer_reference, std430, buffer_reference_align = 8) readonly buffer MapDrawPushRef {
    MapDrawPush v;
};
// The raster's whole push block: its constants, then the camera.
layout(buffer_reference, std430, buffer_reference_align = 8) readonly buffer RasterPushRef {
    LightingRasterPush pass;
    RasterCamera cam;
};
layout(buffer_reference, std430, buffer_reference_align = 8) readonly buffer ShadePushRef {
    ShadePush v;
};
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer LongListRef {
    LongListHeader v;
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

void put(DrawPush d) { put(d.draws); put(d.draw_index); put(d.draw_count); }

void put(DrawRecord d) {
    put(d.positions0); put(d.positions1); put(d.indices); put(d.stride0); put(d.stride1);
    put(d.index_kind); put(d.vertex_count); put(d.first_id); put(d.triangle_count);
    put(d.albedo_flags);
    for (int i = 0; i < 3; ++i) put(d.model0[i]);
    for (int i = 0; i < 3; ++i) put(d.model1[i]);
}

void put(CameraParams c) {
    put(c.view_proj); put(c.position); put(c.forward); put(c.ray00); put(c.ray_dx);
    put(c.ray_dy); put(c.image); put(c.shading); put(c.visibility); put(c.radiance);
    put(c.counters); put(c.camera_end);
}

void main() {
    ProbeTable table = ProbeTable(pc.map);
    dump = Dump(table.dump);

    MsShadowMap m = MsShadowMap(table.shadow_header);
    put(m.light); put(m.size); put(m.range_heads); put(m.ranges); put(m.coverage);
    put(m.cover_depth); put(m.heads); put(m.nodes); put(m.counters); put(m.long_pixels);
    put(m.nearest); put(m.static_nearest); put(m.tiles); put(m.list_ranges);
    put(m.triangles); put(m.static_names);
    MsLightEnd e = MsLightEndRef(table.shadow_header + MS_LIGHT_END_OFFSET).end;
    put(e.view); put(e.frame); put(e.position); put(e.direction);

    PlainHeader p = PlainHeader(table.plain_header);
    put(p.light); put(p.size); put(p.depths); put(p.ids);

    put(DrawOne(table.draw).d);

    put(TargetHeader(table.camera).camera);

    put(pc.map);
    MapDrawPush md = MapDrawPushRef(table.map_draw_push).v;
    put(md.draw); put(md.map); put(md.time); put(md.flags);
    RasterPushRef raster = RasterPushRef(table.raster_push);
    LightingRasterPush lr = raster.pass;
    put(lr.draw); put(lr.visibility); put(lr.target); put(lr.first_sample);
    put(lr.sample_count); put(lr.time); put(lr.flags);
    RasterCamera cam = raster.cam;
    for (int i = 0; i < 3; ++i) put(cam.origin[i]);
    put(cam.near); put(cam.far);
    for (int i = 0; i < 3; ++i) put(cam.ray00[i]);
    for (int i = 0; i < 3; ++i) put(cam.ray_dx[i]);
    for (int i = 0; i < 3; ++i) put(cam.ray_dy[i]);
    put(cam.width); put(cam.spp); put(cam.seed);
    ShadePush sp = ShadePushRef(table.shade_push).v;
    put(sp.draws); put(sp.shadow); put(sp.target); put(sp.draw_count); put(sp.first_sample);
    put(sp.time); put(sp.flags);
    LongListHeader ll = LongListRef(table.long_list).v;
    put(ll.count); put(ll.groups_x); put(ll.groups_y); put(ll.groups_z);
    MaskPush mp = MaskPushRef(table.mask_push).v;
    put(mp.inv_view_proj); put(mp.map); put(mp.size.x); put(mp.size.y);
    put(mp.background_depth); put(mp.flags); put(mp.over_budget); put(mp.loop_budget);
    put(mp.time); put(mp.queue); put(mp.round); put(mp.rounds); put(mp.capacity);
    put(mp.probe);
    TsmMaskPush tp = TsmMaskPushRef(table.tsm_mask_push).v;
    put(tp.inv_view_proj); put(tp.light); put(tp.size.x); put(tp.size.y);
    put(tp.background_depth); put(tp.flags); put(tp.map_size.x); put(tp.map_size.y);
    put(tp.time); put(tp.maps); put(tp.inv_maps); put(tp.first_map); put(tp.batch);
    put(tp.reserved);
    GBufferPush gp = GBufferPushRef(table.gbuffer_push).v;
    put(gp.view_proj); put(gp.eye); put(gp.draws); put(gp.draw_index); put(gp.time);
    RadiancePush rp = RadiancePushRef(table.radiance_push).v;
    put(rp.radiance); put(rp.size.x); put(rp.size.y);

    // The shaders read the header through ms_load's 64-bit words: the same fields again.
    MsMap loaded = ms_load(m);
    put(loaded.light); put(uvec4(loaded.size, 0u, 0u)); put(loaded.range_heads);
    put(loaded.ranges); put(loaded.coverage); put(loaded.cover_depth);
    put(loaded.static_nearest); put(loaded.triangles);
    // And draws through load_draw's words.
    put(load_draw(table.draw, 0u));
    // And the camera through load_camera's.
    put(load_camera(table.camera));

    // Nodes and ranges go through the word helpers the shaders use: the host checks the
    // bytes written, and reading them back must give the values written.
    store_node(table.node, 1u, Node(1.5, 0.25, 7u, 9u));
    store_range(table.range, 1u, MsRange(0.125, 0.75, 2.5, 3.5, 11u, 13u));
    Node node = load_node(table.node, 1u);
    put(node.depth); put(node.time); put(node.id); put(node.next);
    MsRange range = ms_range(table.range, 2u);
    put(range.t_s); put(range.t_e); put(range.d_s); put(range.d_e); put(range.id);
    put(range.next);
    CounterRef(table.counters).c = Counters(21u, 22u, 23u, 24u, 31u, 32u, 33u, 34u, 35u, 36u,
                                                  37u, 38u);
}
