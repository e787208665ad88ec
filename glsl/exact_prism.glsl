// The exact prism (our construction, `PrismConstruction::Exact`): per shadow-map texel, the
// time intervals during which a moving triangle covers the texel's centre, solved in closed
// form instead of rasterizing the papers' triangulated side surfaces.
//
// Why: a prism side is the bilinear surface swept by an edge, and the papers' four triangles
// around its centre give the right times only while the edge translates. Under rotation or
// any non-rigid vertex motion the stored times are off over most of the texels, an edge that
// sweeps over a texel and back leaves no fragment, and a static edge's sliver fans split a
// static triangle's [0, 1] into [0, tau] and [1 - tau, 1] (light leaks on silhouettes).
//
// The math. Let (X, Y) be the texel centre in NDC. A point with clip coordinates (x, y, w)
// lies on the texel's ray iff u = (x - X w, y - Y w) = 0 and w > 0. Vertex k of the triangle
// moves linearly, so u_k(t) = a_k + t d_k is linear in t. The centre is inside the triangle
// at time t iff the origin is inside the 2D triangle u_0 u_1 u_2: its barycentric weights are
// e_k / (e_0 + e_1 + e_2) with e_k = cross(u_{k+1}, u_{k+2}), each a quadratic in t. Coverage
// changes only where some e_k crosses zero (an edge passes over the centre), so the roots of
// the three quadratics in (0, 1) cut the shutter into pieces of constant coverage; each piece
// is tested at its midpoint. So do the times the triangle's plane passes through a spot
// light's position, where the "in front of the light" test flips with no edge passing the
// centre (light_crossing.glsl, found once per triangle by the geometry shader). The result
// is a list of disjoint covered runs [t_a, t_b], each emitted as two nodes (time, depth),
// which the generation pass pairs in time order as usual.
//
// Watertight by construction: two triangles sharing an edge compute its e from the same
// vertex data with the operands swapped, and `precise` keeps the compiler from fusing the
// products differently, so both get exactly opposite coefficients and identical roots. Every
// triangle, static or moving, goes through this same arithmetic (the rasterizer only picks
// which texels to visit, through a slightly dilated footprint), so static and moving
// neighbours agree on the texels near their shared edges.

// Corner k of the triangle as the fragment shader receives it: clip x, y, w and the linear
// depth along the light's view axis, at t = 0 and at t = 1.
struct ExactCorner {
    vec4 at0;
    vec4 at1;
};

// At most 6 edge roots and 3 light crossings (light_crossing.glsl) cut [0, 1] into 10
// pieces, so at most EXACT_MAX_RUNS = 5 covered runs: 10 nodes. The bound is generated from
// src/technique/gpu_constants.rs, where the host's room for the ranges is sized by it too.
#include "gpu_constants.glsl"

// The covered runs of a texel: run i from start[i] to end[i] (covered throughout), `inner`
// a time inside it (where the triangle is not seen edge-on, for the depths at its ends).
struct ExactRuns {
    int count;
    float start[EXACT_MAX_RUNS];
    float end[EXACT_MAX_RUNS];
    float inner[EXACT_MAX_RUNS];
};

precise float exact_cross(vec2 p, vec2 q) {
    precise float r = p.x * q.y - p.y * q.x;
    return r;
}

// A root slot with nothing in it: sorts after every root in (0, 1).
const float EXACT_NO_ROOT = 2.0;

// The roots of c + b t + a t^2 in the open interval (0, 1), or EXACT_NO_ROOT.
vec2 exact_roots01(float a, float b, float c) {
    vec2 roots = vec2(EXACT_NO_ROOT);
    if (a == 0.0) {
        float r = b != 0.0 ? -c / b : EXACT_NO_ROOT;
        roots.x = r > 0.0 && r < 1.0 ? r : EXACT_NO_ROOT;
        return roots;
    }
    float disc = b * b - 4.0 * a * c;
    if (disc < 0.0) return roots;
    // The stable form: no cancellation between b and the square root.
    float q = -0.5 * (b + (b >= 0.0 ? sqrt(disc) : -sqrt(disc)));
    float r0 = q / a;
    if (r0 > 0.0 && r0 < 1.0) roots.x = r0;
    if (q != 0.0) {
        float r1 = c / q;
        if (r1 > 0.0 && r1 < 1.0 && r1 != r0) roots.y = r1;
    }
    return roots;
}

