//! The hard scenes of issue 11: small scenes built so that each isolates one motion or
//! lighting case where a shadow-map method may be wrong even when its own brute-force
//! reference agrees with it. They are measured against an exact (ray-traced) truth, so each
//! keeps every caster inside the light's cone (or box), its shadows on the ground in the
//! camera's view, and is small enough for a CPU ray tracer (at most ~10k triangles).
//!
//! Every vertex moves linearly from its t0 to its t1 position (the scene format's only
//! motion). Where a scene asks for rotation, its two poses are the rigid poses at the start
//! and end angle, and in between each point moves on the chord: the file of each scene says
//! what the motion really is.

mod deforming;
mod grazing;
mod hinged_limb;
mod near_plane;
mod propeller;
mod rotating_triangle;
mod small_cubes;
mod static_silhouette;
mod thin_fast;
mod turning_light;

use glam::{Quat, Vec3};

use super::file::{
    CameraFile, LightFile, MeshSpec, ObjectFile, SCENE_FORMAT, SceneFile, TrianglesSpec,
};

/// The hard scenes, in the order the bench reports them.
pub const HARD_NAMES: &[&str] = &[
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

/// The hard scene `name`, or `None` when there is none of that name.
pub(super) fn hard_scene(name: &str) -> Option<SceneFile> {
    Some(match name {
        "hard-rotating-triangle" => rotating_triangle::scene(),
        "hard-hinged-limb" => hinged_limb::scene(),
        "hard-propeller" => propeller::scene(),
        "hard-near-plane" => near_plane::scene(),
        "hard-grazing" => grazing::scene(),
        "hard-thin-fast" => thin_fast::scene(),
        "hard-deforming" => deforming::scene(),
        "hard-small-cubes" => small_cubes::scene(),
        "hard-static-silhouette" => static_silhouette::scene(),
        "hard-turning-light" => turning_light::scene(),
        _ => return None,
    })
}

/// Albedo of every hard scene's ground (the built-in scenes' grey).
const GROUND_ALBEDO: f32 = 0.8;
/// Radiance of the lit ground where a spot light is aimed.
const GROUND_RADIANCE: f32 = 0.45;

fn scene_file(
    name: &str,
    camera: CameraFile,
    light: LightFile,
    objects: Vec<ObjectFile>,
) -> SceneFile {
    SceneFile {
        format: SCENE_FORMAT.to_owned(),
        name: Some(name.to_owned()),
        camera,
        light,
        ambient: 0.0,
        objects,
    }
}

/// A fov-45 camera at `position` looking at `target`, y up.
fn camera(position: Vec3, target: Vec3) -> CameraFile {
    CameraFile {
        position,
        target,
        up: Vec3::Y,
        fov_y_deg: 45.0,
        near: 0.1,
        far: 100.0,
        t1: None,
    }
}

/// A spot light at `position` aimed at `aim` on the ground (y = 0), bright enough that the
/// ground there has radiance [`GROUND_RADIANCE`]: albedo/pi * I * cos / d^2.
fn spot(position: Vec3, aim: Vec3, cone_angle_deg: f32, near: f32, far: f32) -> LightFile {
    let d = position - aim;
    let cos = d.y / d.length();
    LightFile::Spot {
        position,
        direction: aim - position,
        cone_angle_deg,
        intensity: GROUND_RADIANCE * std::f32::consts::PI / GROUND_ALBEDO * d.length_squared()
            / cos,
        near,
        far,
        t1: None,
    }
}

/// Explicit per-vertex positions (the object's transform, if any, applies to both).
fn triangles(t0: Vec<Vec3>, t1: Vec<Vec3>) -> MeshSpec {
    MeshSpec::Triangles(TrianglesSpec { t0, t1: Some(t1) })
}

/// Rotation of `deg` degrees about `axis` (right-hand rule).
fn turn(axis: Vec3, deg: f32) -> Quat {
    Quat::from_axis_angle(axis.normalize(), deg.to_radians())
}

#[cfg(test)]
pub(super) mod check {
    //! What every hard scene's tests check: framing, light coverage, size.

    use glam::Vec3;

    use super::super::{BuiltinOptions, Light, Mesh, Scene, builtin};

    pub fn scene(name: &str) -> Scene {
        builtin(name, &BuiltinOptions::default()).unwrap()
    }

    pub fn mesh<'a>(s: &'a Scene, name: &str) -> &'a Mesh {
        s.meshes
            .iter()
            .find(|m| m.name == name)
            .unwrap_or_else(|| panic!("{}: no mesh {name}", s.name))
    }

    /// Every mesh but the ground.
    pub fn casters(s: &Scene) -> impl Iterator<Item = &Mesh> {
        s.meshes.iter().filter(|m| m.name != "ground")
    }

    /// The mean of the distinct points (a tessellated face lists some vertices more often
    /// than others, so the mean of a triangle list is not its centre).
    pub fn centre(points: &[Vec3]) -> Vec3 {
        let mut seen = std::collections::HashSet::new();
        let distinct: Vec<Vec3> = points
            .iter()
            .copied()
            .filter(|p| seen.insert(p.to_array().map(f32::to_bits)))
            .collect();
        distinct.iter().sum::<Vec3>() / distinct.len() as f32
    }

    /// The light at t = 0 and at t = 1 (a still light twice): a moving light's casters must
    /// be lit, and their shadows on the ground, at both ends.
    pub fn light_ends(light: &Light) -> [Light; 2] {
        let mut end = light.clone();
        match &mut end {
            Light::Spot(s) => {
                if let Some(pose) = s.t1.take() {
                    (s.position, s.direction) = (pose.position, pose.direction);
                }
            }
            Light::Directional(d) => {
                if let Some(pose) = d.t1.take() {
                    (d.direction, d.center) = (pose.direction, pose.center);
                }
            }
        }
        [light.clone(), end]
    }

    /// Where the light through `p` meets the ground plane y = 0.
    pub fn shadow_on_ground(light: &Light, p: Vec3) -> Vec3 {
        let ray = match light {
            Light::Spot(s) => p - s.position,
            Light::Directional(d) => d.direction,
        };
        assert!(ray.y < 0.0, "{p} does not cast downward");
        p + ray * (p.y / -ray.y)
    }

    /// Whether `p` is lit by the light's cone (spot, with a margin) or inside its box
    /// (directional: within the box's inscribed cylinder and depth range).
    pub fn in_light(light: &Light, p: Vec3) -> bool {
        match light {
            Light::Spot(s) => {
                let d = p - s.position;
                let cos_cone = s.cone_angle_deg.to_radians().cos();
                d.normalize().dot(s.direction) > cos_cone + 0.02 && d.length() < s.far
            }
            Light::Directional(d) => {
                let rel = p - d.eye();
                let depth = rel.dot(d.direction);
                let across = (rel - d.direction * depth).length();
                depth > d.near && depth < d.far && across < d.half_extent
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::{BUILTIN_NAMES, Light};
    use super::check::*;
    use super::*;

    #[test]
    fn every_hard_scene_is_a_builtin() {
        for name in HARD_NAMES {
            assert!(BUILTIN_NAMES.contains(name), "{name}");
            assert_eq!(scene(name).name, *name);
        }
        let hard = BUILTIN_NAMES
            .iter()
            .filter(|n| n.starts_with("hard-"))
            .count();
        assert_eq!(hard, HARD_NAMES.len());
    }

    /// The scene format's built-in list and the README name every hard scene.
    #[test]
    fn every_hard_scene_is_documented() {
        let doc = include_str!("../../../../docs/scene-format.md");
        let readme = include_str!("../../../../README.md");
        for name in HARD_NAMES {
            assert!(
                doc.contains(&format!("- `{name}`")),
                "docs/scene-format.md: {name}"
            );
            assert!(readme.contains(&format!("`{name}`")), "README.md: {name}");
        }
    }

    /// Small enough for the ray tracer, every caster lit at both ends of the shutter (so at
    /// every time: the cone and the box are convex and vertices move on straight lines), its
    /// shadow on the ground plane and on screen (aspect 1, the narrowest likely). The shadow
    /// of a segment is a segment, so the ends suffice.
    #[test]
    fn casters_are_lit_and_their_shadows_on_screen() {
        for name in HARD_NAMES {
            let s = scene(name);
            let n = s.triangle_count();
            assert!((1..=15_000).contains(&n), "{name}: {n} triangles");
            let ground = mesh(&s, "ground");
            let (lo, hi) = ground
                .t0
                .iter()
                .fold((Vec3::MAX, Vec3::MIN), |(a, b), &p| (a.min(p), b.max(p)));
            assert!(lo.y == 0.0 && hi.y == 0.0, "{name}: the ground is at y = 0");
            assert_eq!(ground.t0, ground.t1);
            let mut count = 0;
            for m in casters(&s) {
                for (&p, light) in
                    m.t0.iter()
                        .chain(&m.t1)
                        .flat_map(|p| light_ends(&s.light).map(|l| (p, l)))
                {
                    assert!(p.y >= 0.0, "{name}: {} below the ground at {p}", m.name);
                    assert!(in_light(&light, p), "{name}: {} unlit at {p}", m.name);
                    let hit = shadow_on_ground(&light, p);
                    assert!(
                        hit.x > lo.x && hit.x < hi.x && hit.z > lo.z && hit.z < hi.z,
                        "{name}: {}'s shadow off the ground at {hit}",
                        m.name
                    );
                    let ndc = s.camera.ndc_unit_aspect(hit);
                    assert!(
                        ndc.x.abs() < 0.95 && ndc.y.abs() < 0.95,
                        "{name}: {}'s shadow off screen: {ndc}",
                        m.name
                    );
                    count += 1;
                }
            }
            assert!(count > 0, "{name}: no casters");
        }
    }

    /// The lit ground has radiance ~0.2-0.6 where the shadows fall (so the default exposure
    /// shows them), computed as the renderer does.
    #[test]
    fn ground_radiance_under_the_casters_is_moderate() {
        for name in HARD_NAMES {
            let s = scene(name);
            let hits: Vec<Vec3> = casters(&s)
                .flat_map(|m| m.t0.iter().chain(&m.t1))
                .map(|&p| shadow_on_ground(&s.light, p))
                .collect();
            let at = centre(&hits);
            let radiance = match &s.light {
                Light::Spot(l) => {
                    let d = l.position - at;
                    GROUND_ALBEDO / std::f32::consts::PI * l.intensity * d.normalize().y
                        / d.length_squared()
                }
                Light::Directional(l) => {
                    GROUND_ALBEDO / std::f32::consts::PI * l.irradiance * -l.direction.y
                }
            };
            assert!((0.2..0.6).contains(&radiance), "{name}: {radiance}");
        }
    }
}
