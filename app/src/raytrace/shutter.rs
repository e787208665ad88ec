//! The exact share of the shutter during which a moving point sees the light: the truth for a
//! deferred frame, whose G-buffer point (fixed barycentrics on a moving triangle) moves
//! linearly, `P(t) = P0 + t (P1 - P0)`, as every vertex does.
//!
//! Not sampled: the times at which the shadow ray from `P(t)` can start or stop meeting a
//! triangle are roots of polynomials, found to ~1e-14, and between two such times the ray
//! tracer's own test (the watertight [`Ray::intersect`] on `shade.rs`'s shadow ray, epsilon
//! and all) is asked once, at the midpoint, so the answer is that tracer's visibility
//! integrated over the shutter. Nothing of the shadow maps (texels, bias, normal offset).
//!
//! With every vector relative to `P(t)` (`A' = A(t) - P(t)`, linear in t) and `u(t)` the
//! shadow ray's direction (directional: constant, or for a turning light the blend
//! `-((1 - t) D0 + t D1)`, linear; spot: `L(t) - P(t)`, linear also for a moving light whose
//! position `L(t)` is linear), the ray meets
//! triangle ABC iff its three edge functions `det(A', B', u)`, `det(B', C', u)`,
//! `det(C', A', u)` share a sign and the plane's ray parameter `s = det(A', B', C') / E`
//! (`E` their sum) lies in `[s_min, s_max]`, i.e. `det(A', B', C') - s0 E` has the right
//! sign at both bounds. Each is a triple product of vectors linear in t: a polynomial of
//! degree at most 3 whose coefficients are sums of determinants of the linear parts. The
//! test can change only where one of them changes sign.

use super::bvh::Bvh;
use super::intersect::Ray;
use super::shade::ShadingLight;
use super::triangles::Triangle;
use glam::DVec3;

/// Roots are bracketed to this width in t (the result's accuracy, with the polynomials'
/// rounding: f64 coefficients of products of the scene's coordinates).
const ROOT_WIDTH: f64 = 1e-14;
/// Shadowed intervals closer than this (or to an end of the shutter) are joined (see
/// [`merge`]).
const JOIN: f64 = 1e-12;
/// A triangle is rejected without root finding when two of its edge functions have
/// opposite signs over the whole shutter by more than this share of their largest possible
/// term (rounding of the coefficients is ~1e-15 of it; the tracer's own test, with the same
/// share of error, then agrees at every time).
const CERTAIN: f64 = 1e-12;
/// Swept boxes are grown by this share of the query's coordinates: `lo1 - m` is rounded.
const SWEPT_PAD: f64 = 1e-9;

/// `c[0] + c[1] t + c[2] t^2 + c[3] t^3`.
type Cubic = [f64; 4];

/// A vector linear in t: `a + t b`.
#[derive(Debug, Clone, Copy)]
struct Linear {
    a: DVec3,
    b: DVec3,
}

impl Linear {
    fn bound(self) -> f64 {
        self.a.length() + self.b.length()
    }
}

fn det(x: DVec3, y: DVec3, z: DVec3) -> f64 {
    x.dot(y.cross(z))
}

/// `det(x(t), y(t), z(t))`: trilinear, so the coefficient of `t^k` sums the determinants
/// taking the moving part `b` of exactly k of the three.
fn triple(x: Linear, y: Linear, z: Linear) -> Cubic {
    [
        det(x.a, y.a, z.a),
        det(x.b, y.a, z.a) + det(x.a, y.b, z.a) + det(x.a, y.a, z.b),
        det(x.b, y.b, z.a) + det(x.b, y.a, z.b) + det(x.a, y.b, z.b),
        det(x.b, y.b, z.b),
    ]
}

fn eval(c: &[f64], t: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, &k| acc * t + k)
}

/// Up to three times in (0, 1), ascending.
#[derive(Debug, Default, Clone, Copy)]
struct Roots {
    t: [f64; 3],
    n: usize,
}

