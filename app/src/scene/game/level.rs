//! `game-level`'s static level: a floor, walls with doorways, two rows of round pillars
//! carrying beams, a staircase up to a landing, stacked crates and the post of a spinning
//! trap. Nothing here moves (no `t1`), as most of a game's triangles do not; the
//! tessellation is a game level's order of detail (~50,000 triangles) so that what a
//! static triangle costs the shadow pass shows in the bench.
//!
//! Units are metres; y is up, the camera looks toward -z. The room's floor spans
//! x in [-ROOM_HALF_X, ROOM_HALF_X], z in [ROOM_BACK_Z, ROOM_FRONT_Z]; the front is open
//! (the camera is there).

use glam::{Vec2, Vec3};

use super::super::file::{BoxSpec, MeshSpec, ObjectFile, PlaneSpec, TrianglesSpec};
use super::super::parts::{object, translate};
use super::cylinder::cylinder_mesh;

pub(super) const ROOM_HALF_X: f32 = 8.0;
pub(super) const ROOM_BACK_Z: f32 = -8.0;
pub(super) const ROOM_FRONT_Z: f32 = 6.0;
const WALL_HEIGHT: f32 = 4.5;
const WALL_THICKNESS: f32 = 0.4;
/// Doorways: 2 m wide, 3 m high.
const DOOR_HALF_WIDTH: f32 = 1.0;
const DOOR_HEIGHT: f32 = 3.0;
/// The side doorway in the left wall is centred here.
const SIDE_DOOR_Z: f32 = -3.0;

/// Pillar rows at x = +-PILLAR_X, at these z.
pub(super) const PILLAR_X: f32 = 4.0;
pub(super) const PILLAR_ZS: [f32; 4] = [-6.0, -3.0, 0.0, 3.0];
const PILLAR_RADIUS: f32 = 0.3;
const PLINTH: Vec3 = Vec3::new(0.9, 0.3, 0.9);
const CAPITAL: Vec3 = Vec3::new(0.9, 0.5, 0.9);
const BEAM: Vec2 = Vec2::new(0.7, 0.5);

/// The staircase runs along the right wall from STAIR_FRONT_Z toward -z, STEPS steps up to
/// a landing reaching the back wall.
const STAIR_X: (f32, f32) = (6.0, ROOM_HALF_X);
const STAIR_FRONT_Z: f32 = 1.5;
const STEPS: u32 = 9;
const STEP_RISE: f32 = 0.3;
const STEP_RUN: f32 = 0.45;
pub(super) const LANDING_HEIGHT: f32 = STEPS as f32 * STEP_RISE;

/// The spinning trap's post (its arms move: `movers.rs`).
pub(super) const SPINNER_AT: Vec2 = Vec2::new(-2.3, -3.0);
pub(super) const SPINNER_POST_HEIGHT: f32 = 1.1;

/// Quads per side of each face: `12 n^2` triangles a box, `2 n^2` the floor.
const FLOOR_SUBDIVISIONS: u32 = 80;
const WALL_SUBDIVISIONS: u32 = 13;
const BEAM_SUBDIVISIONS: u32 = 16;
const LANDING_SUBDIVISIONS: u32 = 12;
const STEP_SUBDIVISIONS: u32 = 5;
const PILLAR_PART_SUBDIVISIONS: u32 = 4;
const CRATE_SUBDIVISIONS: u32 = 8;
/// Facets around and rings up a pillar's shaft and the spinner's post.
const PILLAR_FACETS: (u32, u32) = (24, 12);
const POST_FACETS: (u32, u32) = (16, 4);

const FLOOR_ALBEDO: Vec3 = Vec3::new(0.62, 0.6, 0.56);
const WALL_ALBEDO: Vec3 = Vec3::new(0.72, 0.68, 0.6);
const STONE_ALBEDO: Vec3 = Vec3::new(0.78, 0.76, 0.72);
const WOOD_ALBEDO: Vec3 = Vec3::new(0.55, 0.38, 0.22);
pub(super) const CRATE_ALBEDO: Vec3 = Vec3::new(0.7, 0.52, 0.3);
const METAL_ALBEDO: Vec3 = Vec3::new(0.45, 0.47, 0.5);

