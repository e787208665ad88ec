#version 450
// Generation, second tier: the pixels the first tier found too long for its arrays, with
// room for MAX_LIST_NODES fragments. A list longer still is not paired but counted
// (Counters.overlong_pixels), and the renderer reports it as an error with the figures:
// nothing is dropped silently.
#define LIST_CAPACITY MAX_LIST_NODES
#include "generation_common.glsl"

layout(local_size_x = 64) in;

void main() {
    open_map();
    uint index = gl_GlobalInvocationID.x;
    if (index >= long_list.head.count) return;
    uint p = long_list.long_pixels[index];
    uint n = load_list(p);
    if (n <= MAX_LIST_NODES) {
        pair_list(p, n);
        return;
    }
    // Count the rest only to report it; cheap, and bounded by the node capacity.
    n = MAX_LIST_NODES;
    uint a = local_index[MAX_LIST_NODES - 1u];
    for (a = load_node(nodes, a - 1u).next; a != END_OF_LIST && n < 8u * MAX_LIST_NODES;
         a = load_node(nodes, a - 1u).next) {
        ++n;
    }
    atomicAdd(counters_ref.c.overlong_pixels, 1u);
    atomicMax(counters_ref.c.longest_list, n);
    range_heads.v[p] = END_OF_LIST;
}