#define EXACT_SWAP(i, j) { float lo = min(r[i], r[j]); r[j] = max(r[i], r[j]); r[i] = lo; }
// Sorts the first six values in place with a fixed network of compare-exchanges: no
// indexing by run-time values (which a CPU device turns into per-lane gathers).
void exact_sort6(inout float r[9]) {
    EXACT_SWAP(1, 2) EXACT_SWAP(4, 5) EXACT_SWAP(0, 2) EXACT_SWAP(3, 5)
    EXACT_SWAP(0, 1) EXACT_SWAP(3, 4) EXACT_SWAP(1, 4) EXACT_SWAP(0, 3)
    EXACT_SWAP(2, 5) EXACT_SWAP(1, 3) EXACT_SWAP(2, 4) EXACT_SWAP(2, 3)
}

// Merges the ascending r[6..8] into the sorted r[0..5] (insertion, fixed indices).
void exact_merge3(inout float r[9]) {
    EXACT_SWAP(5, 6) EXACT_SWAP(4, 5) EXACT_SWAP(3, 4) EXACT_SWAP(2, 3) EXACT_SWAP(1, 2)
    EXACT_SWAP(0, 1)
    EXACT_SWAP(6, 7) EXACT_SWAP(5, 6) EXACT_SWAP(4, 5) EXACT_SWAP(3, 4) EXACT_SWAP(2, 3)
    EXACT_SWAP(1, 2)
    EXACT_SWAP(7, 8) EXACT_SWAP(6, 7) EXACT_SWAP(5, 6) EXACT_SWAP(4, 5) EXACT_SWAP(3, 4)
    EXACT_SWAP(2, 3)
}
#undef EXACT_SWAP

struct ExactState {
    vec3 e;       // e_k: the (unnormalised) barycentric weight of corner k
    vec3 side;    // the sign of e_k, a zero one replaced by the tie-break's sign
    float w;      // sum of e_k w_k: has the sign of sum(e) iff the hit is in front of the light
    float depth;  // sum of e_k depth_k
};

// The sign e = cross(u_i, u_j) takes when the texel centre moves off the edge's line by an
// infinitesimal step (epsilon, epsilon^2) in NDC: u_k moves by -w_k times the step, so e moves by
// cross(step, g) with g = w_j u_i - w_i u_j. The two triangles sharing an edge get opposite g,
// so a centre exactly on their edge belongs to exactly one of them (the rasterizer's top-left
// rule plays the same part for the papers' construction).
float exact_tie_sign(vec2 ui, float wi, vec2 uj, float wj) {
    vec2 g = wj * ui - wi * uj;
    return g.y != 0.0 ? sign(g.y) : -sign(g.x);
}

ExactState exact_state_at(vec2 a[3], vec2 d[3], ExactCorner c[3], float t) {
    vec2 u[3];
    float w[3];
    for (int k = 0; k < 3; ++k) {
        precise vec2 uk = a[k] + t * d[k];
        u[k] = uk;
        w[k] = c[k].at0.z + t * (c[k].at1.z - c[k].at0.z);
    }
    ExactState s;
    s.e = vec3(exact_cross(u[1], u[2]), exact_cross(u[2], u[0]), exact_cross(u[0], u[1]));
    s.w = 0.0;
    s.depth = 0.0;
    for (int k = 0; k < 3; ++k) {
        int i = (k + 1) % 3, j = (k + 2) % 3;
        s.side[k] = s.e[k] != 0.0 ? sign(s.e[k]) : exact_tie_sign(u[i], w[i], u[j], w[j]);
        float depth = c[k].at0.w + t * (c[k].at1.w - c[k].at0.w);
        s.w += s.e[k] * w[k];
        s.depth += s.e[k] * depth;
    }
    return s;
}

bool exact_covered(ExactState s) {
    float area = s.e.x + s.e.y + s.e.z;
    bool inside = s.side.x == s.side.y && s.side.y == s.side.z && s.side.x != 0.0;
    return inside && area != 0.0 && (area > 0.0 ? s.w > 0.0 : s.w < 0.0);
}

