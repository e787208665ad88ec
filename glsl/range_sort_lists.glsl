// Sorting the collected ranges (range_sort_common.glsl): the sort itself, shared by
// range_sort.comp (lists of up to SHORT_SORT ranges, nearly all) and range_sort_long.comp (the
// rest, up to MAX_LIST_NODES / 2): a texel's list is copied into private arrays, without the
// ranges behind the static layer (pruned, see below), Shell-sorted by (t_s, t_e, d_s, d_e,
// id), a total order on what a range holds, so the order does not depend on the order the
// collection's atomics ran in, and written to the texel's place; with the cover rule, without
// the ranges that nearer ones of two other triangles cover all along (range_cover.glsl).
// The includer defines SORT_CAPACITY.
#include "range_sort_common.glsl"
#include "range_cover.glsl"

// The cover rule (technique::Pruning::Cover). A specialization constant, not a push constant:
// the static rule's pipelines (the default) fold it away, arrays and sweep included, and cost
// what the sort cost before the cover rule existed.
layout(constant_id = 0) const bool COVER_RULE = false;
// The coverage map's rule in one pass (technique::Pruning::Coverage, docs/src/pruning.md):
// where one range holds the texel all frame, nearer than every other range at every time,
// only that range is kept. Not with COVER_RULE.
layout(constant_id = 1) const bool COVERAGE_RULE = false;

uvec2 times[SORT_CAPACITY];
uvec2 depths[SORT_CAPACITY];
uint ids[SORT_CAPACITY];

#include "range_sort_cover.glsl"

// Pruning (docs/src/pruning.md): a range farther from the light than the texel's nearest
// static triangle S all along its interval never decides a test when receivers are tested at
// their plane's depth (the light's bias.w): a receiver S does not shadow is either at most
// S's depth (then the range is behind it too) or on S itself (then its plane's depth at the
// centre is S's, less the depth bias). The margin covers the rounding of a lookup's
// interpolated depth and of the plane's depth against the stored one.
float prune_beyond = uintBitsToFloat(0x7f800000u);     // +inf: keep every range

// (The static triangle is also a cover for the cover rule, with either receiver test; without
// that rule the offset test reads no static layer here.)
void open_pruning(uint p) {
    prune_beyond = uintBitsToFloat(0x7f800000u);
    static_cover = false;
    bool plane_test = map.light.bias.w > 0.5;
    if (map.static_nearest == 0UL || !(plane_test || COVER_RULE)) return;
    uint64_t nearest = MsUint64s(map.static_nearest).v[p];
    uint id = uint(nearest & 0xffffffffUL);
    if (id == NO_TRIANGLE) return;
    float d = ms_static_depth(uint(nearest >> 32));
    static_cover = COVER_RULE;
    static_cover_id = id;
    static_cover_depth = d;
    if (plane_test) prune_beyond = d + PRUNE_MARGIN * max(abs(d), 1.0);
}

// Is a range whose depths at its ends are `depths` pruned?
bool pruned(uvec2 depths) {
    vec2 d = uintBitsToFloat(depths);
    return min(d.x, d.y) > prune_beyond;
}

// Does local range a sort after local range b?
bool sorts_after(uvec2 ta, uvec2 da, uint ia, uvec2 tb, uvec2 db, uint ib) {
    vec2 a = uintBitsToFloat(ta), b = uintBitsToFloat(tb);
    if (a.x != b.x) return a.x > b.x;
    if (a.y != b.y) return a.y > b.y;
    vec2 c = uintBitsToFloat(da), d = uintBitsToFloat(db);
    if (c.x != d.x) return c.x > d.x;
    if (c.y != d.y) return c.y > d.y;
    return ia > ib;
}

// Copies the ranges of the list starting at `head` that are not pruned into the arrays:
// how many, or SORT_CAPACITY + 1 if the list goes on past a full array (open_pruning
// first).
uint load_ranges(uint head) {
    Words words = Words(map.list_ranges);
    uint n = 0u;
    uint r = head;
    while (r != END_OF_LIST && n < SORT_CAPACITY) {
        uint at = 3u * (r - 1u);
        uvec2 d = unpackUint2x32(words.v[at + 1u]);
        uvec2 links = unpackUint2x32(words.v[at + 2u]);
        if (!pruned(d)) {
            times[n] = unpackUint2x32(words.v[at]);
            depths[n] = d;
            ids[n] = links.x;
            ++n;
        }
        r = links.y;
    }
    // A list not finished with the array full is the next tier's (which prunes it again),
    // whether or not what is left would be pruned: reading it here would walk it twice.
    return r == END_OF_LIST ? n : SORT_CAPACITY + 1u;
}

