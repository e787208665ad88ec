// The collection sub-pass's writes (4.2). append_fragment, shared by both constructions:
// append a fragment (a prism surface over texel p at `time`, `depth`) to the texel's linked
// list. A fragment past the node capacity is counted but not linked, so the count tells the
// caller the size needed. With a coverage map (the header has its address) it also keeps the nearest fragment
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

// Lists texel p's tile for the sort (gpu_constants.rs's SORT_TILE_ROW), once: the first
// range stored in it marks it, appends it to the list and counts the sort's workgroups.
void list_sort_tile(MsShadowMap map, uint p) {
    uvec2 size = map.size.xy;
    uint tiles_x = (size.x + TILE_TEXELS - 1u) / TILE_TEXELS;
    uint tiles = tiles_x * ((size.y + TILE_TEXELS - 1u) / TILE_TEXELS);
    uint tile = (p / size.x) / TILE_TEXELS * tiles_x + (p % size.x) / TILE_TEXELS;
    UintArray words = UintArray(map.tiles);
    // A plain read first: most of a tile's texels find it marked and skip the atomic (a stale
    // 0 only falls through to it).
    if (words.v[DISPATCH_WORDS + tile] != 0u) return;
    if (atomicExchange(words.v[DISPATCH_WORDS + tile], 1u) != 0u) return;
    uint index = atomicAdd(words.v[DISPATCH_SORT + 3u], 1u);
    words.v[DISPATCH_WORDS + tiles + index] = tile;
    // Up to SORT_TILE_ROW workgroups across, as many rows as the listed tiles fill (the row
    // count starts at 1).
    atomicMax(words.v[DISPATCH_SORT], min(index + 1u, SORT_TILE_ROW));
    atomicMax(words.v[DISPATCH_SORT + 1u], index / SORT_TILE_ROW + 1u);
}

// The exact construction without a coverage map: append a covered run [times.x, times.y] of
// triangle `id` over texel p (depths at its ends) to the texel's range list, as the generation
// pass would have paired it from its two nodes. The figures stay those of the lists: two
// fragments per run in node_count, and the texel's node head counts its runs (the list's
// length: at most MAX_LIST_NODES fragments, more is an error as in the generation pass; the
// sorting of MS_SORTED_RANGES takes the texel's place in the range buffer from these counts).
// A range past the range capacity is counted but not linked.
void append_range_of(MsShadowMap map, uint p, vec2 times, vec2 depths, uint id, bool bounded) {
    CounterRef counters = CounterRef(map.counters);
    // The fragment count is even: 2^32 - 2 is the last before it wraps. (The range count,
    // half of it, cannot wrap first.)
    if (atomicAdd(counters.c.node_count, 2u) == 0xfffffffeu) atomicOr(counters.c.wrapped, 1u);
    uint fragments = 2u * (atomicAdd(UintArray(map.heads).v[p], 1u) + 1u);
    atomicMax(counters.c.longest_list, fragments);
    // The texel's first range, where the generation sorts the lists: its tile joins the sort.
    if (bounded && fragments == 2u && map.list_ranges != map.ranges) list_sort_tile(map, p);
    if (bounded && fragments > MAX_LIST_NODES) {
        if (fragments == MAX_LIST_NODES + 2u) atomicAdd(counters.c.overlong_pixels, 1u);
        return;
    }
    uint index = atomicAdd(counters.c.range_count, 1u);
    if (index >= counters.c.range_capacity) return;
    uint next = atomicExchange(UintArray(map.range_heads).v[p], index + 1u);
    // list_ranges: the range buffer itself, or, where the map keeps its ranges sorted, the
    // lists the generation pass sorts them from (range_sort.comp).
    store_range(map.list_ranges, index, MsRange(times.x, times.y, depths.x, depths.y, id, next));
}

void append_range(MsShadowMap map, uint p, vec2 times, vec2 depths, uint id) {
    append_range_of(map, p, times, depths, id, true);
}

// The exact lookup's range (the conservative collection): no bound on the texel's list, which
// is neither paired nor sorted; the exact lookup walks all of it (the mask counts its loop
// iterations against a device's loop limit).
void append_named_range(MsShadowMap map, uint p, vec2 times, vec2 depths, uint id) {
    append_range_of(map, p, times, depths, id, false);
}

// The exact lookup's static layer (MsStaticNames in exact_lookup.glsl): a count and a
// capacity, two unused words, a head per texel, then (id, next) pairs.
layout(buffer_reference, std430, buffer_reference_align = 4) buffer StaticNames {
    uint count;
    uint capacity;
    uint unused[2];
    uint v[];
};

// Names static triangle `id` in texel p's static list (kept across frames with the static
// layer). A name past the capacity is counted but not linked (the map then needs more room).
void append_static_name(MsShadowMap map, uint p, uint id) {
    StaticNames names = StaticNames(map.static_names);
    uint index = atomicAdd(names.count, 1u);
    if (index == 0xffffffffu) atomicOr(CounterRef(map.counters).c.wrapped, 1u);
    if (index >= names.capacity) return;
    uint texels = map.size.x * map.size.y;
    uint next = atomicExchange(names.v[p], index + 1u);
    names.v[texels + 2u * index] = id;
    names.v[texels + 2u * index + 1u] = next;
}