/// A static closed box spanning `lo` to `hi`.
fn block(name: &str, albedo: Vec3, lo: Vec3, hi: Vec3, subdivisions: u32) -> ObjectFile {
    let mesh = MeshSpec::Box(BoxSpec {
        size: hi - lo,
        subdivisions,
    });
    object(name, albedo, true, mesh, translate((lo + hi) * 0.5), None)
}

/// A static closed cylinder standing on `base`.
fn column(
    name: &str,
    albedo: Vec3,
    base: Vec3,
    radius: f32,
    height: f32,
    facets: (u32, u32),
) -> ObjectFile {
    let t0 = cylinder_mesh(radius, height, facets.0, facets.1);
    let mesh = MeshSpec::Triangles(TrianglesSpec { t0, t1: None });
    object(name, albedo, true, mesh, translate(base), None)
}

pub(super) fn level() -> Vec<ObjectFile> {
    let mut objects = vec![floor()];
    objects.extend(walls());
    objects.extend(pillars());
    objects.extend(stairs());
    objects.extend(crates());
    objects.push(column(
        "spinner-post",
        METAL_ALBEDO,
        Vec3::new(SPINNER_AT.x, 0.0, SPINNER_AT.y),
        0.12,
        SPINNER_POST_HEIGHT,
        POST_FACETS,
    ));
    objects
}

fn floor() -> ObjectFile {
    let size = Vec2::new(2.0 * ROOM_HALF_X, ROOM_FRONT_Z - ROOM_BACK_Z);
    let mesh = MeshSpec::Plane(PlaneSpec {
        size,
        subdivisions: FLOOR_SUBDIVISIONS,
    });
    let centre = Vec3::new(0.0, 0.0, (ROOM_FRONT_Z + ROOM_BACK_Z) * 0.5);
    object("floor", FLOOR_ALBEDO, false, mesh, translate(centre), None)
}

/// The back wall (a doorway in its middle) and the left wall (a doorway at SIDE_DOOR_Z)
/// are each two pieces and a lintel; the right wall is whole. The side walls run past the
/// back wall's ends to close the corners.
fn walls() -> Vec<ObjectFile> {
    let (x, t, h) = (ROOM_HALF_X, WALL_THICKNESS, WALL_HEIGHT);
    let (back, front) = (ROOM_BACK_Z, ROOM_FRONT_Z);
    let (d, door_h) = (DOOR_HALF_WIDTH, DOOR_HEIGHT);
    let n = WALL_SUBDIVISIONS;
    let wall = |name: &str, lo: Vec3, hi: Vec3| block(name, WALL_ALBEDO, lo, hi, n);
    vec![
        wall(
            "wall-back-left",
            Vec3::new(-x, 0.0, back - t),
            Vec3::new(-d, h, back),
        ),
        wall(
            "wall-back-right",
            Vec3::new(d, 0.0, back - t),
            Vec3::new(x, h, back),
        ),
        wall(
            "wall-back-lintel",
            Vec3::new(-d, door_h, back - t),
            Vec3::new(d, h, back),
        ),
        wall(
            "wall-left-back",
            Vec3::new(-x - t, 0.0, back - t),
            Vec3::new(-x, h, SIDE_DOOR_Z - d),
        ),
        wall(
            "wall-left-front",
            Vec3::new(-x - t, 0.0, SIDE_DOOR_Z + d),
            Vec3::new(-x, h, front),
        ),
        wall(
            "wall-left-lintel",
            Vec3::new(-x - t, door_h, SIDE_DOOR_Z - d),
            Vec3::new(-x, h, SIDE_DOOR_Z + d),
        ),
        wall(
            "wall-right",
            Vec3::new(x, 0.0, back - t),
            Vec3::new(x + t, h, front),
        ),
    ]
}

