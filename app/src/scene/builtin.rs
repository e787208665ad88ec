//! Built-in test scenes. Each is built as a `SceneFile` and converted through the same path
//! as a file on disk, so `builtin(name)` always equals loading `scene_to_json(builtin_file(name))`.

use std::path::Path;

use glam::Vec3;

use super::camera_pan::camera_pan;
use super::file::{
    BoxSpec, CameraFile, LightFile, MeshSpec, SCENE_FORMAT, SceneFile, TransformFile,
};
use super::fox::{FOX_TIME, fox_run};
use super::game::{GAME_TIME, game_level};
use super::hard::hard_scene;
use super::leg::leg_toward_light;
use super::limits::{CUBE_SIZE_RANGE, MAX_CUBE_SPEED, MAX_SCENE_TRIANGLES};
use super::moving_light::moving_light;
use super::parts::{ground, object, random_moving_cube, translate};
use super::rng::SplitMix64;
use super::walker::{WALKER_TIME, walker_toward_light};
use super::{Scene, SceneError};

/// The first name is the default scene; the `hard-` scenes are also in `HARD_NAMES`.
pub const BUILTIN_NAMES: &[&str] = &[
    "cubes-toward-light",
    "random-cubes",
    "leg-toward-light",
    "walker-toward-light",
    "fox-run",
    "game-level",
    "moving-light",
    "camera-pan",
    "hard-rotating-triangle",
    "hard-hinged-limb",
    "hard-propeller",
    "hard-near-plane",
    "hard-grazing",
    "hard-thin-fast",
    "hard-deforming",
    "hard-small-cubes",
    "hard-static-silhouette",
    "hard-turning-light",
];

/// Parameters of the procedural scenes (only `random-cubes` uses them; the hard scenes are
/// fixed).
#[derive(Debug, Clone, PartialEq)]
pub struct BuiltinOptions {
    pub cube_count: usize,
    /// Displacement of each cube over the shutter is uniform in [speed_min, speed_max].
    pub speed_min: f32,
    pub speed_max: f32,
    /// Edge length of each cube. The papers give the count and the speeds but not the size;
    /// what the coverage map saves depends on it (a face must stay over a texel all frame).
    pub cube_size: f32,
    pub seed: u64,
    /// Scenes with an animated character: animation time at shutter open, seconds; `None`:
    /// the scene's own (`builtin_animation_time`). Other scenes ignore it. Double precision,
    /// so a time far from 0 still tells frames 1/100 s apart (`game-level` loops forever).
    pub frame_time: Option<f64>,
    /// Scenes with an animated character: levels of midpoint subdivision of the character
    /// (each multiplies its triangles by 4).
    pub subdivide: u32,
}

impl Default for BuiltinOptions {
    fn default() -> Self {
        Self {
            cube_count: 4000,
            speed_min: 4.0,
            speed_max: 8.0,
            cube_size: 1.0,
            seed: 1,
            frame_time: None,
            subdivide: 0,
        }
    }
}

/// Shutter-open time of a built-in scene with an animated character; `None` for the others
/// (nothing in them moves from frame to frame).
pub fn builtin_animation_time(name: &str) -> Option<f32> {
    match name {
        "walker-toward-light" => Some(WALKER_TIME),
        "fox-run" => Some(FOX_TIME),
        "game-level" => Some(GAME_TIME),
        _ => None,
    }
}

pub fn builtin(name: &str, opts: &BuiltinOptions) -> Result<Scene, SceneError> {
    builtin_file(name, opts)?.to_scene(Path::new("."), name)
}

pub fn builtin_file(name: &str, opts: &BuiltinOptions) -> Result<SceneFile, SceneError> {
    match name {
        "cubes-toward-light" => Ok(cubes_toward_light()),
        "random-cubes" => random_cubes(opts),
        "leg-toward-light" => Ok(leg_toward_light()),
        "walker-toward-light" => {
            // The glTF animations clamp to their keys, so single precision loses nothing.
            walker_toward_light(frame_time(opts, WALKER_TIME) as f32, opts.subdivide)
        }
        "fox-run" => fox_run(frame_time(opts, FOX_TIME) as f32, opts.subdivide),
        "game-level" => game_level(frame_time(opts, GAME_TIME), opts.subdivide),
        "moving-light" => Ok(moving_light()),
        "camera-pan" => Ok(camera_pan()),
        _ => hard_scene(name).ok_or_else(|| SceneError::UnknownBuiltin {
            name: name.to_owned(),
            available: BUILTIN_NAMES.iter().map(|s| s.to_string()).collect(),
        }),
    }
}

