//! `game-level`: a scene shaped like a game's, where most triangles are static and few move.
//! A room of ~50,000 static triangles (`level.rs`) and ~6,000 moving ones, about a tenth
//! (`movers.rs`: the walking CesiumMan, a spinning trap, two thrown crates), lit by one spot
//! light high over the front of the room and seen by a third-person camera that follows the
//! walker.
//! Motion is a game's at 30 fps with a 180-degree shutter (1/60 s).

mod cylinder;
mod level;
mod movers;

use glam::Vec3;

use super::SceneError;
use super::file::{CameraFile, LightFile, SCENE_FORMAT, SceneFile};
use movers::walker_position;

/// Shutter open by default, seconds: 13/24 s into the walk cycle, where a foot swings
/// fastest (as in `walker-toward-light`), with both crates in the air.
pub(super) const GAME_TIME: f32 = 13.0 / 24.0;

/// High above the room's middle aisle, toward its front right, so the casters' shadows fall
/// ahead of them and to their left, onto the floor and the walls the camera sees, while the
/// beams' and pillars' shadows fall outside the aisle.
const LIGHT: Vec3 = Vec3::new(3.0, 8.0, 5.0);
const LIGHT_AIM: Vec3 = Vec3::new(-1.0, 0.0, -3.0);
/// Half-angle wide enough for every part of the room the camera sees.
const LIGHT_CONE_DEG: f32 = 60.0;
/// Radiance 0.62/pi * 300 * cos / d^2 on the floor: ~0.7 around the walker's start (d ~ 9),
/// ~0.07 in the far corner (d ~ 19).
const LIGHT_INTENSITY: f32 = 300.0;

/// Behind the walker's right shoulder and above it, looking past it into the room.
const CAMERA_OFFSET: Vec3 = Vec3::new(0.4, 2.6, 3.8);
const CAMERA_LOOK_OFFSET: Vec3 = Vec3::new(-0.3, 0.6, -5.0);

pub(super) fn game_level(time: f64, subdivide: u32) -> Result<SceneFile, SceneError> {
    let mut objects = level::level();
    objects.extend(movers::movers(time, subdivide)?);
    let walker = walker_position(time);
    Ok(SceneFile {
        format: SCENE_FORMAT.to_owned(),
        name: Some("game-level".to_owned()),
        camera: CameraFile {
            position: walker + CAMERA_OFFSET,
            target: walker + CAMERA_LOOK_OFFSET,
            up: Vec3::Y,
            fov_y_deg: 60.0,
            near: 0.1,
            far: 60.0,
            t1: None,
        },
        light: LightFile::Spot {
            position: LIGHT,
            direction: LIGHT_AIM - LIGHT,
            cone_angle_deg: LIGHT_CONE_DEG,
            intensity: LIGHT_INTENSITY,
            near: 0.5,
            far: 40.0,
            t1: None,
        },
        // A little fill light, as games have, so the shadowed side of the room still reads.
        ambient: 0.04,
        objects,
    })
}

#[cfg(test)]
mod tests {
    use super::super::character::test_support::{assert_inside_spot_cone, fastest};
    use super::super::gltf::shutter_seconds;
    use super::super::{BuiltinOptions, Light, Mesh, Scene, builtin};
    use super::level::{ROOM_BACK_Z, ROOM_FRONT_Z, ROOM_HALF_X};
    use super::movers::{SHUTTER, SPIN_DEG_PER_S, SPINNER_REACH, WALK_SPEED};
    use super::*;

    /// The objects that move, in scene order; everything else is the static level.
    const MOVERS: [&str; 5] = [
        "walker",
        "spinner-arm-0",
        "spinner-arm-1",
        "thrown-crate-0",
        "thrown-crate-1",
    ];

    fn scene_at(time: Option<f64>) -> Scene {
        let options = BuiltinOptions {
            frame_time: time,
            ..Default::default()
        };
        builtin("game-level", &options).unwrap()
    }

