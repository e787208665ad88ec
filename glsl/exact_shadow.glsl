// The exact shadow test of one receiver against one moving triangle, over a window of the
// shutter, in f32: the building block of the exact lookups (issue 35; docs/src/exact-lookups.md).
// Self-contained (no bindings or buffer references, names prefixed `ms_exact_`); its f64
// original is the ray tracer's app/src/raytrace/shutter.rs, whose structure it follows.
//
// The receiver moves linearly, P(t) = P0 + t (P1 - P0) (still: P0 == P1); the triangle's
// corners too, X(t) = X0 + t (X1 - X0). With every vector relative to P(t) (X' = X(t) - P(t),
// linear in t) and u(t) the shadow ray's direction (spot: L - P(t), linear; directional: the
// unit vector against the light's direction, constant), the ray P(t) + s u(t) meets the
// triangle ABC iff its three edge functions det(A', B', u), det(B', C', u), det(C', A', u)
// share a sign (zeros allowed) and the plane's ray parameter s = det(A', B', C') / E (E their
// sum, E != 0) lies in the light's range of s. Each is a triple product of vectors linear in
// t: a cubic (directional: the edges are quadratics) whose coefficients are sums of
// determinants of the vectors' parts. The test can change only where one of the edges, or
// det(A', B', C') - s0 E at a bound s0 of the range, changes sign; between two such times it
// is asked once, at the midpoint.
//
// At most MS_EXACT_MAX_INTERVALS intervals: 15 sign changes cut the window into 16 pieces, and
// touching shadowed pieces are joined (the book's "The bound of 8").
//
// The one epsilon, MS_EXACT_SELF_EPSILON (docs/src/exact-lookups.md, "The one epsilon"): the
// range of s starts there (ms_exact_s_min), so that a receiver is not shadowed by the surface
// it lies on: its own triangle the caller leaves out, its coplanar neighbours remain, and a
// receiver one f32 rounding off their plane meets them at s ~ 0. Spot: s is the share of the
// segment to the light; directional: u is a unit vector and the epsilon is relative to the
// scene's size the caller hands over. The range ends at s = 1 for a spot light. A receiver
// off the triangle's plane by more than rounding all window long (ms_exact_s_from) starts at
// the ray tracer's epsilon instead, so a caster at its foot shadows it. Nothing else is a
// tolerance: roots are bracketed as narrowly as f32 resolves t, and the certain-sign early
// outs only skip work that would find nothing.
//
// Ties: an edge's function is computed from its two corners in one canonical order and
// negated for the triangle that walks the edge the other way (`precise`), so the two
// triangles sharing an edge see exactly opposite values: one of them takes a ray through it
// (watertight). A triangle edge-on to the ray (E == 0) does not block, as in the tracer.

#ifndef MS_EXACT_SHADOW_GLSL
#define MS_EXACT_SHADOW_GLSL

#define MS_EXACT_MAX_INTERVALS 8
// 3 edges x 3 roots + 2 bounds x 3 roots.
#define MS_EXACT_MAX_EVENTS 15
#define MS_EXACT_SELF_EPSILON 1e-4
// Off a triangle's plane: this share of the epsilon, 1e-7, the ray tracer's SHADOW_EPSILON.
#define MS_EXACT_OFF_PLANE_SHARE 1e-3
// Off the plane: |det(A', B', C')| above this times r^2 (r + m) (r: the corners' reach from
// the receiver, m: its distance from the origin), ~16 f32 roundings of the coordinates.
#define MS_EXACT_OFF_PLANE (64.0 / 16777216.0)
// Roots are bracketed to this width in t (~4 ulps of t near 1).
#define MS_EXACT_ROOT_WIDTH 4.8e-7
// Certain signs (early outs without root finding) are by more than this share of the largest
// possible term (f32 rounding of the coefficients: ~1e-6 of it).
#define MS_EXACT_CERTAIN 1e-5
// The union of several triangles' intervals holds this many disjoint ones at most.
#define MS_EXACT_UNION_CAPACITY 8

// The iterations this invocation's data-dependent loops below have run: a caller that must
// stop before lavapipe's loop limiter cuts its loops counts them (exact_lookup.glsl's walk).
uint ms_exact_iterations = 0u;

