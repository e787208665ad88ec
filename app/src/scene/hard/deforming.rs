//! `hard-deforming`: a sheet (a 32 x 32 grid, 2,048 triangles) hanging flat in the air with
//! a wave running across it, lit obliquely from above so that its ripples move its shadow.
//!
//! No part of the sheet moves rigidly: neighbouring vertices move by different amounts, so
//! its triangles stretch, shrink and tilt, and the prisms they sweep are neither
//! translations nor rotations.
//!
//! The motion, exactly: vertex (x, z) of the sheet is at height `HEIGHT + A sin(k s + phase)`
//! with s its coordinate along the wave's direction; the t0 pose has phase 0, the t1 pose
//! phase pi/2 (the wave runs a quarter wavelength), and every vertex moves straight up or
//! down between them. Mid-shutter the blend of the two is the same wave at phase pi/4 with
//! amplitude A cos(pi/4) = 0.707 A: a travelling wave that flattens a little mid-frame.

use glam::{Vec2, Vec3};

use super::super::file::{SceneFile, TransformFile};
use super::super::parts::{ground, object};
use super::{camera, scene_file, spot, triangles};

const LIGHT: Vec3 = Vec3::new(-3.0, 8.0, 2.0);
/// The sheet's centre (its rest height is `CENTRE.y`).
const CENTRE: Vec3 = Vec3::new(0.0, 2.2, -0.2);
const SIZE: f32 = 3.2;
const QUADS: usize = 32;
const AMPLITUDE: f32 = 0.3;
const WAVELENGTH: f32 = 1.6;
/// The wave runs along this horizontal direction (x turned 20 degrees toward z).
const WAVE_DEG: f32 = 20.0;
const PHASES: [f32; 2] = [0.0, std::f32::consts::FRAC_PI_2];

/// Height of the sheet above `CENTRE.y` at horizontal offset `p` from the centre.
fn wave(p: Vec2, phase: f32) -> f32 {
    let along = Vec2::from_angle(WAVE_DEG.to_radians()).dot(p);
    AMPLITUDE * (std::f32::consts::TAU / WAVELENGTH * along + phase).sin()
}

/// The sheet's triangles at `phase`, counter-clockwise seen from above.
fn sheet(phase: f32) -> Vec<Vec3> {
    let point = |i: usize, j: usize| {
        let p = (Vec2::new(i as f32, j as f32) / QUADS as f32 - 0.5) * SIZE;
        CENTRE + Vec3::new(p.x, wave(p, phase), p.y)
    };
    let mut out = Vec::with_capacity(6 * QUADS * QUADS);
    for i in 0..QUADS {
        for j in 0..QUADS {
            let (p00, p10, p11, p01) = (
                point(i, j),
                point(i + 1, j),
                point(i + 1, j + 1),
                point(i, j + 1),
            );
            out.extend_from_slice(&[p00, p11, p10, p00, p01, p11]);
        }
    }
    out
}

pub(super) fn scene() -> SceneFile {
    let aim = LIGHT + (CENTRE - LIGHT) * (LIGHT.y / (LIGHT.y - CENTRE.y));
    scene_file(
        "hard-deforming",
        camera(Vec3::new(2.55, 6.25, 6.7), Vec3::new(1.05, 1.25, -1.05)),
        spot(LIGHT, aim, 35.0, 1.0, 30.0),
        vec![
            ground(16.0, 8),
            object(
                "sheet",
                Vec3::new(0.3, 0.6, 0.35),
                false,
                triangles(sheet(PHASES[0]), sheet(PHASES[1])),
                TransformFile::default(),
                None,
            ),
        ],
    )
}

#[cfg(test)]
mod tests {
    use super::super::check::{mesh, scene};
    use super::*;

    fn normal(t: &[Vec3]) -> Vec3 {
        (t[1] - t[0]).cross(t[2] - t[0]).normalize()
    }

    /// Vertices move only vertically, by the wave's two phases; the sheet never folds (its
    /// triangles keep facing up), and it deforms: edges stretch and triangles tilt by
    /// different amounts, which no rigid motion does.
    #[test]
    fn the_sheet_deforms_non_rigidly() {
        let s = scene("hard-deforming");
        let m = mesh(&s, "sheet");
        assert_eq!(m.triangle_count(), 2 * QUADS * QUADS);
        let (mut lowest, mut highest) = (f32::MAX, f32::MIN);
        for (&a, &b) in m.t0.iter().zip(&m.t1) {
            assert!(a.x == b.x && a.z == b.z, "{a} -> {b} moves sideways");
            let p = Vec2::new(a.x - CENTRE.x, a.z - CENTRE.z);
            assert!((a.y - CENTRE.y - wave(p, PHASES[0])).abs() < 1e-5);
            assert!((b.y - CENTRE.y - wave(p, PHASES[1])).abs() < 1e-5);
            lowest = lowest.min(b.y - a.y);
            highest = highest.max(b.y - a.y);
        }
        // Some vertices rise by ~sqrt(2) A while others fall as much.
        assert!(highest > 0.4 && lowest < -0.4, "{lowest} {highest}");
        let (mut stretch, mut tilt) = (0.0_f32, 0.0_f32);
        let mut tilts = Vec::new();
        for (t0, t1) in m.t0.chunks_exact(3).zip(m.t1.chunks_exact(3)) {
            assert!(normal(t0).y > 0.5 && normal(t1).y > 0.5, "folded");
            let edge = |t: &[Vec3]| (t[1] - t[0]).length();
            stretch = stretch.max((edge(t1) / edge(t0) - 1.0).abs());
            let angle = normal(t0).angle_between(normal(t1)).to_degrees();
            tilt = tilt.max(angle);
            tilts.push(angle);
        }
        assert!(stretch > 0.05, "edges stretch by at most {stretch}");
        assert!(tilt > 20.0, "triangles tilt by at most {tilt} degrees");
        let least = tilts.iter().copied().fold(f32::MAX, f32::min);
        assert!(least < tilt * 0.5, "every triangle tilts alike");
    }
}
