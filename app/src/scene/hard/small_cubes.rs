//! `hard-small-cubes`: 800 small cubes (edge 0.12) in a layer above the ground, each at a
//! random orientation and moving 1.25 to 3.75 of its sizes in a random direction, casting a
//! dappled, blurred shadow: many small prisms, overlapping in the shadow map.
//!
//! Built like `random-cubes` (the same generator and colours, a fixed seed) but with small
//! cubes moving short distances, so each shadow is a few texels and the shadows overlap.
//!
//! The motion: pure translation of each cube.

use glam::Vec3;

use super::super::file::{BoxSpec, MeshSpec, SceneFile};
use super::super::parts::{ground, random_moving_cube};
use super::super::rng::SplitMix64;
use super::{camera, scene_file, spot};

const LIGHT: Vec3 = Vec3::new(-1.0, 8.0, -5.0);
pub(super) const COUNT: usize = 800;
pub(super) const SIZE: f32 = 0.12;
/// Displacement over the shutter, in units (1.25 to 3.75 edge lengths).
pub(super) const SPEED: (f32, f32) = (0.15, 0.45);
/// The layer's half width (x and z) and its heights at t0.
const HALF_WIDTH: f32 = 2.4;
const HEIGHTS: (f32, f32) = (1.4, 2.0);
const SEED: u64 = 11;

pub(super) fn scene() -> SceneFile {
    let mut rng = SplitMix64::new(SEED);
    let unit = MeshSpec::Box(BoxSpec {
        size: Vec3::splat(SIZE),
        subdivisions: 1,
    });
    let mut objects = vec![ground(16.0, 8)];
    for i in 0..COUNT {
        let p0 = Vec3::new(
            rng.range(-HALF_WIDTH, HALF_WIDTH),
            rng.range(HEIGHTS.0, HEIGHTS.1),
            rng.range(-HALF_WIDTH, HALF_WIDTH),
        );
        objects.push(random_moving_cube(&mut rng, i, &unit, p0, SPEED));
    }
    let middle = Vec3::new(0.0, (HEIGHTS.0 + HEIGHTS.1) * 0.5, 0.0);
    let aim = LIGHT + (middle - LIGHT) * (LIGHT.y / (LIGHT.y - middle.y));
    scene_file(
        "hard-small-cubes",
        camera(Vec3::new(0.0, 10.0, 11.5), Vec3::new(0.0, 0.0, 1.2)),
        spot(LIGHT, aim, 40.0, 1.0, 30.0),
        objects,
    )
}

#[cfg(test)]
mod tests {
    use super::super::check::{casters, centre, scene};
    use super::*;

    #[test]
    fn many_small_cubes_move_a_few_of_their_sizes() {
        let s = scene("hard-small-cubes");
        let cubes: Vec<_> = casters(&s).collect();
        assert_eq!(cubes.len(), COUNT);
        assert!((200..=1000).contains(&COUNT));
        for m in cubes {
            assert!(m.closed && m.t0.len() == 36, "{}", m.name);
            let c = centre(&m.t0);
            let moved = centre(&m.t1) - c;
            for (&a, &b) in m.t0.iter().zip(&m.t1) {
                assert!((b - a - moved).length() < 1e-5, "{} turns", m.name);
                assert!((a - c).length() <= SIZE * 3.0_f32.sqrt() / 2.0 + 1e-5);
            }
            let sizes = moved.length() / SIZE;
            assert!(
                (1.25 - 1e-3..=3.75 + 1e-3).contains(&sizes),
                "{}: {sizes}",
                m.name
            );
        }
    }
}