/// `opts.frame_time`, or the scene's own time.
fn frame_time(opts: &BuiltinOptions, own: f32) -> f64 {
    opts.frame_time.unwrap_or(f64::from(own))
}

/// Hong & Oh 2018, Fig. 9: two finely tessellated cubes fly toward a spot light, so their
/// shadows grow and blur, next to a static pillar whose shadow must stay sharp. The cubes
/// hang well away from the light axis so the camera sees their shadows beside them.
pub(super) fn cubes_toward_light() -> SceneFile {
    let light = Vec3::new(0.0, 12.0, 2.0);
    // 22 x 22 quads per face: 2 cubes * 12 * 22^2 = 11,616 of the ~12,140 triangles.
    let cube = MeshSpec::Box(BoxSpec {
        size: Vec3::splat(1.5),
        subdivisions: 22,
    });
    let toward_light = |c: Vec3| c + (light - c).normalize() * 2.5;

    let left = Vec3::new(-2.0, 4.0, 0.5);
    let right = Vec3::new(2.2, 3.5, -1.5);
    let spin = |deg: f32, at: Vec3| TransformFile {
        translation: Some(at),
        rotation_axis: Some(Vec3::new(0.3, 1.0, 0.2)),
        rotation_deg: Some(deg),
        scale: None,
    };
    let pillar = MeshSpec::Box(BoxSpec {
        size: Vec3::new(0.6, 2.0, 0.6),
        subdivisions: 1,
    });
    SceneFile {
        format: SCENE_FORMAT.to_owned(),
        name: Some("cubes-toward-light".to_owned()),
        camera: CameraFile {
            position: Vec3::new(0.0, 8.0, 16.0),
            target: Vec3::new(0.0, 2.6, 0.0),
            up: Vec3::Y,
            fov_y_deg: 45.0,
            near: 0.1,
            far: 100.0,
            t1: None,
        },
        // Ground below the light: 0.8/pi * 250 * cos / 12.2^2 ~ 0.42 radiance.
        light: LightFile::Spot {
            position: light,
            direction: Vec3::ZERO - light, // at the origin; `-light` would print -0.0
            cone_angle_deg: 40.0,
            intensity: 250.0,
            near: 0.5,
            far: 50.0,
            t1: None,
        },
        ambient: 0.0,
        objects: vec![
            ground(20.0, 16),
            object(
                "cube-left",
                Vec3::new(0.8, 0.3, 0.25),
                true,
                cube.clone(),
                translate(left),
                Some(translate(toward_light(left))),
            ),
            object(
                "cube-right",
                Vec3::new(0.25, 0.45, 0.8),
                true,
                cube,
                spin(0.0, right),
                Some(spin(35.0, toward_light(right))),
            ),
            // In front, so nothing it casts or hides overlaps the cubes' shadows.
            object(
                "pillar",
                Vec3::new(0.85, 0.75, 0.4),
                true,
                pillar,
                translate(Vec3::new(2.4, 1.0, 4.6)),
                None,
            ),
        ],
    }
}

/// The random-cubes ground: a plane of 8 x 8 quads, 128 triangles.
const GROUND_SUBDIVISIONS: u32 = 8;
const RANDOM_CUBES_GROUND_TRIANGLES: u64 = 2 * (GROUND_SUBDIVISIONS as u64).pow(2);

