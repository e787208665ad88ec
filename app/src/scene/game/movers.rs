//! `game-level`'s moving casters, as a game would have them: the player character walking
//! through the room, the arms of a spinning trap, and two crates thrown off the landing.
//! Everything is a function of the time at shutter open, so `animate` can pose the whole
//! scene at any time; the shutter is a 180-degree one at 30 fps (1/60 s).
//!
//! Each motion repeats (the walk along its path, the throws) so any time gives a scene with
//! everything in the room. Vertices move linearly over the shutter: the spinner's arms and
//! the crates' tumble are chord blends of two rigid poses (12 degrees apart for the arms, 9
//! at most for the crates, so the arms shrink at most 0.6% mid-shutter).

use glam::Vec3;

use super::super::SceneError;
use super::super::character::{CESIUM_MAN, animated_object};
use super::super::file::{BoxSpec, MeshSpec, ObjectFile, TransformFile};
use super::super::gltf::{AnimationRef, GltfOptions};
use super::super::parts::{object, translate};
use super::level::{CRATE_ALBEDO, LANDING_HEIGHT, SPINNER_AT, SPINNER_POST_HEIGHT};

/// Shutter: 180 degrees at 30 fps, half a frame.
pub(super) const SHUTTER: f32 = 1.0 / 60.0;

/// CesiumMan's walk cycle, seconds (its animation's keys run from 0 to 2 s and its first and
/// last poses are the same), looped here: glTF samplers clamp rather than loop, so a shutter
/// opening in the cycle's last 1/60 s ends on the last pose.
pub(super) const WALK_CYCLE: f32 = 2.0;
/// The walker's speed, m/s: what its planted foot slides back at in the model's in-place
/// walk (0.6-1.3 m/s over a stance, ~0.75 on average over the cycle's frames), so carrying
/// the model at it keeps that foot roughly still on the floor; a slow walk.
pub(super) const WALK_SPEED: f32 = 0.75;
/// It walks toward -z along x = WALK_X, from WALK_Z.0 to WALK_Z.1, then starts again.
pub(super) const WALK_X: f32 = 0.2;
pub(super) const WALK_Z: (f32, f32) = (3.0, -6.0);
/// The model faces +x; turned this far about +y it faces -z, into the room.
const FACING_DEG: f32 = 90.0;

/// The trap's two arms turn this fast about the post (2 turns a second).
pub(super) const SPIN_DEG_PER_S: f32 = 720.0;
/// How far the spinner's arms reach from its axis.
pub(super) const SPINNER_REACH: f32 = 1.6;
/// Each arm: length, thickness, width; at the post's top, centred on its axis.
const ARM: Vec3 = Vec3::new(2.0 * SPINNER_REACH, 0.1, 0.2);
const ARM_SUBDIVISIONS: u32 = 6;

const GRAVITY: f32 = 9.81;
pub(super) const THROWN_EDGE: f32 = 0.5;
const THROWN_SUBDIVISIONS: u32 = 5;
/// A thrown crate: where its centre starts, its launch velocity (m/s), its tumble (axis,
/// degrees a second), and when in the repeat its first throw is.
pub(super) struct Throw {
    pub start: Vec3,
    pub velocity: Vec3,
    pub spin_axis: Vec3,
    pub spin_deg_per_s: f32,
    pub phase: f32,
}

/// From the landing over the room toward the front left, past the right row of pillars;
/// each lands on the floor, then the throw repeats.
pub(super) const THROWS: [Throw; 2] = [
    Throw {
        start: Vec3::new(6.5, LANDING_HEIGHT + 0.5, -3.0),
        velocity: Vec3::new(-5.5, 2.0, 2.5),
        spin_axis: Vec3::new(0.3, 0.2, 1.0),
        spin_deg_per_s: 540.0,
        phase: 0.0,
    },
    Throw {
        start: Vec3::new(6.8, LANDING_HEIGHT + 0.5, -5.5),
        velocity: Vec3::new(-4.5, 3.0, 2.5),
        spin_axis: Vec3::new(1.0, 0.4, 0.1),
        spin_deg_per_s: -450.0,
        phase: 0.25,
    },
];

impl Throw {
    /// Seconds from the throw until the crate's centre is half an edge above the floor.
    pub(super) fn flight(&self) -> f32 {
        let (y0, vy, floor) = (self.start.y, self.velocity.y, 0.5 * THROWN_EDGE);
        (vy + (vy * vy + 2.0 * GRAVITY * (y0 - floor)).sqrt()) / GRAVITY
    }

