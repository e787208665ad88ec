// The collection sub-pass's one write (4.2), shared by both constructions: append a fragment
// (a prism surface over texel p at `time`, `depth`) to the texel's linked list. A fragment
// past the node capacity is counted but not linked, so the count tells the caller the size
// needed. With a coverage map (the header has its address) it also keeps the nearest fragment
// per texel: the nearest map, first pass of the 2017 paper's extension.
#extension GL_EXT_shader_atomic_int64 : require

void append_fragment(MsShadowMap map, uint p, float depth, float time, uint id, uint surface) {
    if (map.nearest != 0UL) {
        atomicMin(Uint64Array(map.nearest).v[p], pack_nearest(depth, surface, id));
    }
    CounterRef counters = CounterRef(map.counters);
    uint index = atomicAdd(counters.c.node_count, 1u);
    // Every count is handed out once, so the last one marks the wrap of the 32-bit counter.
    if (index == 0xffffffffu) atomicOr(counters.c.wrapped, 1u);
    if (index >= counters.c.node_capacity || counters.c.wrapped != 0u) return;
    uint next = atomicExchange(UintArray(map.heads).v[p], index + 1u);
    store_node(map.nodes, index, Node(depth, clamp(time, 0.0, 1.0), id, next));
}
