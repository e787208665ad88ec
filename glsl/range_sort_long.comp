#version 450
// Sorting the collected ranges, second tier (range_sort_lists.glsl): the texels the first
// tier found too long for its arrays, with room for every
// list the collection links (MAX_LIST_NODES / 2 runs; a longer one is an error of the frame,
// counted there). The dispatch is 2D (x at most LONG_SORT_ROW groups of 64), as the first
// tier counted it.
// (One workgroup per texel ranking its ranges in shared memory was 8x slower on lavapipe.)
#define SORT_CAPACITY (MAX_LIST_NODES / 2u)
#include "range_sort_lists.glsl"

layout(local_size_x = 64) in;

void main() {
    open_sort();
    uint index = (gl_WorkGroupID.y * LONG_SORT_ROW + gl_WorkGroupID.x) * 64u +
                 gl_LocalInvocationID.x;
    if (index >= scratch.head.count) return;
    uint p = scratch.v[index];
    open_pruning(p);
    uint n = load_ranges(UintArray(map.range_heads).v[p]);
    if (n <= SORT_CAPACITY) {
        sort_and_store(p, n);
    } else {
        UintArray(map.range_heads).v[p] = END_OF_LIST;
    }
}