    fn mesh<'a>(s: &'a Scene, name: &str) -> &'a Mesh {
        s.meshes.iter().find(|m| m.name == name).unwrap()
    }

    /// Triangles some vertex of which is somewhere else at shutter close.
    fn moving_triangles(m: &Mesh) -> usize {
        m.t0.chunks_exact(3)
            .zip(m.t1.chunks_exact(3))
            .filter(|(a, b)| a != b)
            .count()
    }

    fn spot(s: &Scene) -> &super::super::SpotLight {
        let Light::Spot(light) = &s.light else {
            panic!("spot expected")
        };
        light
    }

    /// ~50k triangles, of which 5-15% move, all of them in the movers, the walker with the
    /// model's 4,672 (assets/models/README.md).
    #[test]
    fn a_level_of_game_size_with_a_tenth_of_it_moving() {
        let s = scene_at(None);
        let total = s.triangle_count();
        assert!((45_000..=60_000).contains(&total), "{total} triangles");
        let moving: usize = s.meshes.iter().map(moving_triangles).sum();
        let share = moving as f64 / total as f64;
        assert!((0.05..=0.15).contains(&share), "{moving} of {total} move");
        let movers = super::super::character::test_support::moving_meshes(&s);
        assert_eq!(movers, MOVERS);
        assert_eq!(mesh(&s, "walker").triangle_count(), 4672);
        let static_triangles = total
            - MOVERS
                .map(|n| mesh(&s, n).triangle_count())
                .iter()
                .sum::<usize>();
        assert!(
            (45_000..55_000).contains(&static_triangles),
            "{static_triangles}"
        );
    }

    #[test]
    fn deterministic() {
        assert_eq!(scene_at(None), scene_at(None));
        assert_eq!(scene_at(None), scene_at(Some(f64::from(GAME_TIME))));
        assert_ne!(scene_at(None), scene_at(Some(f64::from(GAME_TIME) + 0.1)));
    }

    /// A game's motion over a 180-degree shutter at 30 fps: every mover visibly blurred
    /// (2 cm or more), nothing faster than 30 m/s; the spinner's arm tips move the chord of
    /// their turn.
    #[test]
    fn motion_per_shutter_is_a_games() {
        assert_eq!(SHUTTER, shutter_seconds(180.0, 30.0));
        let s = scene_at(None);
        for name in MOVERS {
            let (moved, at) = fastest(mesh(&s, name));
            assert!(
                (0.02..=30.0 * SHUTTER).contains(&moved),
                "{name}: {moved} at {at}"
            );
        }
        let half_turn = (SPIN_DEG_PER_S * SHUTTER * 0.5).to_radians().sin();
        let (tip, _) = fastest(mesh(&s, "spinner-arm-0"));
        assert!(tip >= 2.0 * SPINNER_REACH * half_turn - 1e-4, "{tip}");
        assert!(tip <= 2.0 * (SPINNER_REACH + 0.15) * half_turn, "{tip}");
    }

    /// The walker is carried at the speed its planted foot slides back at in the model's
    /// in-place walk: over a whole cycle, the vertices on the floor (the planted sole) move
    /// on average far slower than the walker does.
    #[test]
    fn the_planted_foot_stays_on_the_floor() {
        let mut velocities = Vec::new();
        for frame in 0..48 {
            let s = scene_at(Some(f64::from(frame) / 24.0));
            let m = mesh(&s, "walker");
            let sole: Vec<Vec3> =
                m.t0.iter()
                    .zip(&m.t1)
                    .filter(|(p, _)| p.y < 0.02)
                    .map(|(a, b)| (*b - *a) / SHUTTER)
                    .collect();
            if !sole.is_empty() {
                velocities.push(sole.iter().sum::<Vec3>() / sole.len() as f32);
            }
        }
        assert!(velocities.len() > 24, "{}", velocities.len());
        let mean = velocities.iter().sum::<Vec3>() / velocities.len() as f32;
        assert!(mean.z.abs() < 0.25 * WALK_SPEED, "{mean}");
    }

    /// Every moving vertex, at both ends of the shutter, is inside the light's cone, at the
    /// default time and along the loops of every motion (the walk, the throws, the spin),
    /// and stays in the room.
    #[test]
    fn movers_stay_lit_and_in_the_room_at_every_time() {
        for step in 0..=32 {
            let time = f64::from(step) * 0.25;
            let s = scene_at(Some(time));
            for name in MOVERS {
                let m = mesh(&s, name);
                assert_inside_spot_cone(&s, m);
                for &p in m.t0.iter().chain(&m.t1) {
                    assert!(
                        p.x.abs() < ROOM_HALF_X && p.z > ROOM_BACK_Z && p.z < ROOM_FRONT_Z,
                        "{name} at {p}, time {time}"
                    );
                    assert!(p.y > -0.2 && p.y < 5.0, "{name} at {p}, time {time}");
                }
            }
        }
    }

    /// No part of the scene that the light reaches is cut off by its near and far planes:
    /// every vertex inside the cone (widened by 10 degrees, for triangles reaching into it)
    /// is between them (a caster outside the cone shadows nothing lit). Nothing is beyond
    /// the camera's far plane.
    #[test]
    fn nothing_is_clipped() {
        let s = scene_at(None);
        let light = spot(&s);
        let cos_wide = (light.cone_angle_deg + 10.0).to_radians().cos();
        let mut inside = 0;
        for m in &s.meshes {
            for &p in m.t0.iter().chain(&m.t1) {
                let d = p - light.position;
                if d.normalize().dot(light.direction) > cos_wide {
                    inside += 1;
                    let depth = d.dot(light.direction);
                    assert!(depth > light.near && depth < light.far, "{} at {p}", m.name);
                }
                assert!(
                    (p - s.camera.position).length() < s.camera.far,
                    "{}",
                    m.name
                );
            }
        }
        // Most of the level is lit, so the check above is not empty.
        assert!(inside > 3 * s.triangle_count(), "{inside}");
    }

    /// The movers' shadows fall on the floor inside the room, or past it on the back wall,
    /// in the camera's view (a square image, the narrowest likely).
    #[test]
    fn moving_shadows_land_on_the_floor_in_view() {
        let s = scene_at(None);
        let light = spot(&s);
        for name in MOVERS {
            for &p in mesh(&s, name).t0.iter().chain(&mesh(&s, name).t1) {
                let ray = p - light.position;
                let to_floor = light.position.y / -ray.y;
                let to_back_wall = (ROOM_BACK_Z - light.position.z) / ray.z;
                let hit = light.position + ray * to_floor.min(to_back_wall);
                assert!(
                    hit.x.abs() < ROOM_HALF_X && hit.z < ROOM_FRONT_Z && hit.y < 2.0,
                    "{name}: shadow at {hit} off the floor and back wall"
                );
                let ndc = s.camera.ndc_unit_aspect(hit);
                assert!(
                    ndc.abs().max_element() < 0.95,
                    "{name}: shadow off screen {ndc}"
                );
            }
        }
    }

    /// Lit floor radiance: moderate where the walker is, dim but not black in the far
    /// corner (albedo/pi * I * cos / d^2).
    #[test]
    fn floor_radiance_is_moderate() {
        let s = scene_at(None);
        let light = spot(&s);
        let albedo = mesh(&s, "floor").albedo.x;
        let radiance = |p: Vec3| {
            let d = light.position - p;
            albedo / std::f32::consts::PI * light.intensity * d.normalize().y / d.length_squared()
        };
        let at_walker = radiance(walker_position(f64::from(GAME_TIME)));
        let far_corner = radiance(Vec3::new(-ROOM_HALF_X, 0.0, ROOM_BACK_Z));
        assert!((0.3..1.0).contains(&at_walker), "{at_walker}");
        assert!((0.04..0.2).contains(&far_corner), "{far_corner}");
    }

    #[test]
    fn documented() {
        let doc = include_str!("../../../../docs/scene-format.md");
        let readme = include_str!("../../../../README.md");
        let cli = include_str!("../../../../docs/src/cli.md");
        assert!(doc.contains("- `game-level`"), "docs/scene-format.md");
        assert!(readme.contains("- `game-level`"), "README.md built-in list");
        assert!(readme.contains("`game`"), "README.md preset list");
        assert!(cli.contains("| `game`"), "docs/src/cli.md preset table");
    }
}
