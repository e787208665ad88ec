//! `hard-rotating-triangle`: one triangle turning 90 degrees in its own plane, the plane
//! facing the light, above a ground plane.
//!
//! A prism side is the surface an edge sweeps; the papers' four triangles around its centre
//! vertex give exact times only when the edge translates. Here every edge turns.
//!
//! The motion, exactly: the t0 pose is the triangle at angle 0, the t1 pose the same
//! triangle turned 90 degrees about the plane's normal through its centroid, and every
//! vertex moves on the chord between the two. So at time t the triangle is the t0 triangle
//! turned by atan(t / (1 - t)) (not 90 t degrees) and scaled about the centroid by
//! sqrt(t^2 + (1 - t)^2): at t = 0.5 it has turned 45 degrees at 0.707 of its size. It
//! stays in its plane and its centroid stays put.

use glam::Vec3;

use super::super::file::{SceneFile, TransformFile};
use super::super::parts::{ground, object};
use super::{camera, scene_file, spot, triangles, turn};

const LIGHT: Vec3 = Vec3::new(-3.0, 9.0, 2.0);
/// The triangle's centroid.
const CENTRE: Vec3 = Vec3::new(0.0, 3.0, 0.0);
/// Distance from the centroid to each corner.
const RADIUS: f32 = 1.6;
const TURN_DEG: f32 = 90.0;

/// The plane's normal: toward the light.
fn normal() -> Vec3 {
    (LIGHT - CENTRE).normalize()
}

/// The corners at angle `deg` in the plane, counter-clockwise about the normal (so the
/// front face looks at the light).
fn corners(deg: f32) -> Vec<Vec3> {
    let n = normal();
    let u = n.cross(Vec3::Z).normalize();
    let v = n.cross(u);
    (0..3)
        .map(|k| {
            let a = (90.0 + 120.0 * k as f32).to_radians();
            CENTRE + turn(n, deg) * (u * a.cos() + v * a.sin()) * RADIUS
        })
        .collect()
}

pub(super) fn scene() -> SceneFile {
    // The light's ray through the centroid meets the ground here: aim the cone at it.
    let aim = LIGHT + (CENTRE - LIGHT) * (LIGHT.y / (LIGHT.y - CENTRE.y));
    scene_file(
        "hard-rotating-triangle",
        camera(Vec3::new(4.0, 7.4, 7.7), Vec3::new(1.3, 1.9, -1.2)),
        spot(LIGHT, aim, 35.0, 1.0, 30.0),
        vec![
            ground(16.0, 8),
            object(
                "triangle",
                Vec3::new(0.85, 0.4, 0.2),
                false,
                triangles(corners(0.0), corners(TURN_DEG)),
                TransformFile::default(),
                None,
            ),
        ],
    )
}

#[cfg(test)]
mod tests {
    use super::super::check::{centre, mesh, scene};
    use super::*;

    /// The triangle faces the light, stays in its plane, and its t1 pose is its t0 pose
    /// turned 90 degrees about the normal through the (static) centroid; mid-shutter it is
    /// the chord blend: turned 45 degrees, at 0.707 of its size.
    #[test]
    fn the_triangle_turns_90_degrees_in_its_plane_facing_the_light() {
        let s = scene("hard-rotating-triangle");
        let tri = mesh(&s, "triangle");
        assert_eq!(tri.triangle_count(), 1);
        let (c0, c1) = (centre(&tri.t0), centre(&tri.t1));
        assert!((c0 - CENTRE).length() < 1e-5 && (c1 - CENTRE).length() < 1e-5);
        let n = normal();
        let face = (tri.t0[1] - tri.t0[0])
            .cross(tri.t0[2] - tri.t0[0])
            .normalize();
        assert!(
            (face - n).length() < 1e-5,
            "front face toward the light: {face}"
        );
        let crate::scene::Light::Spot(light) = &s.light else {
            panic!("spot expected")
        };
        assert!((light.position - CENTRE).normalize().dot(n) > 0.9999);
        for (&a, &b) in tri.t0.iter().zip(&tri.t1) {
            // In the plane at both ends (so at every time).
            assert!((a - CENTRE).dot(n).abs() < 1e-5 && (b - CENTRE).dot(n).abs() < 1e-5);
            // Same distance from the centroid, turned +90 degrees about the normal.
            let (ra, rb) = (a - CENTRE, b - CENTRE);
            assert!((ra.length() - RADIUS).abs() < 1e-5 && (rb.length() - RADIUS).abs() < 1e-5);
            assert!(ra.dot(rb).abs() < 1e-5, "not a quarter turn");
            assert!(
                ra.cross(rb).normalize().dot(n) > 0.9999,
                "turns the wrong way"
            );
            // Mid-shutter (linear motion): 45 degrees, radius scaled by cos 45.
            let mid = (a + b) * 0.5 - CENTRE;
            assert!((mid.length() - RADIUS * 0.5_f32.sqrt()).abs() < 1e-5);
            assert!((mid.normalize().dot(ra.normalize()) - 0.5_f32.sqrt()).abs() < 1e-5);
        }
    }
}
