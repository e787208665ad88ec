//! `hard-propeller`: three thin blades on a static hub spinning about a vertical axis above
//! the ground, each blade a quarter turn over the shutter.
//!
//! Every blade edge turns; the tips sweep wide arcs while the roots barely move, and the
//! blades' swept shadows lie side by side with gaps between them.
//!
//! The motion, exactly: the t0 pose is the propeller at 0 degrees, the t1 pose at 90 degrees
//! (rigid poses), every vertex moving on the chord between them. At time t each blade is
//! therefore its t0 pose turned by atan(t / (1 - t)) (45 degrees at t = 0.5, not a uniform
//! spin) with every radius from the axis scaled by sqrt(t^2 + (1 - t)^2) (0.707 at t = 0.5);
//! heights do not change. That is as fast as linear motion spins sensibly: a 120-degree step
//! would shrink the blades to half their length mid-shutter, 180 degrees collapse them onto
//! the axis.

use glam::Vec3;

use super::super::file::{BoxSpec, MeshSpec, SceneFile, TransformFile};
use super::super::parts::{ground, object, translate};
use super::{camera, scene_file, spot, turn};

const LIGHT: Vec3 = Vec3::new(-2.0, 8.0, 2.5);
/// The hub's centre; the spin axis is vertical through it.
const HUB: Vec3 = Vec3::new(0.0, 2.2, 0.0);
const HUB_SIZE: Vec3 = Vec3::new(0.3, 0.2, 0.3);
/// Full size of a blade, its length along its local x; thin and flat.
const BLADE: Vec3 = Vec3::new(1.5, 0.04, 0.36);
/// Distance from the axis to a blade's root.
const ROOT: f32 = 0.1;
const BLADES: usize = 3;
const SPIN_DEG: f32 = 90.0;
const SUBDIVISIONS: u32 = 6;

/// Blade `k` turned `deg` more than its rest angle, as a rigid pose about the axis.
fn blade_pose(k: usize, deg: f32) -> TransformFile {
    let angle = 360.0 / BLADES as f32 * k as f32 + deg;
    let centre = Vec3::X * (ROOT + BLADE.x * 0.5);
    TransformFile {
        translation: Some(HUB + turn(Vec3::Y, angle) * centre),
        rotation_axis: Some(Vec3::Y),
        rotation_deg: Some(angle),
        scale: None,
    }
}

pub(super) fn scene() -> SceneFile {
    let aim = LIGHT + (HUB - LIGHT) * (LIGHT.y / (LIGHT.y - HUB.y));
    let mut objects = vec![
        ground(16.0, 8),
        object(
            "hub",
            Vec3::new(0.4, 0.4, 0.45),
            true,
            MeshSpec::Box(BoxSpec {
                size: HUB_SIZE,
                subdivisions: 2,
            }),
            translate(HUB),
            None,
        ),
    ];
    for k in 0..BLADES {
        objects.push(object(
            &format!("blade-{k}"),
            Vec3::new(0.3, 0.55, 0.8),
            true,
            MeshSpec::Box(BoxSpec {
                size: BLADE,
                subdivisions: SUBDIVISIONS,
            }),
            blade_pose(k, 0.0),
            Some(blade_pose(k, SPIN_DEG)),
        ));
    }
    scene_file(
        "hard-propeller",
        camera(Vec3::new(2.0, 5.1, 5.2), Vec3::new(0.8, 1.15, -0.85)),
        spot(LIGHT, aim, 35.0, 1.0, 30.0),
        objects,
    )
}

#[cfg(test)]
mod tests {
    use super::super::check::{mesh, scene};
    use super::*;

    /// Each blade's t1 pose is its t0 pose turned 90 degrees about the vertical axis through
    /// the static hub, vertex for vertex; the tips move more than five blade widths.
    #[test]
    fn the_blades_turn_a_quarter_about_the_hub() {
        let s = scene("hard-propeller");
        let hub = mesh(&s, "hub");
        assert_eq!(hub.t0, hub.t1);
        let spin = turn(Vec3::Y, SPIN_DEG);
        let mut fastest = 0.0_f32;
        for k in 0..BLADES {
            let blade = mesh(&s, &format!("blade-{k}"));
            assert!(blade.closed);
            for (&a, &b) in blade.t0.iter().zip(&blade.t1) {
                let expected = HUB + spin * (a - HUB);
                assert!((b - expected).length() < 1e-4, "{a} -> {b}, not {expected}");
                let radius = Vec3::new(a.x - HUB.x, 0.0, a.z - HUB.z).length();
                assert!((ROOT - 1e-5..=1.62).contains(&radius), "{radius}");
                fastest = fastest.max((a - b).length());
            }
        }
        assert!(fastest > 5.0 * BLADE.z, "tips move {fastest}");
        // Mid-shutter the blades are at cos 45 of their radius (chord blend).
        let tip = mesh(&s, "blade-0")
            .t0
            .iter()
            .zip(&mesh(&s, "blade-0").t1)
            .map(|(a, b)| ((*a + *b) * 0.5 - HUB) * Vec3::new(1.0, 0.0, 1.0))
            .map(|r| r.length())
            .fold(0.0, f32::max);
        let full = (ROOT + BLADE.x).hypot(BLADE.z * 0.5);
        assert!((tip - full * 0.5_f32.sqrt()).abs() < 1e-4, "{tip}");
    }
}
