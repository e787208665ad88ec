//! TSM-N exactly: the maps sit at the centres of the shutter's strata, (i + 0.5) / N.

use super::rig::{Frame, Mesh, Rig, errors, light, rect, shifted};
use super::{CONFIGS, HALF, SHADOW, SIZE, TEXEL};
use crate::support::gpu::{assert_no_validation_messages, context};
use glam::Vec3;
use motion_shadows::technique::EngineTsmMap;

/// The lit fraction TSM-N must give exactly, counting the maps' times t_i = (i + 0.5) / N at
/// which `shadowed(t_i)` is false; None where a time's shadow edge lies within `margin` of the
/// point (`edge_distance(t)`: the distance at time t to the nearer edge), where the texel a
/// receiver reads may fall on either side.
fn stratified_lit_fraction(
    n: u32,
    margin: f32,
    shadowed: impl Fn(f32) -> bool,
    edge_distance: impl Fn(f32) -> f32,
) -> Option<f32> {
    let times = (0..n).map(|i| (i as f32 + 0.5) / n as f32);
    if times.clone().any(|t| edge_distance(t) < margin) {
        return None;
    }
    Some(times.filter(|t| !shadowed(*t)).count() as f32 / n as f32)
}

/// TSM-1 and TSM-4 exactly: away from the shadows' edges a pixel's mask is the count of the
/// maps whose time t_i = (i + 0.5) / N sees the light, over N, for a square translating over
/// a still ground and for the ground translating under a still square (light straight down,
/// pixels within two texels of an edge at some t_i left out). The convergence tests' bound
/// (1/N plus a texel's motion) cannot tell a map drawn at i/N from one at (i + 0.5)/N; this
/// can: fails when the maps' times, or the receivers' times, are off the strata's centres.
#[test]
fn engine_tsm_samples_the_strata_centres() {
    let ctx = context();
    let d = 1.5f32;
    let margin = 2.0 * TEXEL;
    let inside = |p: Vec3| p.x.abs() < HALF - 0.1 && p.z.abs() < 1.0 - margin;
    // A square [x0, x0 + s] at t = 0 moving by D over the still ground.
    let (x0, s) = (-1.5f32, 1.0f32);
    let ground = Mesh::new(&ctx, &rect(-6.0, 6.0, -6.0, 6.0, 0.0), None);
    let square = rect(x0, x0 + s, -1.0, 1.0, 1.0);
    let moving_square = Mesh::new(&ctx, &square, Some(&shifted(&square, Vec3::X * d)));
    // The ground moving by D (seen at t = 1) under a still square [c0, c0 + s].
    let c0 = -0.5f32;
    let plane = rect(-6.0, 6.0, -6.0, 6.0, 0.0);
    let moving_ground = Mesh::new(&ctx, &plane, Some(&shifted(&plane, Vec3::X * d)));
    let still_square = Mesh::new(&ctx, &rect(c0, c0 + s, -1.0, 1.0, 1.0), None);
    let light = light(Vec3::NEG_Y, false);
    let mut rig = Rig::new(&ctx);
    for (start, layers) in CONFIGS {
        let map = EngineTsmMap::new(&ctx, SHADOW, SHADOW, layers, start).expect("map");
        for n in [1, 4] {
            for moving_receiver in [false, true] {
                let (receivers, casters) = if moving_receiver {
                    (
                        [moving_ground.draw(0)],
                        [moving_ground.draw(0), still_square.draw(2)],
                    )
                } else {
                    ([ground.draw(0)], [ground.draw(0), moving_square.draw(2)])
                };
                // Where the point seen at x (at shutter close) is at time t, and the square's
                // extent then.
                let at = |x: f32, t: f32| {
                    if moving_receiver {
                        x + (t - 1.0) * d
                    } else {
                        x
                    }
                };
                let extent = |t: f32| {
                    let a = if moving_receiver { c0 } else { x0 + d * t };
                    (a, a + s)
                };
                let expected = |p: Vec3| {
                    if !inside(p) || (moving_receiver && p.x - d < -HALF + 0.1) {
                        return None;
                    }
                    stratified_lit_fraction(
                        n,
                        margin,
                        |t| (extent(t).0..=extent(t).1).contains(&at(p.x, t)),
                        |t| {
                            (at(p.x, t) - extent(t).0)
                                .abs()
                                .min((at(p.x, t) - extent(t).1).abs())
                        },
                    )
                };
                let frame = Frame {
                    receivers: &receivers,
                    casters: &casters,
                    light: &light,
                    maps: n,
                    gbuffer_time: 1.0,
                    moving_receivers: moving_receiver,
                    draw_gbuffer: true,
                };
                let mask = rig.run(&frame, &map).expect("frame");
                let found = errors(&rig, &mask, expected);
                let what =
                    format!("{start:?} x{layers}, N = {n}, moving receiver {moving_receiver}");
                assert!(
                    found.iter().filter(|f| f.2 < 1.0).count() > 100,
                    "{what}: too few shadowed pixels to check"
                );
                for &(i, got, want) in &found {
                    assert!(
                        got == want,
                        "{what}: pixel ({}, {}) lit {got}, the maps at (i + 0.5)/N give {want}",
                        i as u32 % SIZE.0,
                        i as u32 / SIZE.0
                    );
                }
            }
        }
    }
    drop(rig);
    assert_no_validation_messages(&ctx);
}
