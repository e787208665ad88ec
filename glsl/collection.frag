#version 450
// Collection sub-pass (4.2): append this fragment to its pixel's linked list. A fragment past
// the node capacity is counted but not linked, so the count tells the caller the size needed.
// With a coverage map (the header has its address) it also keeps the nearest fragment per pixel: the nearest map, first pass
// of the 2017 paper's extension (same prisms, so it shares this rasterization).
#extension GL_EXT_shader_atomic_int64 : require
#include "shared.glsl"

layout(push_constant) uniform Push { PassConstants pc; };

layout(location = 0) in float in_depth;
layout(location = 1) in float in_time;
layout(location = 2) flat in uint in_id;
layout(location = 3) flat in uint in_surface;

void main() {
    MsShadowMap map = MsShadowMap(pc.map);
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    uint p = pixel.y * map.size.x + pixel.x;
    if (map.nearest != 0UL) {
        atomicMin(Uint64Array(map.nearest).v[p], pack_nearest(in_depth, in_surface, in_id));
    }
    CounterRef counters = CounterRef(map.counters);
    uint index = atomicAdd(counters.c.node_count, 1u);
    // Every count is handed out once, so the last one marks the wrap of the 32-bit counter.
    if (index == 0xffffffffu) atomicOr(counters.c.wrapped, 1u);
    if (index >= counters.c.node_capacity || counters.c.wrapped != 0u) return;
    uint next = atomicExchange(UintArray(map.heads).v[p], index + 1u);
    NodeArray(map.nodes).nodes[index] = Node(in_depth, clamp(in_time, 0.0, 1.0), in_id, next);
}