// A moving light (issue 38), set by the caller before asking (the mask, from the map's
// MsLightEnd; 0 for a still light): a spot's motion L(1) - L(0), its ray L(t) - P(t) linear in
// t; a directional light's turn D(1) - D(0) (unit ends), its ray -((1 - t) D(0) + t D(1))
// linear too, s then in units of a ray up to cos(a / 2) short. Polynomials keep their degree.
vec3 ms_exact_light_motion = vec3(0.0);
vec3 ms_exact_light_turn = vec3(0.0);

// A vector linear in t: a + t b.
struct ms_exact_Linear {
    vec3 a;
    vec3 b;
};

float ms_exact_det(vec3 x, vec3 y, vec3 z) {
    precise float d = x.x * (y.y * z.z - y.z * z.y) + x.y * (y.z * z.x - y.x * z.z)
        + x.z * (y.x * z.y - y.y * z.x);
    return d;
}

// det(x(t), y(t), z(t)) as c.x + c.y t + c.z t^2 + c.w t^3: trilinear, so the coefficient
// of t^k sums the determinants taking the moving part b of exactly k of the three.
vec4 ms_exact_triple(ms_exact_Linear x, ms_exact_Linear y, ms_exact_Linear z) {
    if (z.b == vec3(0.0)) {
        // z stands still (the shadow ray of a still receiver, or any directional one): the
        // four determinants that take z.b are 0; their terms are left out (adding a 0 changes
        // no sum but a zero's sign, which no test reads). An edge's two triangles see the same
        // ray, so both take this branch: their values stay exactly opposite.
        precise vec4 c = vec4(
            ms_exact_det(x.a, y.a, z.a),
            ms_exact_det(x.b, y.a, z.a) + ms_exact_det(x.a, y.b, z.a),
            ms_exact_det(x.b, y.b, z.a),
            0.0);
        return c;
    }
    precise vec4 c = vec4(
        ms_exact_det(x.a, y.a, z.a),
        ms_exact_det(x.b, y.a, z.a) + ms_exact_det(x.a, y.b, z.a) + ms_exact_det(x.a, y.a, z.b),
        ms_exact_det(x.b, y.b, z.a) + ms_exact_det(x.b, y.a, z.b) + ms_exact_det(x.a, y.b, z.b),
        ms_exact_det(x.b, y.b, z.b));
    return c;
}

// A total order on corners (their data), the same in every triangle that holds them.
bool ms_exact_before(ms_exact_Linear x, ms_exact_Linear y) {
    float k[6] = float[6](x.a.x, x.a.y, x.a.z, x.b.x, x.b.y, x.b.z);
    float l[6] = float[6](y.a.x, y.a.y, y.a.z, y.b.x, y.b.y, y.b.z);
    for (int i = 0; i < 6; ++i) {
        if (k[i] != l[i]) return k[i] < l[i];
    }
    return false;
}

// The edge function det(x, y, u) of the edge from x to y, computed in the edge's canonical
// order and negated when walked the other way: exactly opposite for the two triangles that
// share the edge (see the ties above).
vec4 ms_exact_edge(ms_exact_Linear x, ms_exact_Linear y, ms_exact_Linear u) {
    if (ms_exact_before(y, x)) return -ms_exact_triple(y, x, u);
    return ms_exact_triple(x, y, u);
}

// The same edge function of corners x, y and a ray u that stand still: its constant term
// alone, bit for bit the one ms_exact_edge computes for linears whose moving parts are 0 (the
// other terms are then exactly 0), in the same canonical edge order, for a quarter of the
// determinants.
float ms_exact_edge_still(vec3 x, vec3 y, vec3 u) {
    ms_exact_Linear lx = ms_exact_Linear(x, vec3(0.0));
    ms_exact_Linear ly = ms_exact_Linear(y, vec3(0.0));
    if (ms_exact_before(ly, lx)) return -ms_exact_det(y, x, u);
    return ms_exact_det(x, y, u);
}

float ms_exact_eval(vec4 c, float t) {
    precise float r = ((c.w * t + c.z) * t + c.y) * t + c.x;
    return r;
}

vec4 ms_exact_derivative(vec4 c) {
    return vec4(c.y, 2.0 * c.z, 3.0 * c.w, 0.0);
}

