//! Whether a `closed` mesh may really be back-face culled this frame.
//!
//! The renderer skips the triangles of a closed mesh that face away from the light (shadow
//! pass) or the camera (lighting pass) all frame long. That is exact only while the point
//! looked from is outside the mesh: from inside, the faces turned away are the ones that
//! block (a light inside a closed box would light the whole floor through it; a camera inside
//! one would see nothing of it). Culling is only an optimisation, so such a mesh is simply
//! treated as open for the frame.
//!
//! The test is exact for the scene's linear motion: the point is inside the mesh at some
//! time of the shutter iff it is inside at t = 0 (generalised winding number) or the surface
//! passes through it at some t in [0, 1] (a root of a triangle's plane equation, which is a
//! cubic in t, with the point inside that triangle then). Touching counts as inside.

use glam::{DVec3, Vec3};

use super::{Light, Mesh, Scene};

/// A closed mesh that must be drawn without culling, and why.
#[derive(Debug, Clone, PartialEq)]
pub struct CullingException {
    /// Index into `Scene::meshes`.
    pub mesh: usize,
    /// `"the spot light"` or `"the camera"`.
    pub viewpoint: &'static str,
}

impl CullingException {
    /// A one-line note for progress output.
    pub fn note(&self, scene: &Scene) -> String {
        let name = scene.meshes.get(self.mesh).map_or("", |m| m.name.as_str());
        format!(
            "mesh #{} ({:?}) is closed but contains {} during the shutter: drawn without \
             back-face culling",
            self.mesh,
            super::clip::quoted(name),
            self.viewpoint
        )
    }
}

/// The closed meshes that contain (or touch) the spot light's position or the camera's
/// position at some time of the shutter (a moving light or camera where it is at that time). A
/// directional light has no position.
pub fn culling_exceptions(scene: &Scene) -> Vec<CullingException> {
    let c = &scene.camera;
    let camera_moved = c.t1.map_or(Vec3::ZERO, |end| end.position - c.position);
    let mut viewpoints = vec![("the camera", c.position, camera_moved)];
    if let Light::Spot(s) = &scene.light {
        let moved = s.t1.map_or(Vec3::ZERO, |end| end.position - s.position);
        viewpoints.insert(0, ("the spot light", s.position, moved));
    }
    let mut found = Vec::new();
    for (index, mesh) in scene.meshes.iter().enumerate() {
        if !mesh.closed {
            continue;
        }
        if let Some(&(viewpoint, _, _)) = viewpoints
            .iter()
            .find(|(_, p, moved)| contains_during_shutter(&relative(mesh, *moved), *p))
        {
            found.push(CullingException {
                mesh: index,
                viewpoint,
            });
        }
    }
    found
}

/// `mesh` as seen from a point that moves by `moved` over the shutter, from where it stands
/// at t = 0: its t = 1 positions moved back by `moved` (the relative motion stays linear).
fn relative(mesh: &Mesh, moved: Vec3) -> std::borrow::Cow<'_, Mesh> {
    if moved == Vec3::ZERO {
        return std::borrow::Cow::Borrowed(mesh);
    }
    let mut shifted = mesh.clone();
    shifted.t1.iter_mut().for_each(|p| *p -= moved);
    std::borrow::Cow::Owned(shifted)
}

/// Per mesh, whether the renderer may treat it as closed (cull its back faces) this frame:
/// `mesh.closed`, cleared for the meshes of [`culling_exceptions`].
pub fn effective_closed(scene: &Scene) -> Vec<bool> {
    let mut closed: Vec<bool> = scene.meshes.iter().map(|m| m.closed).collect();
    for e in culling_exceptions(scene) {
        closed[e.mesh] = false;
    }
    closed
}

/// Whether `p` is inside (or on) `mesh` at some time t in [0, 1].
pub fn contains_during_shutter(mesh: &Mesh, p: Vec3) -> bool {
    let p = p.as_dvec3();
    // Vertices move linearly, so the mesh stays inside the box of its t0 and t1 positions.
    let (lo, hi) = mesh
        .t0
        .iter()
        .chain(&mesh.t1)
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v.as_dvec3()), hi.max(v.as_dvec3()))
        });
    let margin = 1e-6 * (hi - lo).max_element().max(p.abs().max_element()).max(1.0);
    if p.cmplt(lo - margin).any() || p.cmpgt(hi + margin).any() {
        return false;
    }
    let triangles = || {
        mesh.t0
            .chunks_exact(3)
            .zip(mesh.t1.chunks_exact(3))
            .map(move |(a, b)| {
                let rel = |v: Vec3| v.as_dvec3() - p;
                (
                    [rel(a[0]), rel(a[1]), rel(a[2])],
                    [
                        rel(b[0]) - rel(a[0]),
                        rel(b[1]) - rel(a[1]),
                        rel(b[2]) - rel(a[2]),
                    ],
                )
            })
    };
    let winding: f64 =
        triangles().map(|(v, _)| solid_angle(v)).sum::<f64>() / (4.0 * std::f64::consts::PI);
    winding.abs() >= 0.5 || triangles().any(|(v, d)| passes_through_origin(v, d))
}

