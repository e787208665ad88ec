// Generation sub-pass (4.3): per shadow-map pixel, group the fragments by triangle id, order
// each group by time, and pair consecutive fragments (1st-2nd, 3rd-4th, ...) into depth-time
// ranges. An odd group leaves its latest fragment alone; it becomes a zero-length range
// [t, t] (it happens where the prism is cut by the light's near or far plane, or at a
// pixel centre exactly on a prism edge), kept so that nothing is dropped and counted by tests.
//
// Why time and not the paper's depth: a triangle's fragments at a pixel are the caps (t = 0,
// t = 1, where it covers the pixel then) and the side surfaces (the instants an edge sweeps
// over it), so in time order they alternate entering / leaving and consecutive pairs are
// exactly the intervals during which the triangle covers the pixel. Depth order is the same
// only while the triangle's depth along the pixel's ray is monotonic in time (translation);
// for a triangle moving within its own plane every fragment has the same depth, and the
// pairing fell to the order the fragments were appended in (found on an NVIDIA driver).
// Shared by the two tiers (generation.comp, generation_long.comp), which define LIST_CAPACITY.
#include "shared.glsl"

layout(push_constant) uniform Push { MapPush pc; };
// Pixels whose lists are too long for the first tier, for the second tier (an indirect
// dispatch whose x group count the first tier raises as it appends).
layout(buffer_reference, std430, buffer_reference_align = 16) buffer LongPixels {
    LongListHeader head;
    uint long_pixels[];
};
const uint LONG_TIER_GROUP = 64u;

// Every buffer of the map, from its header (set once per invocation by `open_map`).
MsShadowMap map;
uint64_t nodes;
uint64_t ranges;
UintArray heads;
UintArray range_heads;
CounterRef counters_ref;
LongPixels long_list;

void open_map() {
    map = MsShadowMap(pc.map);
    nodes = map.nodes;
    ranges = map.ranges;
    heads = UintArray(map.heads);
    range_heads = UintArray(map.range_heads);
    counters_ref = CounterRef(map.counters);
    long_list = LongPixels(map.long_pixels);
}

bool before(Node x, uint xi, Node y, uint yi) {
    if (x.time != y.time) return x.time < y.time;
    return x.depth < y.depth || (x.depth == y.depth && xi < yi);
}

uint out_head = END_OF_LIST;

// Writes the range of fragments a and b at `index` (reserved by the caller) and links it.
void emit(Node a, Node b, uint index) {
    MsRange r;
    bool a_first = a.time <= b.time;
    r.t_s = a_first ? a.time : b.time;
    r.t_e = a_first ? b.time : a.time;
    r.d_s = a_first ? a.depth : b.depth;
    r.d_e = a_first ? b.depth : a.depth;
    r.id = a.id;
    if (index >= counters_ref.c.range_capacity) return;
    r.next = out_head;
    store_range(ranges, index, r);
    out_head = index + 1u;
}

// The triangle the coverage map marks pixel p with, or NO_TRIANGLE (also without the map).
// At a marked pixel no range is stored (the 2017 paper's extension: the coverage map itself
// says what shadows there); they are only counted.
uint covering(uint p) {
    return map.coverage != 0UL ? MsUints(map.coverage).v[p] : NO_TRIANGLE;
}

// The list is copied out, Shell-sorted by (id, time, depth, node index) and paired in one sweep.
// LIST_CAPACITY is the tier's: small private arrays are much faster on lavapipe.
Node local_nodes[LIST_CAPACITY];
uint local_index[LIST_CAPACITY];

bool sorts_after(Node x, uint xi, Node y, uint yi) {
    return x.id > y.id || (x.id == y.id && before(y, yi, x, xi));
}

void sort_and_pair(uint n, uint cover) {
    const uint gaps[6] = uint[6](132u, 57u, 23u, 10u, 4u, 1u);
    for (int g = 0; g < 6; ++g) {
        uint gap = gaps[g];
        for (uint i = gap; i < n; ++i) {
            Node key = local_nodes[i];
            uint key_index = local_index[i];
            uint j = i;
            while (j >= gap && sorts_after(local_nodes[j - gap], local_index[j - gap], key,
                                           key_index)) {
                local_nodes[j] = local_nodes[j - gap];
                local_index[j] = local_index[j - gap];
                j -= gap;
            }
            local_nodes[j] = key;
            local_index[j] = key_index;
        }
    }
    // Count the pixel's ranges first, so one atomic reserves room for all of them.
    uint all_ranges = 0u;
    for (uint i = 0u; i < n; ++all_ranges) {
        i += i + 1u < n && local_nodes[i + 1u].id == local_nodes[i].id ? 2u : 1u;
    }
    if (all_ranges == 0u) return;
    atomicAdd(counters_ref.c.ranges_without_coverage, all_ranges);
    if (cover != NO_TRIANGLE) return;
    uint index = atomicAdd(counters_ref.c.range_count, all_ranges);
    for (uint i = 0u; i < n; ++index) {
        bool pair = i + 1u < n && local_nodes[i + 1u].id == local_nodes[i].id;
        emit(local_nodes[i], pair ? local_nodes[i + 1u] : local_nodes[i], index);
        i += pair ? 2u : 1u;
    }
}

// Copies pixel p's list into the private arrays: its length, or LIST_CAPACITY + 1 if longer.
uint load_list(uint p) {
    uint n = 0u;
    uint a = heads.v[p];
    while (a != END_OF_LIST && n < LIST_CAPACITY) {
        local_nodes[n] = load_node(nodes, a - 1u);
        local_index[n] = a;
        a = local_nodes[n].next;
        ++n;
    }
    return a == END_OF_LIST ? n : LIST_CAPACITY + 1u;
}

// Most texels hold no fragment or the two caps of one triangle (static ground, say): those
// are paired here without the private arrays, which a CPU device keeps in memory per lane.
// False if the list is anything else.
bool pair_two(uint p) {
    uint a = heads.v[p];
    if (a == END_OF_LIST) {
        range_heads.v[p] = END_OF_LIST;
        return true;
    }
    Node first = load_node(nodes, a - 1u);
    if (first.next == END_OF_LIST) return false;
    Node second = load_node(nodes, first.next - 1u);
    if (second.next != END_OF_LIST || second.id != first.id) return false;
    // The counting of pair_list / sort_and_pair for one range, written out: a helper shared
    // by both made generation about 10% slower on lavapipe.
    atomicMax(counters_ref.c.longest_list, 2u);
    atomicAdd(counters_ref.c.ranges_without_coverage, 1u);
    if (covering(p) == NO_TRIANGLE) emit(first, second, atomicAdd(counters_ref.c.range_count, 1u));
    range_heads.v[p] = out_head;
    return true;
}

void pair_list(uint p, uint n) {
    atomicMax(counters_ref.c.longest_list, n);
    sort_and_pair(n, covering(p));
    range_heads.v[p] = out_head;
}