// The root of c in [a, b], where it is monotone and negative at a iff negative_at_a,
// bracketed to MS_EXACT_ROOT_WIDTH: Newton steps inside the bracket while they shrink fast
// enough, bisection otherwise (rtsafe); once a Newton step is below the width, two
// evaluations close the bracket around its point, so the width is proven by a sign change.
float ms_exact_root_in(vec4 c, float a, float b, bool negative_at_a) {
    vec4 slope = ms_exact_derivative(c);
    float step_ = b - a;
    float last_step = b - a;
    float x = 0.5 * (a + b);
    // Enough for bisection alone to reach the width from [0, 1].
    for (int i = 0; i < 40; ++i) {
        ++ms_exact_iterations;
        float f = ms_exact_eval(c, x);
        if (f == 0.0) return x;
        if ((f < 0.0) == negative_at_a) a = max(a, x); else b = min(b, x);
        if (b - a <= MS_EXACT_ROOT_WIDTH) break;
        float df = ms_exact_eval(slope, x);
        float newton = x - f / df;
        if (newton > a && newton < b && abs(2.0 * f) <= abs(last_step * df)) {
            last_step = step_;
            step_ = f / df;
            x = newton;
            if (abs(step_) < 0.25 * MS_EXACT_ROOT_WIDTH) {
                float half_width = 0.5 * MS_EXACT_ROOT_WIDTH;
                float probe_lo = max(x - half_width, a);
                float probe_hi = min(x + half_width, b);
                float f_lo = ms_exact_eval(c, probe_lo);
                if (f_lo == 0.0) return probe_lo;
                if ((f_lo < 0.0) == negative_at_a) a = max(a, probe_lo); else b = min(b, probe_lo);
                float f_hi = ms_exact_eval(c, probe_hi);
                if (f_hi == 0.0) return probe_hi;
                if ((f_hi < 0.0) == negative_at_a) a = max(a, probe_hi); else b = min(b, probe_hi);
                x = 0.5 * (a + b);
            }
        } else {
            last_step = step_;
            step_ = 0.5 * (b - a);
            x = a + step_;
        }
        if (x <= a || x >= b) break;
    }
    return 0.5 * (a + b);
}

// Where c changes sign in (lo, hi), ascending, given the points `crit` (ascending, inside)
// between which it is monotone; plus its exact zeros at those points. A root where the sign
// does not change (a double root) changes no test and is not needed.
int ms_exact_monotone_roots(vec4 c, float lo, float hi, float crit[3], int n_crit,
                            out float roots[3]) {
    int n = 0;
    float a = lo;
    float fa = ms_exact_eval(c, a);
    for (int i = 0; i <= n_crit; ++i) {
        ++ms_exact_iterations;
        float b = i < n_crit ? crit[i] : hi;
        float fb = ms_exact_eval(c, b);
        if (fa == 0.0) {
            if (a > lo && n < 3) roots[n++] = a;
        } else if (fb != 0.0 && (fa < 0.0) != (fb < 0.0) && n < 3) {
            roots[n++] = ms_exact_root_in(c, a, b, fa < 0.0);
        }
        a = b;
        fa = fb;
    }
    return n;
}

// Where the polynomial c of degree <= 2 (c.w == 0) changes sign in (lo, hi), ascending (at
// most 2), in closed form (the stable quadratic formula: no loop). A double root changes no
// sign and is left out; two roots closer than f32 resolves are a double root to it.
int ms_exact_quadratic_roots(vec4 c, float lo, float hi, out float roots[3]) {
    roots = float[3](0.0, 0.0, 0.0);
    float r0, r1;
    if (c.z == 0.0) {
        if (c.y == 0.0) return 0;
        r0 = -c.x / c.y;
        r1 = r0;
    } else {
        float discriminant = c.y * c.y - 4.0 * c.z * c.x;
        if (!(discriminant > 0.0)) return 0;
        float q = -0.5 * (c.y + (c.y < 0.0 ? -sqrt(discriminant) : sqrt(discriminant)));
        r0 = q / c.z;
        r1 = q != 0.0 ? c.x / q : r0;
        if (r1 < r0) {
            float swap = r0;
            r0 = r1;
            r1 = swap;
        }
    }
    int n = 0;
    if (r0 > lo && r0 < hi) roots[n++] = r0;
    if (r1 != r0 && r1 > lo && r1 < hi) roots[n++] = r1;
    return n;
}