    /// Centre and tumble angle `tau` seconds after the throw.
    pub(super) fn at(&self, tau: f32) -> (Vec3, f32) {
        let centre = self.start + self.velocity * tau - Vec3::Y * (0.5 * GRAVITY * tau * tau);
        (centre, self.spin_deg_per_s * tau)
    }

    /// Seconds since the latest throw at scene time `time` (reduced in f64: see `movers`).
    pub(super) fn since_throw(&self, time: f64) -> f32 {
        (time + f64::from(self.phase)).rem_euclid(f64::from(self.flight())) as f32
    }
}

/// `time` is f64 and each motion reduces it modulo its own loop before anything is single
/// precision: an f32 time far from 0 (`animate --start 1e8`) steps by seconds, so
/// consecutive frames came out the same.
pub(super) fn movers(time: f64, subdivide: u32) -> Result<Vec<ObjectFile>, SceneError> {
    let mut objects = vec![walker(time, subdivide)?];
    objects.extend(spinner_arms(time));
    for (i, throw) in THROWS.iter().enumerate() {
        objects.push(thrown_crate(i, throw, time));
    }
    Ok(objects)
}

/// Where the walker's root is at `time`: along its path, looping.
pub(super) fn walker_position(time: f64) -> Vec3 {
    let length = f64::from(WALK_Z.0 - WALK_Z.1);
    let along = (f64::from(WALK_SPEED) * time).rem_euclid(length) as f32;
    Vec3::new(WALK_X, 0.0, WALK_Z.0 - along)
}

/// CesiumMan at `time` into its looped walk, carried along its path over the shutter (the
/// whole path is shifted, not wrapped, within one shutter, so the motion stays linear).
fn walker(time: f64, subdivide: u32) -> Result<ObjectFile, SceneError> {
    let at = walker_position(time);
    let mut walker = animated_object(
        "walker",
        Vec3::new(0.3, 0.45, 0.7),
        CESIUM_MAN,
        &GltfOptions {
            animation: Some(AnimationRef::Index(0)),
            time: time.rem_euclid(f64::from(WALK_CYCLE)) as f32,
            shutter: SHUTTER,
            subdivide,
        },
        TransformFile {
            translation: Some(at),
            rotation_axis: Some(Vec3::Y),
            rotation_deg: Some(FACING_DEG),
            scale: None,
        },
    )?;
    walker.t1 = Some(translate(at - Vec3::Z * (WALK_SPEED * SHUTTER)));
    Ok(walker)
}

/// The trap's two crossed arms, turned by the spin at shutter open and close.
fn spinner_arms(time: f64) -> Vec<ObjectFile> {
    let centre = Vec3::new(SPINNER_AT.x, SPINNER_POST_HEIGHT - ARM.y, SPINNER_AT.y);
    let start = (f64::from(SPIN_DEG_PER_S) * time).rem_euclid(360.0) as f32;
    let pose = |deg: f32| TransformFile {
        translation: Some(centre),
        rotation_axis: Some(Vec3::Y),
        rotation_deg: Some(deg),
        scale: None,
    };
    let arm = MeshSpec::Box(BoxSpec {
        size: ARM,
        subdivisions: ARM_SUBDIVISIONS,
    });
    [0.0, 90.0]
        .iter()
        .enumerate()
        .map(|(i, offset)| {
            let deg = start + offset;
            object(
                &format!("spinner-arm-{i}"),
                Vec3::new(0.75, 0.2, 0.15),
                true,
                arm.clone(),
                pose(deg),
                Some(pose(deg + SPIN_DEG_PER_S * SHUTTER)),
            )
        })
        .collect()
}

/// A crate along its throw at shutter open and close. A shutter that opens just before the
/// landing finishes the same flight, so the motion stays one straight line per vertex (the
/// crate then dips into the floor by at most a shutter's fall, ~16 cm).
fn thrown_crate(i: usize, throw: &Throw, time: f64) -> ObjectFile {
    let tau = throw.since_throw(time);
    let pose = |tau: f32| {
        let (centre, deg) = throw.at(tau);
        TransformFile {
            translation: Some(centre),
            rotation_axis: Some(throw.spin_axis),
            rotation_deg: Some(deg),
            scale: None,
        }
    };
    let mesh = MeshSpec::Box(BoxSpec {
        size: Vec3::splat(THROWN_EDGE),
        subdivisions: THROWN_SUBDIVISIONS,
    });
    object(
        &format!("thrown-crate-{i}"),
        CRATE_ALBEDO,
        true,
        mesh,
        pose(tau),
        Some(pose(tau + SHUTTER)),
    )
}
