//! TSM-N converges to the shutter's lit fraction: within 1/N plus a texel's worth of motion at
//! every pixel, the mean error falling as N grows, for a moving caster and a moving receiver.

use super::rig::{Frame, Mesh, Rig, errors, light, rect, shifted};
use super::{CONFIGS, HALF, SHADOW, SIZE, TEXEL};
use crate::support::gpu::{assert_no_validation_messages, context};
use glam::Vec3;
use motion_shadows::technique::EngineTsmMap;

/// The length of [a, b] within the shutter [0, 1].
fn within_shutter(a: f32, b: f32) -> f32 {
    (b.min(1.0) - a.max(0.0)).max(0.0)
}

/// Asserts |error| <= 1/N + the texel term at every pixel, and returns the mean |error|
/// over the pixels whose lit fraction is strictly between 0 and 1.
fn check_convergence(what: &str, n: u32, found: &[(usize, f32, f32)], texel_term: f32) -> f32 {
    let bound = 1.0 / n as f32 + texel_term + 1e-4;
    let partial: Vec<_> = found
        .iter()
        .filter(|(_, _, e)| *e > 0.02 && *e < 0.98)
        .collect();
    assert!(
        partial.len() > 200,
        "{what}, N = {n}: only {} pixels partly lit",
        partial.len()
    );
    for &(i, got, expected) in found {
        assert!(
            (got - expected).abs() <= bound,
            "{what}, N = {n}: pixel ({}, {}) lit {got}, closed form {expected} (bound {bound})",
            i as u32 % SIZE.0,
            i as u32 / SIZE.0
        );
    }
    partial
        .iter()
        .map(|(_, got, expected)| (got - expected).abs())
        .sum::<f32>()
        / partial.len() as f32
}

/// A still ground under a square translating along x (a moving draw), light straight down: a ground
/// point at x is shadowed while the square's extent [x0 + D t, x0 + s + D t] holds x. TSM-N's mask
/// is within 1/N (stratified times) plus a texel's worth of motion of that at every pixel, and its
/// mean error falls as N grows. Both starts, one map per dispatch or batches, give the same mask
/// bit for bit. Fails when the maps' times, the moving draws' time or the counting are wrong.
#[test]
fn engine_tsm_converges_under_a_moving_caster() {
    let ctx = context();
    let (x0, s, d) = (-1.5f32, 1.0f32, 1.5f32);
    let ground = Mesh::new(&ctx, &rect(-6.0, 6.0, -6.0, 6.0, 0.0), None);
    let square = rect(x0, x0 + s, -1.0, 1.0, 1.0);
    let caster = Mesh::new(&ctx, &square, Some(&shifted(&square, Vec3::X * d)));
    let receivers = [ground.draw(0)];
    let casters = [ground.draw(0), caster.draw(2)];
    let light = light(Vec3::NEG_Y, false);
    let closed_form = |p: Vec3| {
        let inside_box = p.x.abs() < HALF - 0.1 && p.z.abs() < HALF - 0.1;
        let near_side = (p.z.abs() - 1.0).abs() < 2.0 * TEXEL;
        if !inside_box || near_side {
            return None;
        }
        if p.z.abs() > 1.0 {
            return Some(1.0);
        }
        Some(1.0 - within_shutter((p.x - x0 - s) / d, (p.x - x0) / d))
    };
    let mut rig = Rig::new(&ctx);
    let mut by_config = Vec::new();
    for (start, layers) in CONFIGS {
        let map = EngineTsmMap::new(&ctx, SHADOW, SHADOW, layers, start).expect("map");
        let start = format!("{start:?} x{layers}");
        let mut means = Vec::new();
        let mut masks = Vec::new();
        for n in [4, 16, 64] {
            let frame = Frame {
                receivers: &receivers,
                casters: &casters,
                light: &light,
                maps: n,
                gbuffer_time: 1.0,
                moving_receivers: false,
                draw_gbuffer: true,
            };
            let mask = rig.run(&frame, &map).expect("frame");
            let found = errors(&rig, &mask, closed_form);
            means.push(check_convergence(&start.clone(), n, &found, TEXEL / d));
            masks.push(mask);
        }
        assert!(
            means[0] > means[1] && means[1] > means[2],
            "{start}: mean errors {means:?} do not fall with N = 4, 16, 64"
        );
        by_config.push((start, masks));
    }
    for (config, masks) in &by_config[1..] {
        assert!(
            masks == &by_config[0].1,
            "{config} differs from {}",
            by_config[0].0
        );
    }
    drop(rig);
    assert_no_validation_messages(&ctx);
}

/// The ground translating along x (a moving draw, drawn into every map at its time, and the
/// G-buffer's receivers drawn at shutter close with their motion) under a still square
/// (a static draw, in the static map): a receiver at x (at time 1) is shadowed while
/// x + (t - 1) D lies in the square's [c0, c0 + s]. Within 1/N plus the texel term at every
/// pixel, the mean error falling with N. Fails when the receiver ignores its motion, or when
/// a map lacks the static draws.
#[test]
fn engine_tsm_converges_for_a_moving_receiver() {
    let ctx = context();
    let (c0, s, d) = (-0.5f32, 0.8f32, 1.5f32);
    let plane = rect(-6.0, 6.0, -6.0, 6.0, 0.0);
    let ground = Mesh::new(&ctx, &plane, Some(&shifted(&plane, Vec3::X * d)));
    let caster = Mesh::new(&ctx, &rect(c0, c0 + s, -1.0, 1.0, 1.0), None);
    let receivers = [ground.draw(0)];
    let casters = [ground.draw(0), caster.draw(2)];
    let light = light(Vec3::NEG_Y, false);
    let closed_form = |p: Vec3| {
        // The path [x - D, x] stays inside the light's box.
        let inside_box = p.x - d > -HALF + 0.1 && p.x < HALF - 0.1 && p.z.abs() < HALF - 0.1;
        let near_side = (p.z.abs() - 1.0).abs() < 2.0 * TEXEL;
        if !inside_box || near_side {
            return None;
        }
        if p.z.abs() > 1.0 {
            return Some(1.0);
        }
        Some(1.0 - within_shutter(1.0 + (c0 - p.x) / d, 1.0 + (c0 + s - p.x) / d))
    };
    let mut rig = Rig::new(&ctx);
    for (start, layers) in CONFIGS {
        let map = EngineTsmMap::new(&ctx, SHADOW, SHADOW, layers, start).expect("map");
        let start = format!("{start:?} x{layers}");
        let mut means = Vec::new();
        for n in [4, 16, 64] {
            let frame = Frame {
                receivers: &receivers,
                casters: &casters,
                light: &light,
                maps: n,
                gbuffer_time: 1.0,
                moving_receivers: true,
                draw_gbuffer: true,
            };
            let mask = rig.run(&frame, &map).expect("frame");
            let found = errors(&rig, &mask, closed_form);
            means.push(check_convergence(&start.clone(), n, &found, TEXEL / d));
        }
        assert!(
            means[0] > means[1] && means[1] > means[2],
            "{start}: mean errors {means:?} do not fall with N = 4, 16, 64"
        );
    }
    drop(rig);
    assert_no_validation_messages(&ctx);
}