// Where the cubic c changes sign in (lo, hi), ascending (at most 3). Between consecutive
// roots of its derivative (a quadratic, in closed form) it is monotone, so each such piece
// holds at most one root and a sign change brackets it. No tolerance decides a degree: a tiny
// leading coefficient only adds pieces. Of degree <= 2: in closed form.
int ms_exact_sign_changes(vec4 c, float lo, float hi, out float roots[3]) {
    float none[3] = float[3](0.0, 0.0, 0.0);
    roots = none;
    if (c == vec4(0.0)) return 0;
    if (c.w == 0.0) return ms_exact_quadratic_roots(c, lo, hi, roots);
    float turns[3];
    int n_turns = ms_exact_quadratic_roots(ms_exact_derivative(c), lo, hi, turns);
    return ms_exact_monotone_roots(c, lo, hi, turns, n_turns, roots);
}

// The polynomial's sign over all of [w0, w1] when its Bernstein coefficients there (whose
// convex hull holds its graph) all have it by more than margin: 1 or -1; 0 otherwise. The
// window's polynomial in s = (t - w0) / (w1 - w0) first: its Taylor coefficients at w0, the
// k-th scaled by (w1 - w0)^k.
int ms_exact_certain_sign(vec4 c, float w0, float w1, float margin) {
    float d = w1 - w0;
    vec4 at = vec4(ms_exact_eval(c, w0), ms_exact_eval(ms_exact_derivative(c), w0),
                   c.z + 3.0 * c.w * w0, c.w) * vec4(1.0, d, d * d, d * d * d);
    vec4 b = vec4(at.x, at.x + at.y / 3.0, at.x + (2.0 * at.y + at.z) / 3.0,
                  at.x + at.y + at.z + at.w);
    if (all(greaterThan(b, vec4(margin)))) return 1;
    if (all(lessThan(b, vec4(-margin)))) return -1;
    return 0;
}

// The start of the range of s that must be free for a receiver to see the light (see the
// epsilon above): spot, a share of the segment to the light; directional, of `scene_size`.
float ms_exact_s_min(bool spot, float scene_size) {
    return spot ? MS_EXACT_SELF_EPSILON : MS_EXACT_SELF_EPSILON * scene_size;
}

// Whether the ray meets the triangle at time t, from the edge polynomials and the plane's.
// The start of s for one triangle over [w0, w1] (plane: det(A', B', C')): the ray tracer's
// epsilon off the plane by more than rounding all window long, else s_min (ms_exact_s_min).
float ms_exact_s_from(vec4 plane, float r, float m, float w0, float w1, float s_min) {
    float margin = MS_EXACT_OFF_PLANE * r * r * (r + m);
    bool off_plane = ms_exact_certain_sign(plane, w0, w1, margin) != 0;
    return off_plane ? s_min * MS_EXACT_OFF_PLANE_SHARE : s_min;
}

bool ms_exact_blocks(vec4 edges[3], vec4 plane, bool spot, float s_min, float t) {
    float x = ms_exact_eval(edges[0], t);
    float y = ms_exact_eval(edges[1], t);
    float z = ms_exact_eval(edges[2], t);
    if ((x < 0.0 || y < 0.0 || z < 0.0) && (x > 0.0 || y > 0.0 || z > 0.0)) return false;
    precise float sum = x + y + z;
    if (sum == 0.0) return false;
    float s = ms_exact_eval(plane, t) / sum;
    return s >= s_min && (!spot || s <= 1.0);
}

// The sizes the certain-sign margins are relative to: the corners' largest reach from the
// receiver over the shutter (r) and the ray's (ray).
void ms_exact_sizes(ms_exact_Linear corner[3], ms_exact_Linear u, out float r, out float ray) {
    r = 0.0;
    for (int i = 0; i < 3; ++i) r = max(r, length(corner[i].a) + length(corner[i].b));
    ray = length(u.a) + length(u.b);
}

// Each edge function's certain sign over [w0, w1] (ms_exact_certain_sign); true when two of
// them have opposite ones: the ray is then outside the triangle all window long.
bool ms_exact_edges_disagree(vec4 edges[3], float r, float ray, float w0, float w1,
                             out int edge_sign[3]) {
    float margin = MS_EXACT_CERTAIN * r * r * ray;
    bool positive = false;
    bool negative = false;
    for (int i = 0; i < 3; ++i) {
        edge_sign[i] = ms_exact_certain_sign(edges[i], w0, w1, margin);
        positive = positive || edge_sign[i] > 0;
        negative = negative || edge_sign[i] < 0;
    }
    return positive && negative;
}