/// Hong & Oh 2017, Fig. 8: a dense field of unit cubes each flying in its own random
/// direction, over a ground plane, lit from above by a spot light covering the field.
fn random_cubes(opts: &BuiltinOptions) -> Result<SceneFile, SceneError> {
    let BuiltinOptions {
        cube_count,
        speed_min,
        speed_max,
        cube_size,
        seed,
        frame_time: _,
        subdivide: _,
    } = *opts;
    // Every size is checked before a cube is placed: the count against the scene's triangle
    // limit (12 per cube, 128 for the ground), the lengths against ranges the framing below
    // stays finite and in single-precision range for.
    let max_cubes = (MAX_SCENE_TRIANGLES - RANDOM_CUBES_GROUND_TRIANGLES) / 12;
    if cube_count == 0 || cube_count as u64 > max_cubes {
        return Err(SceneError::Invalid(format!(
            "random-cubes: the cube count must be in 1..={max_cubes} (12 triangles each, \
             at most {MAX_SCENE_TRIANGLES} in a scene), got {cube_count}"
        )));
    }
    let triangles = 12 * cube_count as u64 + RANDOM_CUBES_GROUND_TRIANGLES;
    super::memory::check_triangles(triangles)
        .map_err(|e| SceneError::Invalid(format!("random-cubes, {cube_count} cubes: {e}")))?;
    if !(0.0 <= speed_min && speed_min <= speed_max && speed_max <= MAX_CUBE_SPEED) {
        return Err(SceneError::Invalid(format!(
            "random-cubes: need 0 <= speed_min <= speed_max <= {MAX_CUBE_SPEED}, \
             got {speed_min:e}..{speed_max:e}"
        )));
    }
    let (min_size, max_size) = CUBE_SIZE_RANGE;
    if !(min_size..=max_size).contains(&cube_size) {
        return Err(SceneError::Invalid(format!(
            "random-cubes: the cube size must be in [{min_size}, {max_size}], got {cube_size:e}"
        )));
    }
    // ~10% of the volume filled by cubes: dense but with gaps for light.
    let side = 2.2 * (cube_count as f32).cbrt() * cube_size;
    // Half-size of the box swept over the shutter; one more cube size keeps the (rotated)
    // cubes above the ground.
    let half = side * 0.5 + speed_max;
    let center = Vec3::new(0.0, half + cube_size, 0.0);

    let mut rng = SplitMix64::new(seed);
    let unit = MeshSpec::Box(BoxSpec {
        size: Vec3::splat(cube_size),
        subdivisions: 1,
    });
    let mut objects = Vec::with_capacity(cube_count + 1);
    for i in 0..cube_count {
        let p0 = center
            + Vec3::new(
                rng.range(-0.5, 0.5),
                rng.range(-0.5, 0.5),
                rng.range(-0.5, 0.5),
            ) * side;
        objects.push(random_moving_cube(
            &mut rng,
            i,
            &unit,
            p0,
            (speed_min, speed_max),
        ));
    }

    // Light twice the field's half-size above its top: a 40 degree half-angle cone then
    // covers the whole swept box (its top corners are at atan(sqrt2/2) ~ 35 degrees).
    let cone = 40.0_f32;
    let light_height = center.y + 3.0 * half;
    let ground_half = light_height * cone.to_radians().tan();
    objects.insert(0, ground(2.0 * ground_half, GROUND_SUBDIVISIONS));

    // Orbit distance at which a fov-45 camera sees the swept box's bounding sphere.
    let radius = half * 3.0_f32.sqrt();
    let target = Vec3::new(0.0, center.y * 0.8, 0.0);
    let distance = 2.8 * radius;
    Ok(SceneFile {
        format: SCENE_FORMAT.to_owned(),
        name: Some("random-cubes".to_owned()),
        camera: CameraFile {
            position: target + Vec3::new(0.0, 0.45, 1.0).normalize() * distance,
            target,
            up: Vec3::Y,
            fov_y_deg: 45.0,
            near: (0.01 * distance).max(0.1),
            far: 2.0 * (distance + ground_half),
            t1: None,
        },
        // Ground right below the light at radiance ~0.5: I = 0.5 * pi / 0.8 * d^2.
        light: LightFile::Spot {
            position: Vec3::new(0.0, light_height, 0.0),
            direction: Vec3::NEG_Y,
            cone_angle_deg: cone,
            intensity: 0.5 * std::f32::consts::PI / 0.8 * light_height * light_height,
            near: half,
            far: 1.1 * light_height / cone.to_radians().cos(),
            t1: None,
        },
        ambient: 0.0,
        objects,
    })
}