/// Signed solid angle of triangle `v` seen from the origin (Van Oosterom & Strackee).
fn solid_angle([a, b, c]: [DVec3; 3]) -> f64 {
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let det = a.dot(b.cross(c));
    let denom = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    2.0 * det.atan2(denom)
}

/// Whether the triangle with vertices `v + t d` contains the origin for some t in [0, 1].
/// Its plane holds the origin where det(v0 + t d0, v1 + t d1, v2 + t d2) = 0, a cubic in t.
fn passes_through_origin(v: [DVec3; 3], d: [DVec3; 3]) -> bool {
    let [a0, b0, c0] = v;
    let [a1, b1, c1] = d;
    let coefficients = [
        a0.dot(b0.cross(c0)),
        a0.dot(b0.cross(c1) + b1.cross(c0)) + a1.dot(b0.cross(c0)),
        a0.dot(b1.cross(c1)) + a1.dot(b0.cross(c1) + b1.cross(c0)),
        a1.dot(b1.cross(c1)),
    ];
    let at = |t: f64| [a0 + a1 * t, b0 + b1 * t, c0 + c1 * t];
    roots_in_unit_interval(coefficients)
        .into_iter()
        .any(|t| contains_origin(at(t)))
}

/// Whether the origin, lying (nearly) in the triangle's plane, is inside the triangle or on
/// its boundary (a little tolerance: touching counts).
fn contains_origin([a, b, c]: [DVec3; 3]) -> bool {
    let n = (b - a).cross(c - a);
    let area2 = n.length_squared();
    if area2 == 0.0 {
        return false;
    }
    let tolerance = -1e-9 * area2;
    // Each edge sees the origin on the triangle's side (signed areas of the sub-triangles).
    [(a, b), (b, c), (c, a)]
        .iter()
        .all(|&(p, q)| p.cross(q).dot(n) >= tolerance)
}

