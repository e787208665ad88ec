//! The configurations the probe runs: random ones and the adversarial classes, each with the
//! scene it builds.

use super::*;

pub(super) fn v(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(x, y, z)
}

/// Two triangles per quad `a b c d` (counter-clockwise), split along a-c.
pub(super) fn quad(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> [[Vec3; 3]; 2] {
    [[a, b, c], [a, c, d]]
}

/// A closed box's 12 triangles, consistently wound, each face split along the diagonal
/// from its corner of least x + z (the top and bottom ones along x = z).
pub(super) fn boxed(lo: Vec3, hi: Vec3) -> Vec<[Vec3; 3]> {
    let c = |x: bool, y: bool, z: bool| {
        v(
            if x { hi.x } else { lo.x },
            if y { hi.y } else { lo.y },
            if z { hi.z } else { lo.z },
        )
    };
    let faces = [
        quad(
            c(false, true, false),
            c(false, true, true),
            c(true, true, true),
            c(true, true, false),
        ),
        quad(
            c(false, false, false),
            c(true, false, false),
            c(true, false, true),
            c(false, false, true),
        ),
        quad(
            c(false, false, false),
            c(false, false, true),
            c(false, true, true),
            c(false, true, false),
        ),
        quad(
            c(true, false, false),
            c(true, true, false),
            c(true, true, true),
            c(true, false, true),
        ),
        quad(
            c(false, false, false),
            c(false, true, false),
            c(true, true, false),
            c(true, false, false),
        ),
        quad(
            c(false, false, true),
            c(true, false, true),
            c(true, true, true),
            c(false, true, true),
        ),
    ];
    faces.into_iter().flatten().collect()
}

pub(super) fn moving(at0: &[[Vec3; 3]], by: Vec3) -> Vec<[[Vec3; 3]; 2]> {
    at0.iter().map(|t| [*t, t.map(|p| p + by)]).collect()
}

pub(super) fn config(class: &'static str, p0: Vec3, p1: Vec3, spot: bool, light: Vec3) -> Config {
    Config {
        class,
        p0,
        p1,
        spot,
        light,
        triangles: Vec::new(),
        window: (0.0, 1.0),
        closed_form: None,
    }
}

pub(super) fn random_configs(rng: &mut Rng, n: usize) -> Vec<Config> {
    let mut r = |lo: f32, hi: f32| lo + (hi - lo) * rng.unit();
    (0..n)
        .map(|i| {
            let spot = i % 2 == 0;
            let p0 = v(r(-1.0, 1.0), r(-0.2, 0.2), r(-1.0, 1.0));
            let p1 = if i % 4 < 2 {
                p0
            } else {
                p0 + v(r(-0.5, 0.5), r(-0.1, 0.1), r(-0.5, 0.5))
            };
            let light = if spot {
                p0 + v(r(-2.0, 2.0), r(4.0, 6.0), r(-2.0, 2.0))
            } else {
                v(r(-0.5, 0.5), -1.0, r(-0.5, 0.5))
            };
            let toward = if spot {
                (light - p0).normalize()
            } else {
                -light.normalize()
            };
            let mut c = config("random", p0, p1, spot, light);
            for _ in 0..1 + i % 4 {
                let centre = p0 + toward * r(0.5, 3.0) + v(r(-0.6, 0.6), 0.0, r(-0.6, 0.6));
                let at0: [Vec3; 3] =
                    std::array::from_fn(|_| centre + v(r(-0.8, 0.8), r(-0.3, 0.3), r(-0.8, 0.8)));
                let drift = v(r(-1.0, 1.0), r(-0.3, 0.3), r(-1.0, 1.0));
                let at1 = at0.map(|p| p + drift + v(r(-0.3, 0.3), r(-0.3, 0.3), r(-0.3, 0.3)));
                c.triangles.push([at0, at1]);
            }
            if i % 8 == 7 {
                let a = r(0.0, 0.6);
                c.window = (a, a + r(0.1, 0.4));
                c.class = "random, window";
            }
            c
        })
        .collect()
}

/// Scissors: a triangle with a still corner C = (-2, 1, 0) and two corners at x = 2 moving
/// across z = 0 in opposite directions at different times (A: z = 1 - 2t, B: z = -1 + 4t),
/// over a receiver at the origin: the ray (x = z = 0) lies between the lines CA and CB while
/// (1 - 2t)(-1 + 4t) <= 0, i.e. two intervals, [0, 1/4] and [1/2, 1]. Then random
/// scissors (corners crossing at random times, the receiver still or moving), for the
/// tracer and sampling only.
pub(super) fn scissor_configs(rng: &mut Rng) -> Vec<Config> {
    let at0 = [v(-2.0, 1.0, 0.0), v(2.0, 1.0, 1.0), v(2.0, 1.0, -1.0)];
    let at1 = [v(-2.0, 1.0, 0.0), v(2.0, 1.0, -1.0), v(2.0, 1.0, 3.0)];
    let mut out = Vec::new();
    for (spot, light) in [(false, v(0.0, -1.0, 0.0)), (true, v(0.0, 10.0, 0.0))] {
        let mut c = config("scissors", Vec3::ZERO, Vec3::ZERO, spot, light);
        c.triangles = vec![[at0, at1]];
        c.closed_form = Some(vec![(0.0, 0.25), (0.5, 1.0)]);
        out.push(c);
    }
    let mut r = |lo: f32, hi: f32| lo + (hi - lo) * rng.unit();
    for i in 0..64 {
        let spot = i % 2 == 0;
        let p0 = v(r(-0.3, 0.3), 0.0, r(-0.3, 0.3));
        let p1 = if i % 4 < 2 {
            p0
        } else {
            p0 + v(r(-0.3, 0.3), 0.0, r(-0.3, 0.3))
        };
        let light = if spot {
            v(r(-1.0, 1.0), 10.0, r(-1.0, 1.0))
        } else {
            v(r(-0.2, 0.2), -1.0, r(-0.2, 0.2))
        };
        let (y, ya, yb) = (r(0.5, 2.0), r(-0.5, 0.5), r(-0.5, 0.5));
        let a = r(0.5, 1.5);
        let b = r(0.5, 1.5);
        let at0 = [
            v(-2.0, y, r(-0.2, 0.2)),
            v(2.0, y + ya, a),
            v(2.0, y + yb, -b),
        ];
        let at1 = [
            at0[0],
            v(2.0, y - ya, -a * r(0.5, 2.0)),
            v(2.0, y - yb, b * r(0.5, 2.0)),
        ];
        let mut c = config("scissors, random", p0, p1, spot, light);
        c.triangles = vec![[at0, at1]];
        out.push(c);
    }
    out
}

/// A box translating along x over a receiver: shadowed while its x range holds the ray's x.
pub(super) fn box_edge_configs() -> Vec<Config> {
    let (a, speed) = (-1.3f32, 2.1f32);
    let walls = boxed(v(a, 1.0, -0.5), v(a + 1.0, 2.0, 0.5));
    let mut out = Vec::new();
    for spot in [false, true] {
        // (receiver start, its motion): still; moving along z (the ray keeps x = 0); moving
        // along x at 0.4 (directional only: relative speed 1.7).
        for (p0, m) in [
            (v(0.0, 0.0, 0.0), Vec3::ZERO),
            (v(0.0, 0.0, -0.3), v(0.0, 0.0, 0.6)),
            (v(0.0, 0.0, 0.0), v(0.4, 0.0, 0.0)),
        ] {
            if spot && m.x != 0.0 {
                continue;
            }
            let light = if spot {
                v(0.0, 10.0, 0.0)
            } else {
                v(0.0, -1.0, 0.0)
            };
            let mut c = config("box edge", p0, p0 + m, spot, light);
            c.triangles = moving(&walls, v(speed, 0.0, 0.0));
            let rel = f64::from(speed) - f64::from(m.x);
            let (a, x) = (f64::from(a), f64::from(p0.x));
            c.closed_form = Some(vec![((x - 1.0 - a) / rel, (x - a) / rel)]);
            out.push(c);
        }
    }
    out
}

/// A plate (two triangles) whose right edge swings by 60 degrees about the z axis through
/// (0, 1, 0), corners moving linearly; a spot light at (0, 5, 0) and a receiver at
/// (0.9, 0, 0): shadowed until the swinging edge's corner crosses the ray (closed form: the
/// corner's path is linear, the ray's line fixed).
pub(super) fn rotating_plate_configs() -> Vec<Config> {
    let angle = 60f64.to_radians();
    let (cos, sin) = (angle.cos(), angle.sin());
    let at = |x: f64, y: f64, z: f32| {
        // About (0, 1): (x, y - 1) rotated.
        v(
            (x * cos - (y - 1.0) * sin) as f32,
            (1.0 + x * sin + (y - 1.0) * cos) as f32,
            z,
        )
    };
    let corners0 = [
        v(-1.0, 1.0, -1.0),
        v(1.0, 1.0, -1.0),
        v(1.0, 1.0, 1.0),
        v(-1.0, 1.0, 1.0),
    ];
    let corners1 = [
        at(-1.0, 1.0, -1.0),
        at(1.0, 1.0, -1.0),
        at(1.0, 1.0, 1.0),
        at(-1.0, 1.0, 1.0),
    ];
    let [q0, q1] = [corners0, corners1].map(|c| quad(c[0], c[1], c[2], c[3]));
    let mut c = config(
        "rotating plate",
        v(0.9, 0.0, 0.0),
        v(0.9, 0.0, 0.0),
        true,
        v(0.0, 5.0, 0.0),
    );
    c.triangles = vec![[q0[0], q1[0]], [q0[1], q1[1]]];
    // The right corner R(t) = (1 + t (cos - 1), 1 + t sin) meets the line x / 0.9 + y / 5 = 1.
    let (r1x, r1y) = (f64::from(corners1[1].x), f64::from(corners1[1].y));
    let t = (1.0 - 1.0 / 0.9 - 1.0 / 5.0) / ((r1x - 1.0) / 0.9 + (r1y - 1.0) / 5.0);
    c.closed_form = Some(vec![(0.0, t)]);
    vec![c]
}

/// A horizontal triangle rising through a spot light's height: it blocks only while below
/// the light (s < 1), i.e. while y(t) = 4 + 2 t < 5.
pub(super) fn through_light_configs() -> Vec<Config> {
    let tri = [v(-1.0, 4.0, -1.0), v(1.5, 4.0, -0.5), v(-0.5, 4.0, 1.5)];
    let mut out = Vec::new();
    for (p0, p1) in [
        (Vec3::ZERO, Vec3::ZERO),
        (v(-0.2, 0.0, 0.0), v(0.2, 0.0, 0.1)),
    ] {
        let mut c = config("through spot plane", p0, p1, true, v(0.0, 5.0, 0.0));
        c.triangles = moving(&[tri], v(0.0, 2.0, 0.0));
        // The ray from P(t) meets the plane y(t) at s = y / 5 < 1 iff y < 5.
        c.closed_form = Some(vec![(0.0, 0.5)]);
        out.push(c);
    }
    out
}

/// A receiver whose shadow ray runs through the diagonals x = z that split a closed box's
/// top and bottom faces, still or moving along the diagonal: always shadowed.
pub(super) fn shared_edge_configs() -> Vec<Config> {
    let walls = boxed(v(-1.0, 1.0, -1.0), v(1.0, 2.0, 1.0));
    let mut out = Vec::new();
    for (spot, light) in [
        (false, v(0.0, -1.0, 0.0)),
        (false, v(-1.0, -3.0, -1.0)),
        (true, v(0.3, 10.0, 0.3)),
        (true, v(2.3, 8.0, 2.3)),
    ] {
        for by in [Vec3::ZERO, v(0.5, 0.0, 0.5), v(0.25, 0.75, 0.25)] {
            let p = v(0.3, 0.0, 0.3);
            let mut c = config("shared edge", p, p, spot, light);
            c.triangles = moving(&walls, by);
            c.closed_form = Some(vec![(0.0, 1.0)]);
            out.push(c);
        }
    }
    out
}

/// A tilted flat fan of six triangles (random plane, corners in f32) and a tilted shadow ray
/// through a point Q on one of its inner edges or at its centre (all in f32, so only rounding
/// decides which of the two triangles holds the ray), the fan still or sliding along the ray:
/// the ray meets the fan all shutter long; no light may pass between two triangles.
pub(super) fn rounded_shared_edge_configs(rng: &mut Rng) -> Vec<Config> {
    let mut r = |lo: f64, hi: f64| lo + (hi - lo) * f64::from(rng.unit());
    let mut out = Vec::new();
    for i in 0..200 {
        let normal = DVec3::new(r(-0.6, 0.6), 1.0, r(-0.6, 0.6)).normalize();
        let e1 = DVec3::new(1.0, 0.0, r(-0.3, 0.3)).cross(normal).normalize();
        let e2 = normal.cross(e1);
        let centre = DVec3::new(r(-3.0, 3.0), r(1.0, 3.0), r(-3.0, 3.0));
        let rim: Vec<Vec3> = (0..6)
            .map(|k| {
                let angle = (k as f64 + r(-0.3, 0.3)) * std::f64::consts::TAU / 6.0;
                (centre + r(0.7, 1.3) * (angle.cos() * e1 + angle.sin() * e2)).as_vec3()
            })
            .collect();
        let c = centre.as_vec3();
        let fan: Vec<[Vec3; 3]> = (0..6).map(|k| [c, rim[k], rim[(k + 1) % 6]]).collect();
        let q = if i % 10 == 0 {
            c
        } else {
            let (k, lambda) = (i % 6, r(0.05, 0.95) as f32);
            c + lambda * (rim[k] - c)
        };
        // The ray's direction, tilted: an axis-aligned one would make the two triangles'
        // products of an edge equal by symmetry alone.
        let up = DVec3::new(r(-0.5, 0.5), 1.0, r(-0.5, 0.5)).normalize();
        let p = (q.as_dvec3() - r(0.5, 2.0) * up).as_vec3();
        let (spot, light) = if i % 2 == 0 {
            (false, (-up).as_vec3())
        } else {
            (true, (q.as_dvec3() + 5.0 * up).as_vec3())
        };
        let mut c = config("shared edge, rounded", p, p, spot, light);
        let slide = if i % 4 < 2 { 0.0 } else { r(-0.4, 0.4) };
        c.triangles = moving(&fan, (slide * up).as_vec3());
        c.closed_form = Some(vec![(0.0, 1.0)]);
        out.push(c);
    }
    out
}

/// Triangles in the plane x = 0.25 with the receiver in it too, so the ray lies in their
/// plane (E = 0): no shadow. Dyadic coordinates: every product exact in f32 and f64.
pub(super) fn edge_on_configs() -> Vec<Config> {
    let tri = [v(0.25, 1.0, -1.0), v(0.25, 1.0, 1.0), v(0.25, 2.0, 0.0)];
    let p = v(0.25, 0.0, 0.0);
    let mut out = Vec::new();
    for (spot, light) in [(false, v(0.0, -1.0, 0.0)), (true, v(0.25, 5.0, 0.5))] {
        for by in [Vec3::ZERO, v(0.0, 0.5, 0.75)] {
            let mut c = config("edge-on", p, p, spot, light);
            c.triangles = moving(&[tri], by);
            c.closed_form = Some(Vec::new());
            out.push(c);
        }
    }
    out
}

/// The union past its capacity: ten triangles cross a still receiver's ray one after the
/// other (each covers it for 0.04, apart by unequal gaps), more disjoint intervals than the
/// union's 8 slots. Added in order, the ninth is joined with the eighth (its nearest) and the
/// tenth with that pair: the union shadows those two gaps and says so (`joined_gaps`), and
/// keeps every other interval as it was.
pub(super) fn past_capacity_configs() -> Vec<Config> {
    let (length, count) = (0.04f32, 10usize);
    let gaps: Vec<f32> = (0..count - 1)
        .map(|k| 0.03 + 0.004 * ((k * 7) % 10) as f32)
        .collect();
    let mut starts = vec![0.01f32];
    for gap in &gaps {
        starts.push(starts.last().unwrap() + length + gap);
    }
    let mut out = Vec::new();
    for (spot, light) in [(false, v(0.0, -1.0, 0.0)), (true, v(0.0, 8.0, 0.0))] {
        let mut c = config(PAST_CAPACITY, Vec3::ZERO, Vec3::ZERO, spot, light);
        for (k, &start) in starts.iter().enumerate() {
            // At z = 0 the triangle spans x in [x0, x0 + 2w] (its apex at x0 + 2w); moving by
            // +1 in x it covers x = 0 during [-x0 - 2w, -x0]. Under the spot light its shadow
            // is wider by the height's share: its corners are scaled to keep the interval.
            let y = 1.0 + 0.1 * k as f32;
            let scale = if spot { (8.0 - y) / 8.0 } else { 1.0 };
            let x0 = -(start + length);
            let tri = [v(x0, y, -1.0), v(x0, y, 1.0), v(x0 + length, y, 0.0)]
                .map(|p| v(p.x * scale, p.y, p.z));
            c.triangles.extend(moving(&[tri], v(scale, 0.0, 0.0)));
        }
        let mut expected: Vec<(f64, f64)> = starts[..count - 3]
            .iter()
            .map(|&s| (f64::from(s), f64::from(s + length)))
            .collect();
        expected.push((
            f64::from(starts[count - 3]),
            f64::from(starts[count - 1] + length),
        ));
        c.closed_form = Some(expected);
        out.push(c);
    }
    out
}

/// The class whose union overflows on purpose (past_capacity_configs).
pub(super) const PAST_CAPACITY: &str = "union past its capacity";

/// A tilted ground of four triangles around a centre; the receiver on triangle 0 (left out,
/// as the caller leaves out its own), on its edge shared with triangle 1, at the shared
/// centre, or inside near that edge, in f32 as a G-buffer would give it: no shadow from its
/// coplanar neighbours, at light angles down to 3 degrees above the surface.
pub(super) fn own_surface_configs() -> Vec<Config> {
    let normal = DVec3::new(0.1, 1.0, 0.2).normalize();
    let e1 = DVec3::X.cross(normal).normalize();
    let e2 = normal.cross(e1);
    let origin = DVec3::new(0.37, 0.11, -0.23);
    let at = |a: f64, b: f64| (origin + a * e1 + b * e2).as_vec3();
    let centre = at(0.0, 0.0);
    let rim = [at(1.0, 0.0), at(0.0, 1.0), at(-1.0, 0.0), at(0.0, -1.0)];
    let fan: Vec<[Vec3; 3]> = (0..4).map(|i| [centre, rim[i], rim[(i + 1) % 4]]).collect();
    let mut out = Vec::new();
    for elevation in [45f64, 10.0, 3.0] {
        for azimuth in [0.3f64, 2.0, 4.0] {
            let (el, az) = (elevation.to_radians(), azimuth);
            let to_light = normal * el.sin() + (e1 * az.cos() + e2 * az.sin()) * el.cos();
            // Receivers on triangle 0 (centre, rim 0, rim 1): on the edge centre-rim 1 that
            // triangle 1 shares, at the centre, inside near the edge.
            let points = [
                (centre + rim[1]) * 0.5,
                centre,
                centre * 0.5 + rim[0] * 0.01 + rim[1] * 0.49,
            ];
            for (k, p) in points.into_iter().enumerate() {
                for by in [Vec3::ZERO, v(0.3, -0.2, 0.1)] {
                    let spot = k % 2 == 0;
                    let light = if spot {
                        p + (to_light * 6.0).as_vec3()
                    } else {
                        (-to_light).as_vec3()
                    };
                    let mut c = config("own surface", p, p + by, spot, light);
                    c.triangles = moving(&fan[1..], by);
                    c.closed_form = Some(Vec::new());
                    out.push(c);
                }
            }
        }
    }
    out
}