impl Roots {
    fn push(&mut self, t: f64) {
        if t > 0.0 && t < 1.0 && self.n < 3 {
            self.t[self.n] = t;
            self.n += 1;
        }
    }

    fn as_slice(&self) -> &[f64] {
        &self.t[..self.n]
    }
}

/// Where the polynomial `c` (degree `c.len() - 1` <= 3) changes sign in (0, 1), plus its
/// exact zeros at the pieces' ends. Between consecutive roots of its derivative it is
/// monotone, so each such piece holds at most one root and a sign change brackets it; the
/// derivative's roots come the same way, down to a linear one. No tolerance decides a
/// degree: a tiny leading coefficient only adds pieces. A root where the sign does not change
/// (a double root) changes no test and is not needed.
fn sign_changes(c: &[f64], out: &mut Roots) {
    if c.len() < 2 || c.iter().all(|&k| k == 0.0) {
        return;
    }
    let mut derivative = [0.0; 3];
    for k in 1..c.len() {
        derivative[k - 1] = k as f64 * c[k];
    }
    let mut critical = Roots::default();
    sign_changes(&derivative[..c.len() - 1], &mut critical);
    let mut a = 0.0;
    let mut fa = eval(c, a);
    for &b in critical.as_slice().iter().chain([1.0].iter()) {
        let fb = eval(c, b);
        if fa == 0.0 {
            out.push(a);
        } else if fb != 0.0 && (fa < 0.0) != (fb < 0.0) {
            out.push(root_in(c, a, b, fa < 0.0));
        }
        (a, fa) = (b, fb);
    }
}

/// The root of `c` in `[a, b]`, where it is monotone and negative at `a` iff `negative_at_a`,
/// bracketed to `ROOT_WIDTH`. Newton steps inside the bracket while they shrink fast enough,
/// bisection otherwise (Numerical Recipes' `rtsafe`); once a Newton step is below the width,
/// two evaluations close the bracket around its point, so the width is always proven by a
/// sign change, not assumed from convergence.
fn root_in(c: &[f64], a: f64, b: f64, negative_at_a: bool) -> f64 {
    let slope: [f64; 3] =
        std::array::from_fn(|k| c.get(k + 1).map_or(0.0, |&v| (k + 1) as f64 * v));
    let slope = &slope[..c.len() - 1];
    let mut bracket = Bracket {
        a,
        b,
        negative_at_a,
    };
    let (mut step, mut last_step) = (b - a, b - a);
    let mut x = 0.5 * (a + b);
    // Enough for bisection alone to reach the width from [0, 1].
    for _ in 0..64 {
        let f = eval(c, x);
        if bracket.narrow(x, f) {
            return x;
        }
        if bracket.b - bracket.a <= ROOT_WIDTH {
            break;
        }
        let df = eval(slope, x);
        let newton = x - f / df;
        if newton > bracket.a && newton < bracket.b && (2.0 * f).abs() <= (last_step * df).abs() {
            (last_step, step) = (step, f / df);
            x = newton;
            if step.abs() < 0.25 * ROOT_WIDTH {
                let half = 0.5 * ROOT_WIDTH;
                for probe in [(x - half).max(bracket.a), (x + half).min(bracket.b)] {
                    if bracket.narrow(probe, eval(c, probe)) {
                        return probe;
                    }
                }
                x = 0.5 * (bracket.a + bracket.b);
            }
        } else {
            (last_step, step) = (step, 0.5 * (bracket.b - bracket.a));
            x = bracket.a + step;
        }
        if x <= bracket.a || x >= bracket.b {
            break;
        }
    }
    0.5 * (bracket.a + bracket.b)
}

/// `[a, b]` holding a sign change of a monotone polynomial.
struct Bracket {
    a: f64,
    b: f64,
    negative_at_a: bool,
}