// ms_exact_shadowed_intervals's general case: the test's changes found as the polynomials'
// sign changes in [w0, w1], and the test asked once between consecutive ones.
int ms_exact_general_intervals(ms_exact_Linear corner[3], ms_exact_Linear u, vec4 edges[3],
                               vec4 plane, bool spot, float s_min, float m, float w0,
                               float w1, inout vec2 intervals[MS_EXACT_MAX_INTERVALS]) {
    // Two edge functions of opposite signs over the whole window: never a hit.
    float r, ray;
    ms_exact_sizes(corner, u, r, ray);
    int edge_sign[3];
    if (ms_exact_edges_disagree(edges, r, ray, w0, w1, edge_sign)) return 0;
    s_min = ms_exact_s_from(plane, r, m, w0, w1, s_min);

    vec4 sum = edges[0] + edges[1] + edges[2];
    float events[MS_EXACT_MAX_EVENTS];
    int n_events = 0;
    for (int k = 0; k < 5; ++k) {
        ++ms_exact_iterations;
        if (k == 4 && !spot) break;
        float s0 = k == 3 ? s_min : 1.0;
        vec4 c = k < 3 ? edges[k] : plane - s0 * sum;
        // A polynomial of a certain sign over the window changes no test there: no roots to
        // look for (the bound of the plane's terms: det(A', B', C') <= r^3, the sum of the
        // edges <= 3 r^2 |u|).
        float plane_margin = MS_EXACT_CERTAIN * r * r * (r + 3.0 * ray * max(s0, 1.0));
        if (k < 3 ? edge_sign[k] != 0 : ms_exact_certain_sign(c, w0, w1, plane_margin) != 0) {
            continue;
        }
        float roots[3];
        int n = ms_exact_sign_changes(c, w0, w1, roots);
        for (int j = 0; j < n; ++j) events[n_events++] = roots[j];
    }
    // Insertion sort: at most 15.
    for (int i = 1; i < n_events; ++i) {
        ++ms_exact_iterations;
        float v = events[i];
        int j = i - 1;
        while (j >= 0 && events[j] > v) {
            ++ms_exact_iterations;
            events[j + 1] = events[j];
            --j;
        }
        events[j + 1] = v;
    }

    int count = 0;
    float start = w0;
    for (int i = 0; i <= n_events; ++i) {
        ++ms_exact_iterations;
        float end_ = i < n_events ? events[i] : w1;
        if (end_ > start && ms_exact_blocks(edges, plane, spot, s_min, 0.5 * (start + end_))) {
            if (count > 0 && intervals[count - 1].y == start) {
                intervals[count - 1].y = end_;
            } else if (count < MS_EXACT_MAX_INTERVALS) {
                intervals[count++] = vec2(start, end_);
            }
        }
        start = max(start, end_);
    }
    return count;
}

// The shadow ray u and the triangle's corners relative to the receiver moving from p0 to p1,
// each linear in t (see the top). `known_still`: the receiver and the light stand still, as
// known when compiled: the ray's motion is the constant -0.0 that -(p1 - p0) gives then, so
// the still ray's branches fold.
void ms_exact_relative(vec3 p0, vec3 p1, bool spot, vec3 light, vec3 t0_corners[3],
                       vec3 t1_corners[3], bool known_still, out ms_exact_Linear u,
                       out ms_exact_Linear corner[3]) {
    vec3 m = known_still ? vec3(0.0) : p1 - p0;
    if (spot) {
        // A moving light: the ray's end moves with it (a uniform branch; a still light's ray
        // as it was, bit for bit).
        vec3 ray_motion =
            known_still || ms_exact_light_motion == vec3(0.0) ? -m : ms_exact_light_motion - m;
        u = ms_exact_Linear(light - p0, ray_motion);
    } else {
        u = ms_exact_Linear(-normalize(light), -ms_exact_light_turn);
    }
    for (int i = 0; i < 3; ++i) {
        corner[i] = ms_exact_Linear(t0_corners[i] - p0, (t1_corners[i] - t0_corners[i]) - m);
    }
}

// Nothing moves relative to the receiver (a still triangle and a still receiver, the common
// case of a level's static geometry): every polynomial is a constant, the answer is the same
// all window long (the general case would find no root and ask the same test once, on the
// same constants).
bool ms_exact_relatively_still(ms_exact_Linear u, ms_exact_Linear corner[3]) {
    return u.b == vec3(0.0) && corner[0].b == vec3(0.0) && corner[1].b == vec3(0.0)
        && corner[2].b == vec3(0.0);
}

