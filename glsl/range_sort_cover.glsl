// The cover sweep over a texel's sorted ranges (range_cover.glsl's rule), for
// range_sort_lists.glsl's arrays: marks in `dropped` the ranges covered all along.
//
// For each range r in turn, from tau = r's start: every candidate active at tau (another
// triangle's range starting by tau: the sorted order stops the scan at the first that starts
// later; and S) reaches as far as it stays nearer than r by the margin; tau moves to the
// second-best reach of distinct triangles (two covers hold up to there), until it reaches
// r's end (dropped) or stops moving (kept). The decisions are taken on all the ranges at
// once (a dropped range may cover another): the proof needs only that the nearest two
// triangles at each time are never dropped.
//
// One flat loop (each iteration visits a candidate or closes a step), so that a vector of
// texels runs at most PRUNE_BUDGET iterations whatever their lists.

uint dropped[(SORT_CAPACITY + 31u) / 32u];

bool is_dropped(uint i) {
    return (dropped[i >> 5u] & (1u << (i & 31u))) != 0u;
}

// How many of the n sorted ranges are kept.
uint drop_covered(uint n) {
    for (uint w = 0u; w < (n + 31u) / 32u; ++w) dropped[w] = 0u;
    // Two covers of triangles other than r's: at least two other candidates.
    if (n + (static_cover ? 1u : 0u) < 3u) return n;
    uint kept = n;
    uint i = 0u, j = 0u;
    vec2 rt = uintBitsToFloat(times[0]), rd = uintBitsToFloat(depths[0]);
    float tau = rt.x;
    CoverStep s = no_cover();
    take_cover(s, static_reach(rt, rd, tau), static_cover_id);
    for (uint spent = 0u; i < n && spent < PRUNE_BUDGET; ++spent) {
        vec2 qt = uintBitsToFloat(times[j < n ? j : 0u]);
        if (j < n && qt.x <= tau) {
            if (ids[j] != ids[i]) {
                take_cover(s, cover_reach(qt, uintBitsToFloat(depths[j]), rt, rd, tau), ids[j]);
            }
            ++j;
            continue;
        }
        // The step is closed: two covers hold from tau to s.second.
        if (s.second >= rt.y) {
            dropped[i >> 5u] |= 1u << (i & 31u);
            --kept;
        }
        if (s.second >= rt.y || !(s.second > tau)) {
            ++i;
            if (i == n) break;
            rt = uintBitsToFloat(times[i]);
            rd = uintBitsToFloat(depths[i]);
            tau = rt.x;
        } else {
            tau = s.second;
        }
        j = 0u;
        s = no_cover();
        take_cover(s, static_reach(rt, rd, tau), static_cover_id);
    }
    return kept;
}