impl Bracket {
    /// Moves an end to `x` by the sign `f` of the polynomial there; true at an exact zero.
    fn narrow(&mut self, x: f64, f: f64) -> bool {
        if f == 0.0 {
            return true;
        }
        if (f < 0.0) == self.negative_at_a {
            self.a = self.a.max(x);
        } else {
            self.b = self.b.min(x);
        }
        false
    }
}

/// The polynomial's sign over all of [0, 1] when its Bernstein coefficients (whose convex
/// hull holds its graph) all have it by more than `margin`; `None` otherwise.
fn certain_sign(c: &Cubic, margin: f64) -> Option<bool> {
    let b = [
        c[0],
        c[0] + c[1] / 3.0,
        c[0] + (2.0 * c[1] + c[2]) / 3.0,
        c[0] + c[1] + c[2] + c[3],
    ];
    if b.iter().all(|&v| v > margin) {
        Some(true)
    } else if b.iter().all(|&v| v < -margin) {
        Some(false)
    } else {
        None
    }
}

/// One receiver's query.
struct Query<'a> {
    light: &'a ShadingLight,
    p0: DVec3,
    /// `P1 - P0`.
    m: DVec3,
    /// The shadow ray's direction relative to the moving point (see the module's docs).
    u: Linear,
    spot: bool,
    s_min: f64,
    s_max: f64,
    /// The swept query: the segment `P0 + s dir`, s in [0, s_far], against boxes.
    inv_dir: DVec3,
    s_far: f64,
    pad: f64,
}

impl<'a> Query<'a> {
    fn new(light: &'a ShadingLight, p0: DVec3, p1: DVec3) -> Self {
        let m = p1 - p0;
        let (ray, s_min, s_max) = light.shadow_ray(p0);
        // A moving light's ray direction changes by `motion` over the shutter: the spot's
        // position linearly, the directional light's (unnormalised) blended direction too.
        let motion = light.motion();
        let (u, spot, s_far) = match light.spot_position() {
            Some(l) => {
                let dl = motion.map_or(DVec3::ZERO, |(dl, _)| dl);
                (
                    Linear {
                        a: l - p0,
                        b: dl - m,
                    },
                    true,
                    1.0,
                )
            }
            None => (
                match motion {
                    None => Linear {
                        a: ray.dir,
                        b: DVec3::ZERO,
                    },
                    // `-((1 - t) D0 + t D1)`: the blend itself, not its normalised start.
                    Some((_, dd)) => Linear {
                        a: -light.direction(),
                        b: -dd,
                    },
                },
                false,
                f64::INFINITY,
            ),
        };
        let size = p0.abs().max_element() + m.abs().max_element() + ray.dir.abs().max_element();
        Self {
            light,
            p0,
            m,
            u,
            spot,
            s_min,
            s_max,
            inv_dir: ray.dir.recip(),
            s_far,
            pad: SWEPT_PAD * size,
        }
    }

