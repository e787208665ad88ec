// The times at which a moving triangle's plane passes through a perspective light's
// position (exact_prism.glsl's third kind of cut, after the edges passing the texel centre).
//
// Why: with the corners' clip (x, y, w) as columns v_k, the exact test's w-sum is
// sum_k e_k w_k = det(v_0, v_1, v_2) for every texel (Cramer: sum_k e_k v_k = det(V) r with
// r = (X, Y, 1) the texel's ray), so the "hit in front of the light" test flips exactly
// where det(V(t)) changes sign: where the plane passes through the light. While the
// triangle contains the light there, its hit on every texel's ray passes through the light
// from in front to behind (or back) at that instant, which no edge root marks; a piece
// spanning it, tested at its midpoint, would be kept or dropped whole (a straight-edged
// split of the shadow). det(V(t)) is a cubic in t, the same for every texel: its sign
// changes in (0, 1) are found here once per triangle and handed to the fragment shader as
// extra cuts. Only a triangle with some corner at or behind the light at t = 0 or t = 1 can
// contain the light at some time (every point of a triangle all in front stays in front),
// so the others skip this.

// det(v_0(t), v_1(t), v_2(t)) with v_k(t) = p_k + t (q_k - p_k), evaluated as it stands (not
// from the expanded coefficients) so that its sign near a root is as accurate as f32 allows.
float light_crossing_det(vec3 p[3], vec3 q[3], float t) {
    vec3 v0 = mix(p[0], q[0], t), v1 = mix(p[1], q[1], t), v2 = mix(p[2], q[2], t);
    return dot(v0, cross(v1, v2));
}

// The time in [lo, hi] where the determinant changes sign (it does: checked by the caller),
// negative before it iff `lo_negative` (given, as the determinant may be exactly 0 at lo).
float light_crossing_bisect(vec3 p[3], vec3 q[3], float lo, float hi, bool lo_negative) {
    for (int i = 0; i < 40 && hi - lo > 0.0; ++i) {
        float mid = 0.5 * (lo + hi);
        if (mid <= lo || mid >= hi) break;
        if ((light_crossing_det(p, q, mid) < 0.0) == lo_negative) lo = mid; else hi = mid;
    }
    return 0.5 * (lo + hi);
}

// The sign changes of det(V(t)) in (0, 1), ascending, unused slots EXACT_NO_ROOT. The cubic
// is monotone between its critical points (the roots of its derivative in (0, 1)), so each
// of the at most three monotone stretches holds at most one sign change, found by bisection.
vec3 light_crossing_times(vec3 p[3], vec3 q[3]) {
    vec3 d[3] = vec3[3](q[0] - p[0], q[1] - p[1], q[2] - p[2]);
    // det(p + t d) = c0 + c1 t + c2 t^2 + c3 t^3; the derivative is c1 + 2 c2 t + 3 c3 t^2.
    float c1 = dot(d[0], cross(p[1], p[2])) + dot(p[0], cross(d[1], p[2])) +
               dot(p[0], cross(p[1], d[2]));
    float c2 = dot(p[0], cross(d[1], d[2])) + dot(d[0], cross(p[1], d[2])) +
               dot(d[0], cross(d[1], p[2]));
    float c3 = dot(d[0], cross(d[1], d[2]));
    vec2 critical = exact_roots01(3.0 * c3, 2.0 * c2, c1);
    float bounds[4] = float[4](0.0, min(critical.x, critical.y), max(critical.x, critical.y), 1.0);
    vec3 cuts = vec3(EXACT_NO_ROOT);
    int n = 0;
    float lo = 0.0;
    float at_lo = light_crossing_det(p, q, 0.0);
    for (int i = 1; i < 4; ++i) {
        float hi = min(bounds[i], 1.0);
        if (hi <= lo) continue;
        float at_hi = light_crossing_det(p, q, hi);
        if ((at_lo < 0.0 && at_hi > 0.0) || (at_lo > 0.0 && at_hi < 0.0)) {
            cuts[n++] = light_crossing_bisect(p, q, lo, hi, at_lo < 0.0);
        }
        // A zero at a stretch's end carries the sign from before it, so a sign change
        // through an exact zero is still seen (and one touching zero is not).
        if (at_hi != 0.0) at_lo = at_hi;
        lo = hi;
    }
    return cuts;
}