// The test where ms_exact_relatively_still holds: on the constants alone (m: the receiver's
// distance from the origin, for ms_exact_s_from).
bool ms_exact_blocks_still(ms_exact_Linear u, ms_exact_Linear corner[3], bool spot,
                           float s_min, float m) {
    vec3 c[3] = vec3[3](corner[0].a, corner[1].a, corner[2].a);
    vec4 edges[3] = vec4[3](vec4(ms_exact_edge_still(c[0], c[1], u.a), vec3(0.0)),
                            vec4(ms_exact_edge_still(c[1], c[2], u.a), vec3(0.0)),
                            vec4(ms_exact_edge_still(c[2], c[0], u.a), vec3(0.0)));
    vec4 plane = vec4(ms_exact_det(c[0], c[1], c[2]), vec3(0.0));
    float r = max(max(length(c[0]), length(c[1])), length(c[2]));
    return ms_exact_blocks(edges, plane, spot, ms_exact_s_from(plane, r, m, 0.0, 1.0, s_min),
                           0.0);
}

// ms_exact_blocks_still for a receiver at p and a triangle with corners `at` that both stand
// still (a directional light's ray stands still; a spot's does when the receiver does).
bool ms_exact_blocks_still_at(vec3 p, bool spot, vec3 light, float s_min, vec3 at[3]) {
    ms_exact_Linear u = ms_exact_Linear(spot ? light - p : -normalize(light), vec3(0.0));
    ms_exact_Linear corner[3];
    for (int i = 0; i < 3; ++i) corner[i] = ms_exact_Linear(at[i] - p, vec3(0.0));
    return ms_exact_blocks_still(u, corner, spot, s_min, length(p));
}

// The intervals of [w0, w1] (within the shutter [0, 1]) during which the triangle with
// corners t0_corners at t = 0 and t1_corners at t = 1 blocks the shadow ray of the receiver
// moving from p0 (t = 0) to p1 (t = 1): ascending, disjoint, apart; their count (at most
// MS_EXACT_MAX_INTERVALS). `light`: the spot's position, or the direction a directional
// light travels (any length); `s_min` from ms_exact_s_min; `known_still`: ms_exact_relative.
int ms_exact_shadowed_intervals(vec3 p0, vec3 p1, bool spot, vec3 light, float s_min,
                                vec3 t0_corners[3], vec3 t1_corners[3], float w0, float w1,
                                bool known_still, out vec2 intervals[MS_EXACT_MAX_INTERVALS]) {
    for (int i = 0; i < MS_EXACT_MAX_INTERVALS; ++i) intervals[i] = vec2(0.0);
    if (!(w1 > w0)) return 0;
    ms_exact_Linear u, corner[3];
    ms_exact_relative(p0, p1, spot, light, t0_corners, t1_corners, known_still, u, corner);
    // The receiver's distance from the origin, which its coordinates' rounding is relative to.
    float m = max(length(p0), length(p1));
    if (ms_exact_relatively_still(u, corner)) {
        if (!ms_exact_blocks_still(u, corner, spot, s_min, m)) return 0;
        intervals[0] = vec2(w0, w1);
        return 1;
    }
    vec4 edges[3] = vec4[3](ms_exact_edge(corner[0], corner[1], u),
                            ms_exact_edge(corner[1], corner[2], u),
                            ms_exact_edge(corner[2], corner[0], u));
    vec4 plane = ms_exact_triple(corner[0], corner[1], corner[2]);
    return ms_exact_general_intervals(corner, u, edges, plane, spot, s_min, m, w0, w1,
                                      intervals);
}

int ms_exact_shadowed_intervals(vec3 p0, vec3 p1, bool spot, vec3 light, float s_min,
                                vec3 t0_corners[3], vec3 t1_corners[3], float w0, float w1,
                                out vec2 intervals[MS_EXACT_MAX_INTERVALS]) {
    return ms_exact_shadowed_intervals(p0, p1, spot, light, s_min, t0_corners, t1_corners, w0,
                                       w1, false, intervals);
}

