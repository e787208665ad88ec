//! The pieces the built-in scenes are made of (objects, transforms, a ground, random cubes),
//! shared by the scene builders and the built-in table, which imports the builders (so the
//! builders do not import it back).

use glam::{Vec2, Vec3};

use super::file::{MeshSpec, ObjectFile, PlaneSpec, TransformFile};
use super::rng::SplitMix64;

pub(super) fn translate(t: Vec3) -> TransformFile {
    TransformFile {
        translation: Some(t),
        ..Default::default()
    }
}

pub(super) fn object(
    name: &str,
    albedo: Vec3,
    closed: bool,
    mesh: MeshSpec,
    t0: TransformFile,
    t1: Option<TransformFile>,
) -> ObjectFile {
    ObjectFile {
        name: name.to_owned(),
        albedo,
        closed,
        mesh,
        t0: (t0 != TransformFile::default()).then_some(t0),
        t1,
    }
}

pub(super) fn ground(size: f32, subdivisions: u32) -> ObjectFile {
    let mesh = MeshSpec::Plane(PlaneSpec {
        size: Vec2::splat(size),
        subdivisions,
    });
    object(
        "ground",
        Vec3::splat(0.8),
        false,
        mesh,
        TransformFile::default(),
        None,
    )
}

/// Pleasant, not garish: moderate saturation and value, any hue.
pub(super) fn random_albedo(rng: &mut SplitMix64) -> Vec3 {
    let (h, s, v) = (
        rng.range(0.0, 6.0),
        rng.range(0.45, 0.75),
        rng.range(0.6, 0.9),
    );
    let f = |n: f32| {
        let k = (n + h) % 6.0;
        v - v * s * k.min(4.0 - k).clamp(0.0, 1.0)
    };
    Vec3::new(f(5.0), f(3.0), f(1.0))
}

/// Cube `i` of a random field (`random-cubes`, `hard-small-cubes`): at `p0` in a random
/// orientation, moving a random distance in `speed` in a random direction, a random albedo.
pub(super) fn random_moving_cube(
    rng: &mut SplitMix64,
    i: usize,
    unit: &MeshSpec,
    p0: Vec3,
    speed: (f32, f32),
) -> ObjectFile {
    let t0 = TransformFile {
        translation: Some(p0),
        rotation_axis: Some(rng.unit_vector()),
        rotation_deg: Some(rng.range(0.0, 360.0)),
        scale: None,
    };
    let p1 = p0 + rng.unit_vector() * rng.range(speed.0, speed.1);
    let albedo = random_albedo(rng);
    object(
        &format!("cube-{i}"),
        albedo,
        true,
        unit.clone(),
        t0,
        Some(translate(p1)),
    )
}
