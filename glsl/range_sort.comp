#version 450
// Sorting the collected ranges, first tier (range_sort_common.glsl, range_sort_lists.glsl):
// every texel whose list keeps at most SHORT_SORT ranges after the static rule's pruning
// (nearly all) is sorted, pruned by the cover rule where COVER_RULE, and written to places it
// takes; longer lists go to range_sort_long.comp through the scratch list (an indirect
// dispatch whose group counts this tier raises). One workgroup per 8x8-texel tile that holds
// a range: the tiles the collection listed (collection_append.glsl's list_sort_tile).
#define SHORT_SORT 16u
#define SORT_CAPACITY SHORT_SORT
#include "range_sort_lists.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

// A list of one or two ranges (most texels that hold any), written without the private
// arrays, which a CPU device keeps in memory per lane.
void store_short(uint p, uint head, uint second, uvec2 links, uvec2 links2) {
    Words words = Words(map.list_ranges);
    uint at = 3u * (head - 1u);
    uvec2 t0 = unpackUint2x32(words.v[at]), d0 = unpackUint2x32(words.v[at + 1u]);
    uint i0 = links.x;
    uvec2 t1 = uvec2(0u), d1 = uvec2(0u);
    uint i1 = links2.x;
    bool keep0 = !pruned(d0), keep1 = second != END_OF_LIST;
    if (keep1) {
        uint at2 = 3u * (second - 1u);
        t1 = unpackUint2x32(words.v[at2]);
        d1 = unpackUint2x32(words.v[at2 + 1u]);
        keep1 = !pruned(d1);
    }
    // Two left: the cover rule's candidates for each are the other and S (range_cover.glsl).
    if (COVER_RULE && keep0 && keep1) {
        bool drop0 = covered_by_pair(t0, d0, i0, t1, d1, i1);
        keep1 = !covered_by_pair(t1, d1, i1, t0, d0, i0);
        keep0 = !drop0;
    }
    // Two left: the coverage rule keeps one that holds the texel all frame in front of the other.
    if (COVERAGE_RULE && keep0 && keep1) {
        if (covers_all_frame(t0) && behind_all_along(d0, t1, d1)) {
            keep1 = false;
        } else if (covers_all_frame(t1) && behind_all_along(d1, t0, d0)) {
            keep0 = false;
        }
    }
    if (!keep0) {   // the second (if kept) alone
        t0 = t1; d0 = d1; i0 = i1;
        if (!keep1) {
            UintArray(map.range_heads).v[p] = END_OF_LIST;
            return;
        }
        keep1 = false;
    }
    uint n = keep1 ? 2u : 1u;
    uint base = take_places(n);
    // Past the capacity the frame overflowed (the counters say so, and it is recorded again
    // with room): nothing is written out of bounds.
    if (base + n > CounterRef(map.counters).c.range_capacity) {
        UintArray(map.range_heads).v[p] = END_OF_LIST;
        return;
    }
    Words out_words = Words(map.ranges);
    if (n == 2u) {
        if (sorts_after(t0, d0, i0, t1, d1, i1)) {
            uvec2 ts = t0, ds = d0;
            uint is = i0;
            t0 = t1; d0 = d1; i0 = i1;
            t1 = ts; d1 = ds; i1 = is;
        }
        uint out2 = 3u * (base + 1u);
        out_words.v[out2] = packUint2x32(t1);
        out_words.v[out2 + 1u] = packUint2x32(d1);
        out_words.v[out2 + 2u] = packUint2x32(uvec2(i1, END_OF_LIST));
    }
    uint out1 = 3u * base;
    out_words.v[out1] = packUint2x32(t0);
    out_words.v[out1 + 1u] = packUint2x32(d0);
    out_words.v[out1 + 2u] = packUint2x32(uvec2(i0, n == 2u ? base + 2u : END_OF_LIST));
    UintArray(map.range_heads).v[p] = base + 1u;
}

void main() {
    open_sort();
    UintArray tile_words = UintArray(map.tiles);
    uint slot = gl_WorkGroupID.y * SORT_TILE_ROW + gl_WorkGroupID.x;
    // The last row's workgroups past the list.
    if (slot >= tile_words.v[DISPATCH_SORT + 3u]) return;
    uint tiles_x = (map.size.x + TILE_TEXELS - 1u) / TILE_TEXELS;
    uint tiles = tiles_x * ((map.size.y + TILE_TEXELS - 1u) / TILE_TEXELS);
    uint tile = tile_words.v[DISPATCH_WORDS + tiles + slot];
    uvec2 pixel = uvec2(tile % tiles_x, tile / tiles_x) * TILE_TEXELS + gl_LocalInvocationID.xy;
    if (pixel.x >= map.size.x || pixel.y >= map.size.y) return;
    uint p = pixel.y * map.size.x + pixel.x;
    uint head = UintArray(map.range_heads).v[p];
    if (head == END_OF_LIST) return;
    open_pruning(p);
    Words words = Words(map.list_ranges);
    uvec2 links = unpackUint2x32(words.v[3u * (head - 1u) + 2u]);
    uint second = links.y;
    uvec2 links2 = second != END_OF_LIST ? unpackUint2x32(words.v[3u * (second - 1u) + 2u])
                                         : uvec2(0u);
    if (second == END_OF_LIST || links2.y == END_OF_LIST) {
        store_short(p, head, second, links, links2);
        return;
    }
    uint n = load_ranges(head);
    if (n <= SHORT_SORT) {
        sort_and_store(p, n);
        return;
    }
    uint index = atomicAdd(scratch.head.count, 1u);
    // Groups of 64, in the dispatch the collection started at 0 x 1 x 1 groups (not the
    // long-pixel list's own: the generation's pairing uses that one).
    UintArray dispatch = UintArray(map.tiles);
    uint group = index / 64u;
    if (index % 64u == 0u && group < LONG_SORT_ROW) atomicAdd(dispatch.v[DISPATCH_SORT_LONG], 1u);
    if (index % (64u * LONG_SORT_ROW) == 0u && index != 0u) {
        atomicAdd(dispatch.v[DISPATCH_SORT_LONG + 1u], 1u);
    }
    scratch.v[index] = p;
}