    /// Whether a box that holds some triangles at t = 0 (`lo0, hi0`) and t = 1 (`lo1, hi1`),
    /// and so their blend at every t, may hold a point the shadow ray of `P(t)` reaches at
    /// that t. Directional: `P0 + t m + s u` in `B(t)` means `P0 + s u` in `B(t) - t m`, the
    /// blend of `B0` and `B1 - m`, inside their bounding box. Spot: `(1 - s) P(t) + s L` in
    /// `B(t)` means `(1 - s) P0 + s L` in `B(t) - (1 - s) t m`, a convex combination of
    /// `B0`, `B1` and `B1 - m`. So the ray (segment) from `P0` against that box.
    ///
    /// A moving spot at `L0 + t dL`: `(1 - s) P0 + s L0` in `B(t) - t (1 - s) m - t s dL`, in
    /// the box of `B0` and `B1` grown by the box of `0`, `-m` and `-dL`. A turning
    /// directional light's rays fan out from `P0`, which one segment does not bound: every
    /// box may be reached.
    fn may_reach(&self, lo0: DVec3, hi0: DVec3, lo1: DVec3, hi1: DVec3) -> bool {
        let (mut lo, mut hi) = (lo0.min(lo1 - self.m), hi0.max(hi1 - self.m));
        match (self.light.motion(), self.spot) {
            (None, true) => (lo, hi) = (lo.min(lo1), hi.max(hi1)),
            (None, false) => {}
            (Some((dl, _)), true) => {
                let (shift_lo, shift_hi) = (
                    DVec3::ZERO.min(-self.m).min(-dl),
                    DVec3::ZERO.max(-self.m).max(-dl),
                );
                (lo, hi) = (lo0.min(lo1) + shift_lo, hi0.max(hi1) + shift_hi);
            }
            (Some(_), false) => return true,
        }
        let pad = self.pad + SWEPT_PAD * lo.abs().max(hi.abs()).max_element();
        let (lo, hi) = (lo - pad, hi + pad);
        let a = (lo - self.p0) * self.inv_dir;
        let b = (hi - self.p0) * self.inv_dir;
        let (mut near, mut far) = (0.0f64, self.s_far);
        for axis in 0..3 {
            let (n, f) = (a[axis].min(b[axis]), a[axis].max(b[axis]));
            // A NaN (the ray in a slab's plane) leaves the interval as it was.
            if n > near {
                near = n;
            }
            if f < far {
                far = f;
            }
            if near > far {
                return false;
            }
        }
        true
    }

    /// The tracer's test: does the shadow ray of `P(t)` (to the light where it is at `t`) meet
    /// `tri` at time `t`?
    fn blocks(&self, tri: &Triangle, t: f64) -> bool {
        let (ray, s_min, s_max): (Ray, f64, f64) =
            self.light.at(t).shadow_ray(self.p0 + t * self.m);
        ray.intersect(&tri.at(t), s_min, s_max).is_some()
    }

    /// Appends the intervals of the shutter during which `tri` blocks the shadow ray.
    fn shadow_of(&self, tri: &Triangle, out: &mut Vec<(f64, f64)>) {
        let [a, b, c] = [0, 1, 2].map(|i| Linear {
            a: tri.p0[i] - self.p0,
            // A static triangle's `d` is zero: `at` returning `p0` is the same line.
            b: tri.d[i] - self.m,
        });
        let edges = [
            triple(a, b, self.u),
            triple(b, c, self.u),
            triple(c, a, self.u),
        ];
        let r = a.bound().max(b.bound()).max(c.bound());
        let margin = CERTAIN * r * r * self.u.bound();
        // Two edge functions of opposite signs over the whole shutter: never a hit.
        let signs = edges.map(|e| certain_sign(&e, margin));
        if signs.contains(&Some(true)) && signs.contains(&Some(false)) {
            return;
        }
        // Where two edge functions have opposite signs beyond their rounding, the tracer
        // finds no hit either: such pieces need no test.
        let may_hit = |t: f64| {
            let v = edges.map(|e| eval(&e, t));
            !(v.iter().any(|&x| x > margin) && v.iter().any(|&x| x < -margin))
        };
        let mut events = Events::default();
        for e in &edges {
            events.add(e);
        }
        if !events.pieces().any(|(t0, t1)| may_hit(0.5 * (t0 + t1))) {
            return;
        }
        let plane = triple(a, b, c);
        let sum: Cubic = std::array::from_fn(|k| edges[0][k] + edges[1][k] + edges[2][k]);
        for s0 in [self.s_min, self.s_max] {
            if s0.is_finite() {
                events.add(&std::array::from_fn(|k| plane[k] - s0 * sum[k]));
            }
        }
        let start = out.len();
        for (t0, t1) in events.pieces() {
            let mid = 0.5 * (t0 + t1);
            if !may_hit(mid) || !self.blocks(tri, mid) {
                continue;
            }
            match out[start..].last_mut() {
                Some(last) if last.1 == t0 => last.1 = t1,
                _ => out.push((t0, t1)),
            }
        }
    }
}

