//! `hard-thin-fast`: thin rods and poles (4 to 6 hundredths wide) above the ground, each
//! moving 5 to 9 of its widths over the shutter (one along its own length instead).
//!
//! A rod's shadow is a few shadow-map texels wide (at 2048 x 2048, 4-9 texels; at the
//! image's own resolution, less than one) and each ground point under its path is covered
//! for a short part of the shutter: coarse time or depth quantisation shows as gaps or
//! bands in the swept shadows.
//!
//! The motion: pure translation (every vertex of a rod moves by the same vector).

use glam::Vec3;

use super::super::file::{BoxSpec, MeshSpec, ObjectFile, SceneFile};
use super::super::parts::{ground, object, translate};
use super::{camera, scene_file, spot};

const LIGHT: Vec3 = Vec3::new(-2.0, 8.0, 2.5);

/// (name, full size, centre at t0, centre at t1).
pub(super) const RODS: [(&str, Vec3, Vec3, Vec3); 7] = [
    // Horizontal rods moving across their length.
    (
        "rod-0",
        Vec3::new(2.6, 0.04, 0.04),
        Vec3::new(0.0, 1.6, -0.6),
        Vec3::new(0.0, 1.6, -0.25),
    ),
    (
        "rod-1",
        Vec3::new(2.4, 0.05, 0.05),
        Vec3::new(0.2, 2.3, 0.6),
        Vec3::new(0.2, 2.3, 0.25),
    ),
    (
        "rod-2",
        Vec3::new(0.04, 0.04, 2.4),
        Vec3::new(-0.9, 1.2, 0.0),
        Vec3::new(-0.6, 1.2, 0.0),
    ),
    (
        "rod-3",
        Vec3::new(0.06, 0.06, 2.6),
        Vec3::new(1.0, 2.0, 0.1),
        Vec3::new(1.4, 1.9, 0.1),
    ),
    // Vertical poles hovering above the ground.
    (
        "pole-0",
        Vec3::new(0.05, 1.4, 0.05),
        Vec3::new(-1.6, 1.0, 1.0),
        Vec3::new(-1.33, 1.0, 1.0),
    ),
    (
        "pole-1",
        Vec3::new(0.04, 1.2, 0.04),
        Vec3::new(1.8, 0.9, -1.2),
        Vec3::new(2.0, 0.9, -1.0),
    ),
    // Along its own length: the shadow's sides stay put, its ends move.
    (
        "rod-lengthwise",
        Vec3::new(2.0, 0.04, 0.04),
        Vec3::new(-0.2, 0.8, 1.6),
        Vec3::new(0.3, 0.8, 1.6),
    ),
];

fn rod(&(name, size, from, to): &(&str, Vec3, Vec3, Vec3)) -> ObjectFile {
    object(
        name,
        Vec3::new(0.75, 0.7, 0.3),
        true,
        MeshSpec::Box(BoxSpec {
            size,
            subdivisions: 4,
        }),
        translate(from),
        Some(translate(to)),
    )
}

pub(super) fn scene() -> SceneFile {
    let middle = Vec3::new(0.0, 1.5, 0.2);
    let aim = LIGHT + (middle - LIGHT) * (LIGHT.y / (LIGHT.y - middle.y));
    let mut objects = vec![ground(16.0, 8)];
    objects.extend(RODS.iter().map(rod));
    scene_file(
        "hard-thin-fast",
        camera(Vec3::new(1.8, 5.7, 6.2), Vec3::new(0.65, 1.15, -0.4)),
        spot(LIGHT, aim, 35.0, 1.0, 30.0),
        objects,
    )
}

#[cfg(test)]
mod tests {
    use super::super::check::{mesh, scene};
    use super::*;

    /// Each rod translates rigidly by 5 to 9 of its widths across its length (the lengthwise
    /// one: more than 10 widths along it), and is at most 0.06 wide.
    #[test]
    fn thin_rods_move_several_widths() {
        let s = scene("hard-thin-fast");
        for (name, size, from, to) in RODS {
            let m = mesh(&s, name);
            let moved = to - from;
            for (&a, &b) in m.t0.iter().zip(&m.t1) {
                assert!((b - a - moved).length() < 1e-5, "{name} is not translating");
            }
            let width = size.min_element();
            let length = size.max_element();
            assert!(width <= 0.06 && length >= 20.0 * width, "{name}: {size}");
            let axis = Vec3::select(size.cmpeq(Vec3::splat(length)), Vec3::ONE, Vec3::ZERO);
            let along = moved.dot(axis).abs();
            let across = (moved - axis * moved.dot(axis)).length();
            if name == "rod-lengthwise" {
                assert!(along > 10.0 * width && across == 0.0, "{name}");
            } else {
                assert!(along == 0.0, "{name} moves along itself");
                let widths = across / width;
                assert!((5.0..=9.0).contains(&widths), "{name}: {widths} widths");
            }
        }
    }
}