// Is range b farther than range a, which holds all frame, at both ends of b's interval (so,
// both depths being linear in time, all along it) by the pruning margin?
bool behind_all_along(uvec2 da, uvec2 tb, uvec2 db) {
    vec2 a = uintBitsToFloat(da), t = uintBitsToFloat(tb), b = uintBitsToFloat(db);
    // Spelled out and `precise`: the CPU model (tests/gpu/pruning_model.rs) repeats it.
    precise vec2 front = a.x + t * (a.y - a.x);
    precise vec2 reach = front + PRUNE_MARGIN * max(abs(front), vec2(1.0));
    return all(greaterThan(b, reach));
}

// Does range (t, d) hold the texel all frame? (Where the static layer's triangle is nearer,
// it shadows whatever lies behind it first: the ranges behind the cover decide no more.)
bool covers_all_frame(uvec2 t) {
    return uintBitsToFloat(t) == vec2(0.0, 1.0);
}

// The coverage rule on the n sorted ranges: the one that covers the texel all frame nearer
// than all the others, moved first, and 1; or n.
uint keep_covering_range(uint n) {
    for (uint i = 0u; i < n; ++i) {
        if (uintBitsToFloat(times[i].x) != 0.0) break;   // sorted by start time
        if (!covers_all_frame(times[i])) continue;
        bool nearest = true;
        for (uint j = 0u; j < n && nearest; ++j) {
            nearest = j == i || behind_all_along(depths[i], times[j], depths[j]);
        }
        if (nearest) {
            times[0] = times[i];
            depths[0] = depths[i];
            ids[0] = ids[i];
            return 1u;
        }
    }
    return n;
}

// Takes n places in the range buffer (one atomic on the places taken so far: the buffer
// ends up exactly full), the first of them.
uint take_places(uint n) {
    return atomicAdd(CounterRef(map.counters).c.sorted_count, n);
}

// Sorts the n ranges loaded for texel p and writes them (with the cover rule, those it keeps)
// to places it takes, each linked to the next.
void sort_and_store(uint p, uint n) {
    const uint gaps[5] = uint[5](57u, 23u, 10u, 4u, 1u);
    for (int g = 0; g < 5; ++g) {
        uint gap = gaps[g];
        for (uint i = gap; i < n; ++i) {
            uvec2 t = times[i], d = depths[i];
            uint id = ids[i];
            uint j = i;
            while (j >= gap && sorts_after(times[j - gap], depths[j - gap], ids[j - gap], t, d, id)) {
                times[j] = times[j - gap];
                depths[j] = depths[j - gap];
                ids[j] = ids[j - gap];
                j -= gap;
            }
            times[j] = t;
            depths[j] = d;
            ids[j] = id;
        }
    }
    if (COVERAGE_RULE) n = keep_covering_range(n);
    uint kept = COVER_RULE ? drop_covered(n) : n;
    UintArray heads = UintArray(map.range_heads);
    if (kept == 0u) {
        heads.v[p] = END_OF_LIST;
        return;
    }
    uint base = take_places(kept);
    // Past the capacity the frame overflowed (the counters say so, and it is recorded again
    // with room): nothing is written out of bounds.
    if (base + kept > CounterRef(map.counters).c.range_capacity) {
        heads.v[p] = END_OF_LIST;
        return;
    }
    Words out_words = Words(map.ranges);
    uint k = 0u;
    for (uint i = 0u; i < n; ++i) {
        if (COVER_RULE && kept < n && is_dropped(i)) continue;
        uint at = 3u * (base + k);
        out_words.v[at] = packUint2x32(times[i]);
        out_words.v[at + 1u] = packUint2x32(depths[i]);
        ++k;
        out_words.v[at + 2u] = packUint2x32(uvec2(ids[i], k < kept ? base + k + 1u : END_OF_LIST));
    }
    heads.v[p] = base + 1u;
}