/// The t in [0, 1] where c0 + c1 t + c2 t^2 + c3 t^3 = 0 (bisection on monotone pieces;
/// also t where the cubic only touches zero). An identically zero cubic gives samples.
fn roots_in_unit_interval(c: [f64; 4]) -> Vec<f64> {
    let f = |t: f64| ((c[3] * t + c[2]) * t + c[1]) * t + c[0];
    let scale = c.iter().map(|x| x.abs()).fold(0.0, f64::max);
    if scale == 0.0 {
        return (0..=8).map(|i| f64::from(i) / 8.0).collect();
    }
    // Split [0, 1] where the derivative c1 + 2 c2 t + 3 c3 t^2 vanishes.
    let mut cuts = vec![0.0, 1.0];
    let (qa, qb, qc) = (3.0 * c[3], 2.0 * c[2], c[1]);
    if qa.abs() > 1e-300 {
        let disc = qb * qb - 4.0 * qa * qc;
        if disc >= 0.0 {
            let s = disc.sqrt();
            cuts.extend([(-qb - s) / (2.0 * qa), (-qb + s) / (2.0 * qa)]);
        }
    } else if qb.abs() > 1e-300 {
        cuts.push(-qc / qb);
    }
    cuts.retain(|t| (0.0..=1.0).contains(t));
    cuts.sort_by(f64::total_cmp);
    let near_zero = |t: f64| f(t).abs() <= 1e-12 * scale;
    let mut roots: Vec<f64> = cuts.iter().copied().filter(|&t| near_zero(t)).collect();
    for pair in cuts.windows(2) {
        let (mut lo, mut hi) = (pair[0], pair[1]);
        if f(lo).signum() == f(hi).signum() {
            continue;
        }
        for _ in 0..80 {
            let mid = 0.5 * (lo + hi);
            if f(mid).signum() == f(lo).signum() {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        roots.push(0.5 * (lo + hi));
    }
    roots
}

#[cfg(test)]
mod tests {
    use super::super::{BuiltinOptions, box_mesh, builtin};
    use super::*;

    fn unit_box(t0: Vec3, t1: Vec3) -> Mesh {
        let local = box_mesh(Vec3::ONE, 2);
        Mesh {
            name: "box".into(),
            albedo: Vec3::splat(0.5),
            closed: true,
            t0: local.iter().map(|&p| p + t0).collect(),
            t1: local.iter().map(|&p| p + t1).collect(),
        }
    }

    #[test]
    fn static_box_contains_its_inside_only() {
        let b = unit_box(Vec3::ZERO, Vec3::ZERO);
        for inside in [Vec3::ZERO, Vec3::splat(0.49), Vec3::new(-0.3, 0.1, 0.45)] {
            assert!(contains_during_shutter(&b, inside), "{inside}");
        }
        // On a face, an edge or a corner: touching counts.
        for on in [
            Vec3::new(0.5, 0.1, 0.2),
            Vec3::new(0.5, 0.5, 0.0),
            Vec3::splat(-0.5),
        ] {
            assert!(contains_during_shutter(&b, on), "{on}");
        }
        for outside in [
            Vec3::splat(0.51),
            Vec3::new(0.0, 0.0, 0.6),
            Vec3::new(3.0, 0.0, 0.0),
        ] {
            assert!(!contains_during_shutter(&b, outside), "{outside}");
        }
    }

    #[test]
    fn moving_box_is_caught_when_it_passes_over_the_point_mid_shutter() {
        // From x = -3 to x = +3: outside the point at both ends, over it at t = 0.5.
        let b = unit_box(Vec3::new(-3.0, 0.0, 0.0), Vec3::new(3.0, 0.0, 0.0));
        assert!(contains_during_shutter(&b, Vec3::ZERO));
        assert!(contains_during_shutter(&b, Vec3::new(2.9, 0.2, -0.2)));
        assert!(!contains_during_shutter(&b, Vec3::new(3.6, 0.0, 0.0)));
        // Diagonally: the point is inside the box the motion sweeps, but off the path.
        let d = unit_box(Vec3::new(-3.0, -3.0, 0.0), Vec3::new(3.0, 3.0, 0.0));
        assert!(!contains_during_shutter(&d, Vec3::new(2.0, -2.0, 0.0)));
        assert!(contains_during_shutter(&d, Vec3::new(2.0, 2.2, 0.1)));
    }

    #[test]
    fn builtin_scenes_keep_their_culling() {
        for name in super::super::BUILTIN_NAMES {
            let s = builtin(
                name,
                &BuiltinOptions {
                    cube_count: 300,
                    ..Default::default()
                },
            )
            .unwrap();
            assert_eq!(culling_exceptions(&s), [], "{name}");
        }
    }

    #[test]
    fn a_moving_light_passing_through_a_still_box_opens_it() {
        let mut s = builtin("moving-light", &BuiltinOptions::default()).unwrap();
        let Light::Spot(light) = &s.light else {
            panic!("spot expected")
        };
        let (start, end) = (light.position, light.t1.unwrap().position);
        let post = s.meshes.iter().position(|m| m.name == "post-0").unwrap();
        // Still, halfway along the light's path: outside it at t = 0 and t = 1, not between.
        let halfway = unit_box(0.5 * (start + end), 0.5 * (start + end));
        s.meshes[post].t0 = halfway.t0;
        s.meshes[post].t1 = halfway.t1;
        let exceptions = culling_exceptions(&s);
        let expected = CullingException {
            mesh: post,
            viewpoint: "the spot light",
        };
        assert_eq!(exceptions, [expected]);
    }

    #[test]
    fn the_mesh_around_the_light_or_camera_is_opened_and_named() {
        let mut s = builtin("cubes-toward-light", &BuiltinOptions::default()).unwrap();
        let Light::Spot(light) = &s.light else {
            panic!("spot expected")
        };
        let pillar = s.meshes.iter().position(|m| m.name == "pillar").unwrap();
        let around = |p: Vec3| unit_box(p, p).t0;
        s.meshes[pillar].t0 = around(light.position);
        s.meshes[pillar].t1 = around(light.position);
        let cubes = s.meshes.iter().position(|m| m.name == "cube-left").unwrap();
        s.meshes[cubes].t0 = around(Vec3::new(-2.0, 4.0, 0.5));
        s.meshes[cubes].t1 = around(s.camera.position);
        let exceptions = culling_exceptions(&s);
        assert_eq!(
            exceptions,
            [
                CullingException {
                    mesh: cubes,
                    viewpoint: "the camera"
                },
                CullingException {
                    mesh: pillar,
                    viewpoint: "the spot light"
                },
            ]
        );
        let closed = effective_closed(&s);
        assert!(!closed[pillar] && !closed[cubes]);
        assert!(
            s.meshes
                .iter()
                .zip(&closed)
                .filter(|(m, _)| m.name.starts_with("cube-right"))
                .all(|(_, &c)| c)
        );
        assert!(exceptions[1].note(&s).contains("\"pillar\""));
        // Opened, the meshes raise no exception any more.
        for e in &exceptions {
            s.meshes[e.mesh].closed = false;
        }
        assert_eq!(culling_exceptions(&s), []);
        assert_eq!(
            effective_closed(&s),
            s.meshes.iter().map(|m| m.closed).collect::<Vec<_>>()
        );
    }

    #[test]
    fn cubic_roots() {
        // (t - 0.25)(t - 0.5)(t - 2) = t^3 - 2.75 t^2 + 1.625 t - 0.25
        let roots = roots_in_unit_interval([-0.25, 1.625, -2.75, 1.0]);
        assert_eq!(roots.len(), 2, "{roots:?}");
        assert!((roots[0] - 0.25).abs() < 1e-12 && (roots[1] - 0.5).abs() < 1e-12);
        // A double root (touching): (t - 0.5)^2 = t^2 - t + 0.25.
        let roots = roots_in_unit_interval([0.25, -1.0, 1.0, 0.0]);
        assert!(roots.iter().any(|t| (t - 0.5).abs() < 1e-9), "{roots:?}");
        assert!(roots_in_unit_interval([1.0, 0.0, 0.0, 0.0]).is_empty());
    }
}
