// Sorting the collected ranges (MS_SORTED_RANGES): where the collection stored each covered
// run as its range directly, it linked them into per-texel lists in the order its fragment
// invocations ran (the header's list_ranges) and counted each texel's runs (in the node
// heads). range_sort.comp gives every texel a place of exactly that many ranges in the range
// buffer (an atomic on the ranges reserved so far) and copies its list there, sorted by start time and linked in that order;
// range_sort_long.comp does the same for the few lists too long for the first tier's arrays.
// A lookup then reads a texel's ranges from consecutive addresses, and one at time t may stop
// at the first range that starts after t. The buffer holds exactly the ranges the lists held
// but the pruned ones.
#include "shared.glsl"

layout(push_constant) uniform Push { MapPush pc; };

// The generation pass's long-pixel list (generation_common.glsl's LongPixels), reused for the
// long lists' pixels.
layout(buffer_reference, std430, buffer_reference_align = 16) buffer SortScratch {
    LongListHeader head;
    uint v[];
};
// The long lists' dispatch: workgroups of 64 long lists, LONG_SORT_ROW groups across (x,
// counted up to it by the first tier as it appends), rows of them down (y). Its arguments
// are the third of the header's `tiles` (uint DISPATCH_SORT_LONG on, gpu_constants.rs).
const uint LONG_SORT_ROW = 65535u;
// Pruning's margin PRUNE_MARGIN, relative to the depths compared (the static layer's,
// range_sort_lists.glsl; the larger of a range's and its cover's, range_cover.glsl): generated
// from src/technique/gpu_constants.rs, which the tests' CPU model of pruning reads too.

MsShadowMap map;
SortScratch scratch;

void open_sort() {
    map = MsShadowMap(pc.map);
    scratch = SortScratch(map.long_pixels);
}