// Whether ms_exact_shadowed_intervals can find anything in [w0, w1], as far as certain signs
// tell without root finding: MS_EXACT_NONE (two edge functions of opposite signs all window
// long) or MS_EXACT_ASK. The cheap half, for callers that gather the triangles left and ask
// them together: llvmpipe runs a loop body's whole code for every lane, taken or not, so a
// loop holding the root finding would pay for it on every triangle.
const int MS_EXACT_NONE = 0;
const int MS_EXACT_ASK = 1;
// (`known_still`: see ms_exact_relative.)
int ms_exact_classify(vec3 p0, vec3 p1, bool spot, vec3 light, float s_min,
                      vec3 t0_corners[3], vec3 t1_corners[3], float w0, float w1,
                      bool with_plane, bool known_still) {
    if (!(w1 > w0)) return MS_EXACT_NONE;
    ms_exact_Linear u, corner[3];
    ms_exact_relative(p0, p1, spot, light, t0_corners, t1_corners, known_still, u, corner);
    // Each edge as the triangle walks it, not in the edges' canonical order: only a sign
    // certain by the margin (far above the orders' rounding difference) rejects, so a ray
    // on or near a shared edge is always asked the whole test, which takes that order.
    vec4 edges[3] = vec4[3](ms_exact_triple(corner[0], corner[1], u),
                            ms_exact_triple(corner[1], corner[2], u),
                            ms_exact_triple(corner[2], corner[0], u));
    float r, ray;
    ms_exact_sizes(corner, u, r, ray);
    int edge_sign[3];
    if (ms_exact_edges_disagree(edges, r, ray, w0, w1, edge_sign)) return MS_EXACT_NONE;
    if (with_plane) {
        // The edges alone test the shadow ray's whole line: a triangle the line meets behind
        // the receiver (s below the lowest start the whole test may take, ms_exact_s_from's
        // off-plane one) or, for a spot light, beyond the light (s > 1) blocks nothing.
        // s = det(A', B', C') / E: where E has a certain sign all window long and so has
        // det - s0 E at a bound s0, s stays on one side of s0 (the margins: the general
        // test's).
        vec4 sum = edges[0] + edges[1] + edges[2];
        int e = ms_exact_certain_sign(sum, w0, w1, 3.0 * MS_EXACT_CERTAIN * r * r * ray);
        if (e != 0) {
            vec4 plane = ms_exact_triple(corner[0], corner[1], corner[2]);
            float margin = MS_EXACT_CERTAIN * r * r * (r + 3.0 * ray * max(s_min, 1.0));
            float s_lowest = s_min * MS_EXACT_OFF_PLANE_SHARE;
            if (e * ms_exact_certain_sign(plane - s_lowest * sum, w0, w1, margin) < 0) {
                return MS_EXACT_NONE;
            }
            if (spot && e * ms_exact_certain_sign(plane - sum, w0, w1, margin) > 0) {
                return MS_EXACT_NONE;
            }
        }
    }
    return MS_EXACT_ASK;
}

// The union of several triangles' shadowed intervals: up to MS_EXACT_UNION_CAPACITY disjoint
// intervals, in no order, in vector registers (starts s0 s1, ends e0 e1; an empty slot holds
// MS_EXACT_EMPTY in both), worked on with constant indices: as a sorted array (run-time
// indices, which lavapipe keeps in memory) the exact mask was 4x slower.
struct ms_exact_Union {
    vec4 s0;
    vec4 s1;
    vec4 e0;
    vec4 e1;
    // Set when more disjoint intervals came than fit: one was then joined with its nearest
    // neighbour, shadowing the gap between them (never lighting a shadowed time).
    bool joined_gaps;
};

// Outside the shutter [0, 1]: an empty slot overlaps no interval and has no length.
#define MS_EXACT_EMPTY -1.0

ms_exact_Union ms_exact_union_empty() {
    vec4 empty = vec4(MS_EXACT_EMPTY);
    return ms_exact_Union(empty, empty, empty, empty, false);
}

// Puts [lo, hi] into the first empty slot; false when there is none.
bool ms_exact_union_place(inout ms_exact_Union u, float lo, float hi) {
    if (u.e0.x == MS_EXACT_EMPTY) { u.s0.x = lo; u.e0.x = hi; }
    else if (u.e0.y == MS_EXACT_EMPTY) { u.s0.y = lo; u.e0.y = hi; }
    else if (u.e0.z == MS_EXACT_EMPTY) { u.s0.z = lo; u.e0.z = hi; }
    else if (u.e0.w == MS_EXACT_EMPTY) { u.s0.w = lo; u.e0.w = hi; }
    else if (u.e1.x == MS_EXACT_EMPTY) { u.s1.x = lo; u.e1.x = hi; }
    else if (u.e1.y == MS_EXACT_EMPTY) { u.s1.y = lo; u.e1.y = hi; }
    else if (u.e1.z == MS_EXACT_EMPTY) { u.s1.z = lo; u.e1.z = hi; }
    else if (u.e1.w == MS_EXACT_EMPTY) { u.s1.w = lo; u.e1.w = hi; }
    else return false;
    return true;
}

