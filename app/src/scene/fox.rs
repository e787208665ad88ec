//! `fox-run`: the Fox model's `Run` clip, scaled to about one unit tall, running in place
//! toward the spot light of `leg-toward-light` on the same stage: four legs swinging at
//! once, a denser pattern of blurred and sharp shadow edges than the walker's.

use glam::Vec3;

use super::SceneError;
use super::character::{FOX, SHUTTER_180_AT_24, animated_object, staged_scene};
use super::file::{SceneFile, TransformFile};
use super::gltf::{AnimationRef, GltfOptions};

/// Shutter open, seconds into the 1.16 s run cycle: frame 12 at 24 fps, the one whose
/// 180-degree shutter moves a vertex farthest (a foot, 10.5 model units).
pub(super) const FOX_TIME: f32 = 12.0 / 24.0;

/// The model is about 79 units tall (assets/models/README.md); this makes it ~1.
pub(super) const FOX_SCALE: f32 = 1.0 / 79.0;

pub(super) fn fox_run(time: f32, subdivide: u32) -> Result<SceneFile, SceneError> {
    let fox = animated_object(
        "fox",
        Vec3::new(0.85, 0.45, 0.2),
        FOX,
        &GltfOptions {
            animation: Some(AnimationRef::Name("Run".into())),
            time,
            shutter: SHUTTER_180_AT_24,
            subdivide,
        },
        TransformFile {
            scale: Some(Vec3::splat(FOX_SCALE)),
            ..Default::default()
        },
    )?;
    Ok(staged_scene("fox-run", fox))
}

#[cfg(test)]
mod tests {
    use super::super::character::test_support::{assert_inside_spot_cone, fastest};
    use super::super::leg::WALL_Z;
    use super::super::{BuiltinOptions, Mesh, Scene, builtin};
    use super::*;

    fn scene() -> Scene {
        builtin("fox-run", &BuiltinOptions::default()).unwrap()
    }

    fn fox(s: &Scene) -> &Mesh {
        s.meshes.iter().find(|m| m.name == "fox").unwrap()
    }

    /// 576 triangles (assets/models/README.md) plus the backdrop's two 16 x 16 planes; the
    /// model's 79 units (its rest height, README) scaled to ~1.
    #[test]
    fn fox_has_the_models_triangles_at_about_one_unit_tall() {
        let s = scene();
        assert_eq!(fox(&s).triangle_count(), 576);
        assert_eq!(s.triangle_count(), 576 + 2 * 2 * 16 * 16);
        let (lo, hi) = fox(&s)
            .t0
            .iter()
            .fold((Vec3::MAX, Vec3::MIN), |(a, b), &p| (a.min(p), b.max(p)));
        assert!((0.85..1.05).contains(&(hi.y - lo.y)), "{lo} {hi}");
        assert!(lo.y > -0.05 && lo.z > WALL_Z + 0.5, "{lo}");
    }

    /// The fastest vertex is a foot (lowest tenth of the figure), no frame of the cycle
    /// (every 1/24 s) moves a vertex farther, and the fox moves as a whole hardly at all
    /// (it runs in place, so its shadow stays on the stage).
    #[test]
    fn the_largest_motion_is_at_the_feet() {
        let s = scene();
        let (moved, at) = fastest(fox(&s));
        assert!(moved > 0.1 && at.y < 0.1, "{moved} at {at}");
        for frame in 0..28 {
            let other = fox_run(frame as f32 / 24.0, 0)
                .unwrap()
                .to_scene(std::path::Path::new("."), "f")
                .unwrap();
            let (d, _) = fastest(fox(&other));
            assert!(d <= moved + 1e-6, "frame {frame}: {d} > {moved}");
        }
        let centre = |p: &[Vec3]| p.iter().sum::<Vec3>() / p.len() as f32;
        let m = fox(&s);
        assert!((centre(&m.t1) - centre(&m.t0)).length() < 0.05);
    }

    #[test]
    fn fox_inside_light_cone() {
        let s = scene();
        assert_inside_spot_cone(&s, fox(&s));
    }
}
