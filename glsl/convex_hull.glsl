// The convex hull of a footprint's points (Andrew's monotone chain), counter-clockwise, for
// the geometry shaders that rasterize a moving triangle's footprint (the collection's exact
// construction and the lighting pass). The includer defines HULL_MAX_POINTS.
//
// Why it is more than the textbook chain: a triangle that does not move, or moves only along
// the view direction, hands over its corners twice, at t = 0 and t = 1, as equal or nearly
// equal points. A compiler that fuses one product of a turn test into a multiply-add (NVIDIA
// does) gives a duplicate a turn of a few ulps of either sign instead of zero, so the chain
// keeps it; a zero-length edge then normalises to NaN, and a near-zero one to a direction
// made of rounding noise, and growing the hull along such an edge's normal pulled the
// footprint inward or dropped the whole triangle (on an H200: every texel of a square sinking
// straight down, 116 texels of a tessellated lid). So the turn test is `precise`, and points
// closer than `merge` to a point already kept are dropped before the chain: the hull then
// misses at most `merge` of the footprint in any direction, which the caller adds to its
// growth, and every edge it has is long enough for its normal to mean something.

// What a fused multiply-add would add to a turn: nothing here. The hull's test shader
// (tests/glsl/hull_probe.comp) defines it as the rounding error of the first product, to run
// the chain as a fusing compiler would (lavapipe never fuses).
#ifndef HULL_FUSED_RESIDUAL
#define HULL_FUSED_RESIDUAL(x, y) 0.0
#endif

// The turn of o -> a -> b: positive counter-clockwise.
precise float hull_turn(vec2 o, vec2 a, vec2 b) {
    precise float r = (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x) +
                      HULL_FUSED_RESIDUAL(a.x - o.x, b.y - o.y);
    return r;
}

// How close two points may lie before one stands for both: a 256th of a texel or pixel, or
// a few float ulps of the largest coordinate where that is coarser.
float hull_merge_distance(vec2 p[HULL_MAX_POINTS], int n) {
    float largest = 0.0;
    for (int i = 0; i < n; ++i) largest = max(largest, max(abs(p[i].x), abs(p[i].y)));
    return max(1.0 / 256.0, largest * 5e-7);
}

// Sorts p[0..n) by x, then y, and keeps only points farther than `merge` (in x or in y) from
// every point kept before them; returns how many are kept, at the front of p.
int hull_sorted_distinct(inout vec2 p[HULL_MAX_POINTS], int n, float merge) {
    for (int i = 1; i < n; ++i) {
        vec2 key = p[i];
        int j = i - 1;
        while (j >= 0 && (p[j].x > key.x || (p[j].x == key.x && p[j].y > key.y))) {
            p[j + 1] = p[j];
            --j;
        }
        p[j + 1] = key;
    }
    int kept = 0;
    for (int i = 0; i < n; ++i) {
        bool near = false;
        for (int k = 0; k < kept; ++k) {
            vec2 gap = abs(p[i] - p[k]);
            near = near || (gap.x <= merge && gap.y <= merge);
        }
        if (!near) p[kept++] = p[i];
    }
    return kept;
}

// The hull of p[0..n) (reordered), its vertices counter-clockwise in hull[0..h); returns h:
// 1 where every point merged into one, 2 for a segment. `merge` as for hull_sorted_distinct.
int convex_hull(inout vec2 p[HULL_MAX_POINTS], int n, float merge,
                out vec2 hull[2 * HULL_MAX_POINTS]) {
    n = hull_sorted_distinct(p, n, merge);
    int k = 0;
    for (int i = 0; i < n; ++i) {
        while (k >= 2 && hull_turn(hull[k - 2], hull[k - 1], p[i]) <= 0.0) --k;
        hull[k++] = p[i];
    }
    int lower = k + 1;
    for (int i = n - 2; i >= 0; --i) {
        while (k >= lower && hull_turn(hull[k - 2], hull[k - 1], p[i]) <= 0.0) --k;
        hull[k++] = p[i];
    }
    return max(k - 1, 1);  // the chain ends where it started; one point: just it
}

// The hull grown by `by`: it holds every point within `by` of the hull. Each edge moves out by
// `by`; at a corner the moved edges meet (the miter), except at a sharp corner, whose
// miter would reach far out: there two corners, `by` past the corner along each edge, at
// `by` out from it (the bevel between them stays `by` from the corner for any angle under
// 90 degrees). Returns the grown polygon's size, at most twice the hull's.
int hull_grow(inout vec2 hull[2 * HULL_MAX_POINTS], int h, float by) {
    vec2 grown[2 * HULL_MAX_POINTS];
    int g = 0;
    for (int i = 0; i < h; ++i) {
        vec2 prev = hull[(i + h - 1) % h], here = hull[i], next = hull[(i + 1) % h];
        vec2 e1 = normalize(here - prev), e2 = normalize(next - here);
        vec2 n1 = vec2(e1.y, -e1.x), n2 = vec2(e2.y, -e2.x);
        float meet = 1.0 + dot(n1, n2);
        if (meet >= 0.125) {
            grown[g++] = here + by * (n1 + n2) / meet;
        } else {
            grown[g++] = here + by * (n1 + e1);
            grown[g++] = here + by * (n2 - e2);
        }
    }
    for (int i = 0; i < g; ++i) hull[i] = grown[i];
    return g;
}