/// Each pillar: a square plinth, a round shaft and a square capital; a beam along each
/// row rests on the capitals and runs from the back wall to the front of the room.
fn pillars() -> Vec<ObjectFile> {
    let n = PILLAR_PART_SUBDIVISIONS;
    let shaft = WALL_HEIGHT - PLINTH.y - CAPITAL.y;
    let mut objects = Vec::new();
    for (side, x) in [("left", -PILLAR_X), ("right", PILLAR_X)] {
        for (i, &z) in PILLAR_ZS.iter().enumerate() {
            let foot = Vec3::new(x, 0.0, z);
            let half = Vec3::new(0.5, 0.0, 0.5);
            objects.push(block(
                &format!("plinth-{side}-{i}"),
                STONE_ALBEDO,
                foot - half * PLINTH,
                foot + PLINTH * Vec3::new(0.5, 1.0, 0.5),
                n,
            ));
            objects.push(column(
                &format!("pillar-{side}-{i}"),
                STONE_ALBEDO,
                foot + Vec3::Y * PLINTH.y,
                PILLAR_RADIUS,
                shaft,
                PILLAR_FACETS,
            ));
            let top = foot + Vec3::Y * (PLINTH.y + shaft);
            objects.push(block(
                &format!("capital-{side}-{i}"),
                STONE_ALBEDO,
                top - half * CAPITAL,
                top + CAPITAL * Vec3::new(0.5, 1.0, 0.5),
                n,
            ));
        }
        objects.push(block(
            &format!("beam-{side}"),
            WOOD_ALBEDO,
            Vec3::new(x - BEAM.x * 0.5, WALL_HEIGHT, ROOM_BACK_Z),
            Vec3::new(x + BEAM.x * 0.5, WALL_HEIGHT + BEAM.y, ROOM_FRONT_Z),
            BEAM_SUBDIVISIONS,
        ));
    }
    objects
}

/// Steps as a stack of solid blocks (step i is i + 1 rises tall), then the landing.
fn stairs() -> Vec<ObjectFile> {
    let (x0, x1) = STAIR_X;
    let mut objects: Vec<ObjectFile> = (0..STEPS)
        .map(|i| {
            let z_front = STAIR_FRONT_Z - i as f32 * STEP_RUN;
            block(
                &format!("step-{i}"),
                STONE_ALBEDO,
                Vec3::new(x0, 0.0, z_front - STEP_RUN),
                Vec3::new(x1, (i + 1) as f32 * STEP_RISE, z_front),
                STEP_SUBDIVISIONS,
            )
        })
        .collect();
    let landing_front = STAIR_FRONT_Z - STEPS as f32 * STEP_RUN;
    objects.push(block(
        "landing",
        STONE_ALBEDO,
        Vec3::new(x0, 0.0, ROOM_BACK_Z),
        Vec3::new(x1, LANDING_HEIGHT, landing_front),
        LANDING_SUBDIVISIONS,
    ));
    objects
}

/// Crates in the left corners, one stacked on others.
fn crates() -> Vec<ObjectFile> {
    let n = CRATE_SUBDIVISIONS;
    // (centre of the bottom face, edge length)
    let stacks = [
        (Vec3::new(-6.6, 0.0, 3.6), 0.9),
        (Vec3::new(-5.6, 0.0, 3.9), 0.8),
        (Vec3::new(-6.4, 0.9, 3.7), 0.7),
        (Vec3::new(-6.5, 0.0, 2.5), 0.8),
        (Vec3::new(-6.6, 0.0, -7.2), 0.9),
        (Vec3::new(-5.8, 0.0, -6.4), 0.6),
    ];
    stacks
        .iter()
        .enumerate()
        .map(|(i, &(bottom, edge))| {
            let half = Vec3::new(edge * 0.5, 0.0, edge * 0.5);
            block(
                &format!("crate-{i}"),
                CRATE_ALBEDO,
                bottom - half,
                bottom + half + Vec3::Y * edge,
                n,
            )
        })
        .collect()
}
