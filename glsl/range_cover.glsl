// Pruning's general rule (docs/src/pruning.md, "Covered ranges"): a range r of triangle A is
// left out when at every time of its closed interval [t_s, t_e] two covers of distinct
// triangles, neither A, are nearer to the light than r by the margin. A cover is another
// range of the texel (one the static rule kept) or the texel's static-layer triangle S. Then
// at any time the nearest occluder and the nearest of another triangle are both kept and
// both nearer than r, so whatever the receiver's own triangle, one of them shadows wherever r
// would: no lookup changes, with either receiver test. Included by range_sort_lists.glsl,
// which declares the arrays, and used by range_sort.comp's short lists without them; both
// only where the pipeline is specialized with COVER_RULE (opt-in: docs/src/pruning.md).

// The texel's static-layer triangle as a cover (open_pruning sets it).
bool static_cover = false;
float static_cover_depth = 0.0;
uint static_cover_id = NO_TRIANGLE;

// PRUNE_BUDGET (generated from src/technique/gpu_constants.rs): the most steps of the cover
// sweep one texel may take (each a candidate visited or a step closed). The sweep is one flat
// loop, so a CPU device's vector of texels runs it at most this many times: with the sort's own
// loops, far below lavapipe's 65,535 loop iterations per invocation, past which it silently
// leaves every loop (the writes after it included). A texel that runs out keeps the ranges it
// has not decided (keeping is always sound).

// A range's depth at time `at` in its interval (its ends as stored; a zero-length range has
// d_s, as the lookups take it). `precise`: the CPU model in the tests rounds the same.
float cover_depth_at(vec2 t, vec2 d, float at) {
    // (Equal ends: the interpolation below gives d.x exactly; S and level plates skip it.)
    if (at <= t.x || d.x == d.y) return d.x;
    if (at >= t.y) return d.y;
    precise float s = (at - t.x) / (t.y - t.x);
    precise float v = d.x + (d.y - d.x) * s;
    return v;
}

// How much nearer than r (times rt, depths rd) at `at` the cover q is.
float cover_gap(vec2 qt, vec2 qd, vec2 rt, vec2 rd, float at) {
    precise float gap = cover_depth_at(rt, rd, at) - cover_depth_at(qt, qd, at);
    return gap;
}

// The margin of a pair: PRUNE_MARGIN relative to the larger depth of the two (a lookup's
// rounding of either interpolation is a few ulps of it; the margin is about 80), so no lookup
// can find r nearer than q where the sort found q nearer.
float cover_margin(vec2 rd, vec2 qd) {
    precise float m = PRUNE_MARGIN * max(max(max(abs(rd.x), abs(rd.y)),
                                             max(abs(qd.x), abs(qd.y))), 1.0);
    return m;
}

// Whether q may be a cover of r at tau (cheap: no division): it holds at tau and its nearer
// end is nearer than r's depth there by half the margin. Its interpolated depth is never
// below that end by more than an ulp or two, so no cover fails this.
bool may_cover(vec2 qt, vec2 qd, vec2 rd, float tau, float r_at_tau) {
    precise float half_below = r_at_tau - 0.5 * cover_margin(rd, qd);
    return qt.x <= tau && tau <= qt.y && min(qd.x, qd.y) < half_below;
}

// How long from tau the cover q (times qt, depths qd) stays nearer than r by the margin:
// the latest time checked, up to the earlier of their ends; -1 where q is not a cover at tau.
// `r_at_tau` is r's depth at tau (the same for every candidate of a step). Both depths are
// linear there, so the gap checked at tau and at the reach holds between.
float cover_reach(vec2 qt, vec2 qd, vec2 rt, vec2 rd, float tau, float r_at_tau) {
    if (!may_cover(qt, qd, rd, tau, r_at_tau)) return -1.0;
    float m = cover_margin(rd, qd);
    precise float gap = r_at_tau - cover_depth_at(qt, qd, tau);
    if (!(gap > m)) return -1.0;
    float e = min(qt.y, rt.y);
    float gap_e = cover_gap(qt, qd, rt, rd, e);
    if (gap_e > m) return e;
    // The gap closes before e: reach to where it is 2m on the line through the pair's common
    // start lo and e (a time fixed per pair, so the sweep's steps are finitely many), if the
    // gap checked there exceeds m.
    float lo = max(qt.x, rt.x);
    precise float g0 = cover_gap(qt, qd, rt, rd, lo) - 2.0 * m;
    precise float g1 = gap_e - 2.0 * m;
    if (!(g0 > 0.0)) return tau;
    precise float x = lo + g0 / (g0 - g1) * (e - lo);
    if (!(x > tau)) return tau;
    return cover_gap(qt, qd, rt, rd, x) > m ? x : tau;
}

// The static layer's triangle as a cover of r from tau (always active).
bool static_may_cover(vec2 rd, float tau, float r_at_tau) {
    return static_cover && may_cover(vec2(0.0, 1.0), vec2(static_cover_depth), rd, tau, r_at_tau);
}

float static_reach(vec2 rt, vec2 rd, float tau, float r_at_tau) {
    if (!static_cover) return -1.0;
    return cover_reach(vec2(0.0, 1.0), vec2(static_cover_depth), rt, rd, tau, r_at_tau);
}

// The two best reaches of distinct triangles at one step: `best` of triangle `best_id`,
// `second` the best of any other (-1: none).
struct CoverStep {
    float best;
    float second;
    uint best_id;
};

CoverStep no_cover() {
    return CoverStep(-1.0, -1.0, NO_TRIANGLE);
}

void take_cover(inout CoverStep s, float reach, uint id) {
    if (reach < 0.0) return;
    if (id == s.best_id) {
        s.best = max(s.best, reach);
    } else if (reach > s.best) {
        s.second = s.best;
        s.best = reach;
        s.best_id = id;
    } else {
        s.second = max(s.second, reach);
    }
}

// A texel of two ranges (kept by the static rule): is r (times rt, depths rd, triangle rid)
// covered by the other, q, and S together? What the sweep answers there: with two candidates
// it drops r only if both reach r's end from its start (a later step finds the same reaches).
bool covered_by_pair(uvec2 rt_bits, uvec2 rd_bits, uint rid, uvec2 qt_bits, uvec2 qd_bits,
                     uint qid) {
    if (!static_cover || qid == rid) return false;
    vec2 rt = uintBitsToFloat(rt_bits), rd = uintBitsToFloat(rd_bits);
    if (static_reach(rt, rd, rt.x, rd.x) < rt.y) return false;
    return cover_reach(uintBitsToFloat(qt_bits), uintBitsToFloat(qd_bits), rt, rd, rt.x, rd.x)
           >= rt.y;
}