/// The times in (0, 1) where one of a triangle's polynomials changes sign: at most 3 for
/// each of 3 edges and 2 bounds of the ray.
#[derive(Default)]
struct Events {
    t: [f64; 15],
    n: usize,
}

impl Events {
    fn add(&mut self, p: &Cubic) {
        let mut roots = Roots::default();
        sign_changes(p, &mut roots);
        for &t in roots.as_slice() {
            self.t[self.n] = t;
            self.n += 1;
        }
        self.t[..self.n].sort_unstable_by(f64::total_cmp);
    }

    /// The pieces of [0, 1] between consecutive events (empty ones left out).
    fn pieces(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        let ends = std::iter::once(0.0)
            .chain(self.t[..self.n].iter().copied())
            .chain(std::iter::once(1.0));
        ends.clone().zip(ends.skip(1)).filter(|(t0, t1)| t1 > t0)
    }
}

/// The intervals of the shutter [0, 1] during which the point moving linearly from `p0`
/// (t = 0) to `p1` (t = 1) does not see `light`: its shadow ray at time t (as `shade.rs`
/// casts it) meets a triangle other than the one with id `skip` (the receiver's own) at that
/// time. Sorted, disjoint, merged.
pub fn shadowed_intervals(
    bvh: &Bvh,
    light: &ShadingLight,
    p0: DVec3,
    p1: DVec3,
    skip: u32,
) -> Vec<(f64, f64)> {
    let query = Query::new(light, p0, p1);
    let mut intervals = Vec::new();
    bvh.visit_swept(
        |lo0, hi0, lo1, hi1| query.may_reach(lo0, hi0, lo1, hi1),
        |_, tri| {
            if tri.id == skip {
                return false;
            }
            let [(lo0, hi0), (lo1, hi1)] = tri.end_bounds();
            if !query.may_reach(lo0, hi0, lo1, hi1) {
                return false;
            }
            let before = intervals.len();
            query.shadow_of(tri, &mut intervals);
            // Stop once the shadow covers the whole shutter (a point inside a closed mesh's
            // shadow is covered by one moving triangle after another).
            intervals.len() > before && merge(&mut intervals) == [(0.0, 1.0)]
        },
    );
    merge(&mut intervals);
    intervals
}

/// Sorts and merges intervals in place: overlapping ones, and those less than `JOIN` apart
/// (where the ray passes from one triangle to its neighbour, the two ends are roots of two
/// polynomials of the same edge, rounded differently: a gap of ~1e-15 that is not light).
fn merge(intervals: &mut Vec<(f64, f64)>) -> &[(f64, f64)] {
    intervals.sort_unstable_by(|x, y| x.0.total_cmp(&y.0));
    let mut n = 0;
    for i in 0..intervals.len() {
        let (a, b) = intervals[i];
        if n > 0 && a <= intervals[n - 1].1 + JOIN {
            intervals[n - 1].1 = intervals[n - 1].1.max(b);
        } else {
            intervals[n] = (a, b);
            n += 1;
        }
    }
    intervals.truncate(n);
    // Likewise at the shutter's ends.
    if let Some(first) = intervals.first_mut() {
        if first.0 < JOIN {
            first.0 = 0.0;
        }
    }
    if let Some(last) = intervals.last_mut() {
        if last.1 > 1.0 - JOIN {
            last.1 = 1.0;
        }
    }
    intervals
}

/// The share of the shutter during which the point moving linearly from `p0` to `p1` sees
/// `light` (1 - the measure of [`shadowed_intervals`]). The directional shadow ray's epsilon
/// scales with the scene size given to [`ShadingLight::new`].
pub fn lit_fraction(bvh: &Bvh, light: &ShadingLight, p0: DVec3, p1: DVec3, skip: u32) -> f64 {
    let shadowed: f64 = shadowed_intervals(bvh, light, p0, p1, skip)
        .iter()
        .map(|(a, b)| b - a)
        .sum();
    (1.0 - shadowed).max(0.0)
}