// Adds [iv.x, iv.y] (within [0, 1]), joining it with every interval it overlaps or touches.
// One pass is enough: the intervals are disjoint, so growing iv by those it meets never makes
// it meet another.
void ms_exact_union_add(inout ms_exact_Union u, vec2 iv) {
    if (!(iv.y > iv.x)) return;
    bvec4 m0 = bvec4(uvec4(lessThanEqual(u.s0, vec4(iv.y))) & uvec4(greaterThanEqual(u.e0, vec4(iv.x))));
    bvec4 m1 = bvec4(uvec4(lessThanEqual(u.s1, vec4(iv.y))) & uvec4(greaterThanEqual(u.e1, vec4(iv.x))));
    vec4 lo4 = min(mix(vec4(iv.x), u.s0, m0), mix(vec4(iv.x), u.s1, m1));
    vec4 hi4 = max(mix(vec4(iv.y), u.e0, m0), mix(vec4(iv.y), u.e1, m1));
    float lo = min(min(lo4.x, lo4.y), min(lo4.z, lo4.w));
    float hi = max(max(hi4.x, hi4.y), max(hi4.z, hi4.w));
    vec4 empty = vec4(MS_EXACT_EMPTY);
    u.s0 = mix(u.s0, empty, m0);
    u.e0 = mix(u.e0, empty, m0);
    u.s1 = mix(u.s1, empty, m1);
    u.e1 = mix(u.e1, empty, m1);
    if (ms_exact_union_place(u, lo, hi)) return;
    // Full, and [lo, hi] met none of the intervals: join it with the nearest, across a gap
    // that holds no other interval (it would be nearer).
    vec4 gap0 = max(u.s0 - vec4(hi), vec4(lo) - u.e0);
    vec4 gap1 = max(u.s1 - vec4(hi), vec4(lo) - u.e1);
    vec4 g = min(gap0, gap1);
    float nearest = min(min(g.x, g.y), min(g.z, g.w));
    bvec4 n0 = equal(gap0, vec4(nearest));
    bvec4 n1 = any(n0) ? bvec4(false) : equal(gap1, vec4(nearest));
    // Only the first of equally near slots takes it.
    n0 = bvec4(n0.x, n0.y && !n0.x, n0.z && !any(n0.xy), n0.w && !any(n0.xyz));
    n1 = bvec4(n1.x, n1.y && !n1.x, n1.z && !any(n1.xy), n1.w && !any(n1.xyz));
    u.s0 = mix(u.s0, min(u.s0, vec4(lo)), n0);
    u.e0 = mix(u.e0, max(u.e0, vec4(hi)), n0);
    u.s1 = mix(u.s1, min(u.s1, vec4(lo)), n1);
    u.e1 = mix(u.e1, max(u.e1, vec4(hi)), n1);
    u.joined_gaps = true;
}

// The union's total length: the shadowed time, of which the lit fraction of a window [w0, w1]
// is 1 - length / (w1 - w0).
float ms_exact_union_length(ms_exact_Union u) {
    return dot(u.e0 - u.s0, vec4(1.0)) + dot(u.e1 - u.s1, vec4(1.0));
}

// Whether one interval of the union holds all of [w0, w1].
bool ms_exact_union_covers(ms_exact_Union u, float w0, float w1) {
    bvec4 c0 = bvec4(uvec4(lessThanEqual(u.s0, vec4(w0))) & uvec4(greaterThanEqual(u.e0, vec4(w1))));
    bvec4 c1 = bvec4(uvec4(lessThanEqual(u.s1, vec4(w0))) & uvec4(greaterThanEqual(u.e1, vec4(w1))));
    return any(c0) || any(c1);
}

// Slot i (0 to MS_EXACT_UNION_CAPACITY - 1): its interval, or (MS_EXACT_EMPTY, MS_EXACT_EMPTY).
vec2 ms_exact_union_slot(ms_exact_Union u, int i) {
    return i < 4 ? vec2(u.s0[i], u.e0[i]) : vec2(u.s1[i - 4], u.e1[i - 4]);
}

#endif
