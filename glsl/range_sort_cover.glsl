// The cover sweep over a texel's sorted ranges (range_cover.glsl's rule), for
// range_sort_lists.glsl's arrays: marks in `dropped` the ranges covered all along.
//
// For each range r in turn (in start order), from tau = r's start: every candidate (another
// triangle's range holding at tau, and S) reaches as far as it stays nearer than r by the
// margin; tau moves to the second-best reach of distinct triangles (two covers hold up to
// there), until it reaches r's end (dropped) or stops moving (kept). The decisions are taken
// on all the ranges at once (a dropped range may cover another): the proof needs only that
// the nearest two triangles at each time are never dropped.
//
// One flat loop (each iteration adds a range to the candidates, visits one, or closes a
// step), so that a vector of texels runs at most PRUNE_BUDGET iterations whatever their
// lists. (Measured on lavapipe, the stacked plates' sort: 3.7 s where a later step scanned
// every range that starts by tau, 3.2 s without the stop at two covers reaching r's end,
// 2.5 s as it is; the sort without the cover rule takes 0.64 s.)

uint dropped[(SORT_CAPACITY + 31u) / 32u];
// The candidates: the ranges that have started by tau, less those that ended before the
// start of a range already swept (in no order). Ranges' starts only grow from one range to
// the next and tau from one step to the next, so a step scans these instead of every range
// that starts by tau, and one that ended before the current range's start is done with.
uint started[SORT_CAPACITY];

bool is_dropped(uint i) {
    return (dropped[i >> 5u] & (1u << (i & 31u))) != 0u;
}

// How many of the n sorted ranges are kept.
uint drop_covered(uint n) {
    // Two covers of triangles other than r's: at least two other candidates. (`dropped` is
    // read only where some range is dropped.)
    if (n + (static_cover ? 1u : 0u) < 3u) return n;
    for (uint w = 0u; w < (n + 31u) / 32u; ++w) dropped[w] = 0u;
    uint kept = n;
    // r = range i (triangle a); j scans `started` (live of them), after `added` ranges are in.
    uint i = 0u, j = 0u, a = ids[0], added = 0u, live = 0u;
    bool adding = true;
    vec2 rt = uintBitsToFloat(times[0]), rd = uintBitsToFloat(depths[0]);
    float tau = rt.x, r_at_tau = rd.x;
    CoverStep s = no_cover();
    take_cover(s, static_reach(rt, rd, tau, r_at_tau), static_cover_id);
    for (uint spent = 0u; i < n && spent < PRUNE_BUDGET; ++spent) {
        if (adding) {
            if (added < n && uintBitsToFloat(times[added].x) <= tau) {
                started[live++] = added++;
                continue;
            }
            adding = false;
        }
        if (j < live) {
            uint q = started[j];
            vec2 qt = uintBitsToFloat(times[q]);
            if (qt.y < rt.x) {
                started[j] = started[--live];   // ended before r's start: out for good
            } else {
                ++j;
                if (ids[q] != a) {
                    float reach = cover_reach(qt, uintBitsToFloat(depths[q]), rt, rd, tau, r_at_tau);
                    take_cover(s, reach, ids[q]);
                    // Two covers reach r's end: dropped, whatever the rest offer.
                    if (s.second >= rt.y) j = live;
                }
            }
            continue;
        }
        // The step is closed: two covers hold from tau to s.second.
        bool drop = s.second >= rt.y;
        if (drop) {
            dropped[i >> 5u] |= 1u << (i & 31u);
            --kept;
        }
        if (drop || !(s.second > tau)) {
            ++i;
            if (i == n) break;
            rt = uintBitsToFloat(times[i]);
            rd = uintBitsToFloat(depths[i]);
            a = ids[i];
            tau = rt.x;
            r_at_tau = rd.x;
        } else {
            tau = s.second;
            r_at_tau = cover_depth_at(rt, rd, tau);
        }
        adding = true;
        j = 0u;
        s = no_cover();
        take_cover(s, static_reach(rt, rd, tau, r_at_tau), static_cover_id);
    }
    return kept;
}