#[cfg(test)]
mod tests {
    use super::super::file::{parse_scene_json, scene_to_json};
    use super::super::{Light, Mesh};
    use super::*;

    fn centre(points: &[Vec3]) -> Vec3 {
        points.iter().sum::<Vec3>() / points.len() as f32
    }

    fn small(count: usize, seed: u64) -> BuiltinOptions {
        BuiltinOptions {
            cube_count: count,
            seed,
            ..Default::default()
        }
    }

    #[test]
    fn json_round_trip_equals_builtin() {
        for &name in BUILTIN_NAMES {
            let opts = BuiltinOptions::default();
            let json = scene_to_json(&builtin_file(name, &opts).unwrap());
            let loaded = parse_scene_json(&json, Path::new("."), "exported.json").unwrap();
            assert_eq!(loaded, builtin(name, &opts).unwrap(), "{name}");
        }
    }

    #[test]
    fn cubes_toward_light_size_and_motion() {
        let s = builtin("cubes-toward-light", &BuiltinOptions::default()).unwrap();
        assert!(
            (11_000..13_000).contains(&s.triangle_count()),
            "{}",
            s.triangle_count()
        );
        let mesh = |n: &str| s.meshes.iter().find(|m| m.name == n).unwrap();
        assert_eq!(mesh("pillar").t0, mesh("pillar").t1);
        assert_ne!(mesh("ground").t0.len(), 0);
        let Light::Spot(light) = &s.light else {
            panic!("spot expected")
        };
        for cube in ["cube-left", "cube-right"] {
            let (c0, c1) = (centre(&mesh(cube).t0), centre(&mesh(cube).t1));
            assert!(((c1 - c0).length() - 2.5).abs() < 1e-3);
            assert!((light.position - c1).length() < (light.position - c0).length() - 2.4);
        }
    }

    /// Every shadow-casting vertex, at both ends of the shutter, projects from the light onto
    /// the ground inside the light cone, the ground plane and the camera's view (aspect 1,
    /// the narrowest likely), so the blurred and sharp shadows are all on screen.
    #[test]
    fn cubes_toward_light_shadows_are_lit_and_visible() {
        let s = builtin("cubes-toward-light", &BuiltinOptions::default()).unwrap();
        let Light::Spot(light) = &s.light else {
            panic!("spot expected")
        };
        let ndc = |p: Vec3| s.camera.ndc_unit_aspect(p);
        let cos_cone = light.cone_angle_deg.to_radians().cos();
        let casters: Vec<&Mesh> = s.meshes.iter().filter(|m| m.name != "ground").collect();
        assert_eq!(casters.len(), 3);
        for m in casters {
            for &p in m.t0.iter().chain(&m.t1) {
                let ray = p - light.position;
                let hit = light.position + ray * (light.position.y / -ray.y);
                let to_hit = (hit - light.position).normalize();
                assert!(
                    to_hit.dot(light.direction) > cos_cone + 0.02,
                    "{} outside cone",
                    m.name
                );
                assert!(
                    hit.x.abs() < 9.0 && hit.z.abs() < 9.0,
                    "{} off the ground",
                    m.name
                );
                let ndc = ndc(hit);
                assert!(
                    ndc.x.abs() < 0.95 && ndc.y.abs() < 0.95,
                    "{} shadow off screen: {ndc}",
                    m.name
                );
            }
        }
    }

    #[test]
    fn random_cubes_deterministic_per_seed() {
        let a = builtin("random-cubes", &small(10, 3)).unwrap();
        assert_eq!(a, builtin("random-cubes", &small(10, 3)).unwrap());
        assert_ne!(a, builtin("random-cubes", &small(10, 4)).unwrap());
        assert_eq!(a.meshes.len(), 11);
        assert_eq!(a.triangle_count(), 10 * 12 + 2 * 64);
    }

