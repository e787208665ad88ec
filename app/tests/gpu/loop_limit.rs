//! Devices that leave shader loops after a fixed count (lavapipe: 65,535 iterations per
//! invocation, silently) must not turn long shadow lookups into wrong pixels.
//!
//! A comb of 36 thin slats sweeps over the ground: every ground point under the sweep is
//! shadowed 36 times, in 36 disjoint intervals of the shutter, so its lit fraction is
//! 1 - 36 w / D in closed form (slat width w, travel D), and measuring it takes the analytic
//! estimator's long path (more disjoint intervals than it keeps in private memory). At 8
//! samples per invocation that is more loop iterations than lavapipe runs: the renderer must
//! notice, shade again with one sample per invocation and get the closed form. With a filter
//! over four texels even one sample is too much there: the renderer must say so.

use crate::support::gpu::{
    assert_no_validation_messages, context, mesh, overhead_directional, scene,
};
use glam::{Vec2, Vec3};
use motion_shadows::technique::{ShadowEstimator, ShadowFilter};
use motion_shadows_app::render::{Method, RenderSettings, Renderer};
use motion_shadows_app::scene::{Scene, plane_mesh};

const SLATS: usize = 36;
const WIDTH: f32 = 0.02;
const PERIOD: f32 = 0.1;
/// The comb travels twice its length: every slat passes over every point of its middle
/// stretch (from the comb's end at t = 0 to its start at t = 1).
const TRAVEL: f32 = 2.0 * SLATS as f32 * PERIOD;
const FIRST: f32 = -6.0;
/// Radiance of lit ground: albedo 0.8 / pi * irradiance 3 (overhead), no ambient.
const LIT: f32 = 0.8 / std::f32::consts::PI * 3.0;

fn comb_scene() -> Scene {
    let strip = |x0: f32| {
        let (x1, y) = (x0 + WIDTH, 1.0);
        let (a, b, c, d) = (
            Vec3::new(x0, y, -8.0),
            Vec3::new(x0, y, 8.0),
            Vec3::new(x1, y, 8.0),
            Vec3::new(x1, y, -8.0),
        );
        vec![a, b, c, a, c, d]
    };
    let mut t0 = Vec::new();
    for k in 0..SLATS {
        t0.extend(strip(FIRST + k as f32 * PERIOD));
    }
    let t1: Vec<Vec3> = t0.iter().map(|p| *p + Vec3::X * TRAVEL).collect();
    let ground = plane_mesh(Vec2::splat(16.0), 8);
    scene(
        "comb",
        overhead_directional(8.0),
        vec![
            mesh("ground", ground.clone(), ground, false),
            mesh("comb", t0, t1, false),
        ],
    )
}

fn settings(filter: ShadowFilter, spp: u32) -> RenderSettings {
    RenderSettings {
        width: 128,
        height: 96,
        spp,
        seed: 2,
        shadow_size: Some((256, 256)),
        method: Method::Temporal,
        shadow_estimator: ShadowEstimator::Analytic,
        shadow_filter: filter,
        ..RenderSettings::default()
    }
}

#[test]
fn long_lookups_are_shaded_again_or_refused_where_loops_are_limited() {
    let ctx = context();
    let limited = ctx.info().shader_loop_limit.is_some();
    let s = comb_scene();
    let mut renderer = Renderer::new(&ctx).unwrap();
    let mut messages = Vec::new();
    let result = renderer
        .render(&s, &settings(ShadowFilter::None, 8), &mut |m| {
            messages.push(m.to_owned())
        })
        .expect("one sample per invocation fits");
    let retried = messages.iter().any(|m| m.contains("one sample per pass"));
    eprintln!("loop limit: {limited}; shaded again with one sample per pass: {retried}");
    assert_eq!(retried, limited, "{messages:?}");

    // Pixels all of whose samples see the ground where the whole comb sweeps over it.
    let expected = 1.0 - SLATS as f32 * WIDTH / TRAVEL;
    let rays = crate::support::sampling::CameraRays::of(
        &motion_shadows_app::render::upload::camera_view(&s, (128, 96)),
        (128, 96),
    );
    let origin = rays.origin.as_dvec3();
    let (lo, hi) = (
        f64::from(FIRST + SLATS as f32 * PERIOD + 0.1),
        f64::from(FIRST + TRAVEL - 0.1),
    );
    let mut checked = 0;
    for y in 0..96u32 {
        for x in 0..128u32 {
            let i = (y * 128 + x) as usize;
            if result.moving_coverage[i] > 0.0 {
                continue;
            }
            let corners = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)].map(|(dx, dy)| {
                let d = rays.direction(x as f32 + dx, y as f32 + dy);
                origin + d * (-origin.y / d.y)
            });
            if corners
                .iter()
                .any(|p| p.x < lo || p.x > hi || p.z.abs() > 7.0)
            {
                continue;
            }
            let got = result.image.rgb[i * 3 + 1] / LIT;
            assert!(
                (got - expected).abs() < 2e-3,
                "pixel ({x},{y}): lit {got}, closed form {expected}"
            );
            checked += 1;
        }
    }
    eprintln!("{checked} ground pixels at the closed form {expected}");
    assert!(checked > 200, "only {checked} pixels checked");

    // Four texels per lookup: too long for one invocation on a loop-limited device.
    let filtered = renderer.render(&s, &settings(ShadowFilter::Bilinear, 2), &mut |_| {});
    match (limited, filtered) {
        (true, Err(e)) => {
            let text = e.to_string();
            eprintln!("refused: {text}");
            assert!(text.contains("loop iterations"), "{text}");
        }
        (true, Ok(_)) => panic!("a loop-limited device must refuse the filtered comb"),
        (false, r) => {
            r.expect("no loop limit: the filtered comb renders");
        }
    }
    assert_no_validation_messages(&ctx);
}