// Depth of the triangle along the texel's ray at a run's end, from the state there, or
// from the state at a time inside the run where the triangle is seen edge-on at the end.
float exact_depth_at(ExactState at_end, ExactState inside) {
    float area = at_end.e.x + at_end.e.y + at_end.e.z;
    if (abs(area) <= 1e-6 * (abs(at_end.e.x) + abs(at_end.e.y) + abs(at_end.e.z))) {
        return inside.depth / (inside.e.x + inside.e.y + inside.e.z);
    }
    return at_end.depth / area;
}

// The covered runs of the texel whose centre is `ndc`; `cuts` are the times the triangle's
// plane passes through the light (light_crossing.glsl), ascending, EXACT_NO_ROOT unused.
ExactRuns exact_prism_runs(ExactCorner c[3], vec2 ndc, vec3 cuts, out vec2 a[3],
                           out vec2 d[3]) {
    bool moving = false;
    for (int k = 0; k < 3; ++k) {
        precise vec2 u0 = c[k].at0.xy - ndc * c[k].at0.z;
        precise vec2 u1 = c[k].at1.xy - ndc * c[k].at1.z;
        a[k] = u0;
        precise vec2 dk = u1 - u0;
        d[k] = dk;
        moving = moving || c[k].at0 != c[k].at1;
    }
    // A triangle that does not move has no roots: one piece, tested at t = 0.5 (d is zero,
    // so u = a exactly), [0, 1] or nothing.
    float roots[9];
    roots[6] = cuts.x;
    roots[7] = cuts.y;
    roots[8] = cuts.z;
    for (int k = 0; k < 3; ++k) {
        int i = (k + 1) % 3, j = (k + 2) % 3;
        precise float qa = exact_cross(d[i], d[j]);
        precise float qb = exact_cross(a[i], d[j]) + exact_cross(d[i], a[j]);
        precise float qc = exact_cross(a[i], a[j]);
        vec2 r = moving ? exact_roots01(qa, qb, qc) : vec2(EXACT_NO_ROOT);
        roots[2 * k] = r.x;
        roots[2 * k + 1] = r.y;
    }
    exact_sort6(roots);
    // The same for every fragment of the triangle: most never take this.
    if (cuts.x < EXACT_NO_ROOT) exact_merge3(roots);
    int n = 0;
    for (int k = 0; k < 9; ++k) n += roots[k] < EXACT_NO_ROOT ? 1 : 0;

    ExactRuns runs;
    runs.count = 0;
    float run_start = -1.0;
    for (int piece = 0; piece <= n; ++piece) {
        float from = piece == 0 ? 0.0 : roots[piece - 1];
        float to = piece == n ? 1.0 : roots[piece];
        if (to <= from) continue;
        bool covered = exact_covered(exact_state_at(a, d, c, 0.5 * (from + to)));
        if (covered && run_start < 0.0) run_start = from;
        if (run_start >= 0.0 && (!covered || piece == n)) {
            float end = covered ? to : from;
            runs.start[runs.count] = run_start;
            runs.end[runs.count] = end;
            runs.inner[runs.count] = 0.5 * (run_start + end);
            ++runs.count;
            run_start = -1.0;
        }
    }
    return runs;
}

// The two nodes of run i (its start and end): their times and depths.
void exact_run_nodes(vec2 a[3], vec2 d[3], ExactCorner c[3], ExactRuns runs, int i,
                     out vec2 times, out vec2 depths) {
    times = vec2(runs.start[i], runs.end[i]);
    ExactState inside = exact_state_at(a, d, c, runs.inner[i]);
    depths = vec2(exact_depth_at(exact_state_at(a, d, c, times.x), inside),
                  exact_depth_at(exact_state_at(a, d, c, times.y), inside));
}

// The surface a node lies on, for the coverage map's nearest map (SURFACE_* of shared.glsl):
// the triangle itself at t = 0 or t = 1, or the instant an edge passes over the texel.
uint exact_surface(float time) {
    return time == 0.0 ? SURFACE_CAP0 : (time == 1.0 ? SURFACE_CAP1 : SURFACE_SIDE);
}