    #[test]
    fn random_cubes_speeds_sizes_colours_and_coverage() {
        for cube_size in [1.0, 5.0] {
            let opts = BuiltinOptions {
                cube_count: 200,
                speed_min: 2.0,
                speed_max: 3.0,
                cube_size,
                seed: 9,
                frame_time: None,
                subdivide: 0,
            };
            let s = builtin("random-cubes", &opts).unwrap();
            let Light::Spot(light) = &s.light else {
                panic!("spot expected")
            };
            let cos_cone = light.cone_angle_deg.to_radians().cos();
            for m in s.meshes.iter().filter(|m| m.name.starts_with("cube-")) {
                assert!(m.closed && m.t0.len() == 36);
                let speed = (centre(&m.t1) - centre(&m.t0)).length();
                assert!(
                    (2.0 - 1e-3..=3.0 + 1e-3).contains(&speed),
                    "{}: speed {speed}",
                    m.name
                );
                // The farthest corner from the centre: half the cube's diagonal.
                let c = centre(&m.t0);
                let reach = m.t0.iter().map(|p| (*p - c).length()).fold(0.0, f32::max);
                let half_diagonal = cube_size * 3.0_f32.sqrt() / 2.0;
                assert!((reach - half_diagonal).abs() < 1e-3 * cube_size, "{reach}");
                assert!(m.albedo.min_element() >= 0.1 && m.albedo.max_element() <= 0.9);
                for &p in m.t0.iter().chain(&m.t1) {
                    assert!(p.y > 0.0, "{} goes below the ground", m.name);
                    assert!((p - light.position).normalize().dot(light.direction) > cos_cone);
                }
            }
        }
    }

    /// The framing (camera, light, ground) stays finite and valid at every corner of the
    /// documented ranges, and just past them the options are refused by name.
    #[test]
    fn random_cubes_ranges_frame_valid_scenes_at_their_corners() {
        let (min_size, max_size) = CUBE_SIZE_RANGE;
        for cube_count in [1, 50] {
            for cube_size in [min_size, max_size] {
                for (speed_min, speed_max) in [(0.0, 0.0), (0.0, MAX_CUBE_SPEED)] {
                    let opts = BuiltinOptions {
                        cube_count,
                        speed_min,
                        speed_max,
                        cube_size,
                        seed: 3,
                        frame_time: None,
                        subdivide: 0,
                    };
                    let s =
                        builtin("random-cubes", &opts).unwrap_or_else(|e| panic!("{opts:?}: {e}"));
                    assert_eq!(s.triangle_count(), 12 * cube_count + 128);
                }
            }
        }
        for (opts, needle) in [
            (
                BuiltinOptions {
                    cube_size: max_size * 1.01,
                    ..small(1, 1)
                },
                "cube size",
            ),
            (
                BuiltinOptions {
                    cube_size: min_size * 0.99,
                    ..small(1, 1)
                },
                "cube size",
            ),
            (
                BuiltinOptions {
                    speed_min: 0.0,
                    speed_max: 1e30,
                    ..small(1, 1)
                },
                "speed_max <= 1000",
            ),
            (small(2_796_193, 1), "cube count"),
        ] {
            match builtin("random-cubes", &opts) {
                Err(SceneError::Invalid(m)) => assert!(m.contains(needle), "{m}"),
                other => panic!("{opts:?}: {other:?}"),
            }
        }
    }

    #[test]
    fn bad_names_and_options_are_errors() {
        match builtin("nope", &BuiltinOptions::default()) {
            Err(SceneError::UnknownBuiltin { name, available }) => {
                assert_eq!(name, "nope");
                assert_eq!(available, BUILTIN_NAMES);
            }
            other => panic!("{other:?}"),
        }
        for opts in [
            small(0, 1),
            BuiltinOptions {
                speed_min: 5.0,
                speed_max: 4.0,
                ..Default::default()
            },
            BuiltinOptions {
                speed_min: -1.0,
                ..Default::default()
            },
            BuiltinOptions {
                speed_max: f32::INFINITY,
                ..Default::default()
            },
            BuiltinOptions {
                cube_size: 0.0,
                ..Default::default()
            },
            BuiltinOptions {
                cube_size: f32::NAN,
                ..Default::default()
            },
        ] {
            assert!(
                matches!(builtin("random-cubes", &opts), Err(SceneError::Invalid(_))),
                "{opts:?}"
            );
        }
    }
}
