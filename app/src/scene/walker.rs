//! `walker-toward-light` (Hong & Oh 2018, Fig. 10, with a real character): CesiumMan
//! walking in place toward the spot light of `leg-toward-light`, on the same stage, so the
//! swinging foot moves toward the light and its shadow on the ground and the back wall
//! blurs along the step while the rest of the body's stays nearly sharp.

use glam::Vec3;

use super::SceneError;
use super::character::{CESIUM_MAN, SHUTTER_180_AT_24, animated_object, staged_scene};
use super::file::{SceneFile, TransformFile};
use super::gltf::{AnimationRef, GltfOptions};

/// Shutter open, seconds into the walk cycle: frame 13 of the 48 over the 2 s cycle at
/// 24 fps, the one whose 180-degree shutter moves a vertex farthest (a foot, 5.6 cm).
pub(super) const WALKER_TIME: f32 = 13.0 / 24.0;

/// The model faces +x; turned this far about +y it faces +z, the light.
const FACING_DEG: f32 = -90.0;

pub(super) fn walker_toward_light(time: f32, subdivide: u32) -> Result<SceneFile, SceneError> {
    let walker = animated_object(
        "walker",
        Vec3::new(0.3, 0.45, 0.7),
        CESIUM_MAN,
        &GltfOptions {
            animation: Some(AnimationRef::Index(0)),
            time,
            shutter: SHUTTER_180_AT_24,
            subdivide,
        },
        TransformFile {
            translation: None,
            rotation_axis: Some(Vec3::Y),
            rotation_deg: Some(FACING_DEG),
            scale: None,
        },
    )?;
    Ok(staged_scene("walker-toward-light", walker))
}

#[cfg(test)]
mod tests {
    use super::super::character::test_support::{assert_inside_spot_cone, fastest};
    use super::super::leg::{LIGHT, WALL_Z};
    use super::super::{BuiltinOptions, Mesh, Scene, builtin};
    use super::*;

    fn scene() -> Scene {
        builtin("walker-toward-light", &BuiltinOptions::default()).unwrap()
    }

    fn walker(s: &Scene) -> &Mesh {
        s.meshes.iter().find(|m| m.name == "walker").unwrap()
    }

    /// 4,672 triangles (assets/models/README.md) plus the backdrop's two 16 x 16 planes.
    #[test]
    fn walker_has_the_models_triangles_on_the_stage() {
        let s = scene();
        assert_eq!(walker(&s).triangle_count(), 4672);
        assert_eq!(s.triangle_count(), 4672 + 2 * 2 * 16 * 16);
        let moving = super::super::character::test_support::moving_meshes(&s);
        assert_eq!(moving, ["walker"]);
        for &p in walker(&s).t0.iter().chain(&walker(&s).t1) {
            // The model stands on y = 0 (its lowest key pose dips 2.6 cm below).
            assert!(p.y > -0.03 && p.y < 1.53 && p.z > WALL_Z + 1.0, "{p}");
        }
    }

    /// Each level of subdivision splits every triangle in four, the papers' way to their
    /// sizes; past the loader's limit of 8 levels the scene is refused by name.
    #[test]
    fn subdivide_multiplies_the_walkers_triangles() {
        let options = |subdivide| BuiltinOptions {
            subdivide,
            ..Default::default()
        };
        let s = builtin("walker-toward-light", &options(2)).unwrap();
        assert_eq!(walker(&s).triangle_count(), 4672 * 16);
        match builtin("walker-toward-light", &options(9)) {
            Err(e) => assert!(e.to_string().contains("subdivide must be at most 8"), "{e}"),
            Ok(_) => panic!("9 levels accepted"),
        }
    }

    /// A walker's swinging foot outruns every other part: the fastest vertex is in the
    /// lowest tenth of the 1.5 m figure, it moves toward the light, and no time of the cycle
    /// (every 1/24 s) moves a vertex farther than the chosen one.
    #[test]
    fn the_largest_motion_is_a_foot_stepping_toward_the_light() {
        let s = scene();
        let m = walker(&s);
        let (moved, at) = fastest(m);
        assert!(moved > 0.02 && at.y < 0.15, "{moved} at {at}");
        let i = m.t0.iter().position(|&p| p == at).unwrap();
        assert!((LIGHT - m.t1[i]).length() < (LIGHT - at).length() - 0.5 * moved);
        for frame in 0..48 {
            let other = walker_toward_light(frame as f32 / 24.0, 0)
                .unwrap()
                .to_scene(std::path::Path::new("."), "w")
                .unwrap();
            let (d, _) = fastest(walker(&other));
            assert!(d <= moved + 1e-6, "frame {frame}: {d} > {moved}");
        }
    }

    /// Every walker vertex, at both ends of the shutter (so at every time: the cone is
    /// convex and vertices move on straight lines), is inside the spot light's cone.
    #[test]
    fn walker_inside_light_cone() {
        let s = scene();
        assert_inside_spot_cone(&s, walker(&s));
    }
}
