//! The lighting pass's stochastic rasterization against a CPU ray cast of every sample: the
//! screen-space hull each moving triangle is drawn with must cover every pixel where one of its
//! samples can hit the triangle (else samples are lost silently), and each sample must see
//! exactly what its ray meets at its time. (It catches a hull grown by 0.3 instead of 0.5
//! pixel; smaller shortfalls leave too few samples in the missing band to be sure of.)

use crate::support::gpu::{
    assert_no_validation_messages, context, mesh, overhead_directional, render, scene,
};
use crate::support::sampling::{CameraRays, hits, pixel_key, pixel_sample};
use glam::{DVec3, Vec3};
use motion_shadows_app::render::upload::camera_view;
use motion_shadows_app::render::{Method, RenderSettings};

const SIZE: (u32, u32) = (128, 96);
const SPP: u32 = 32;
const SEED: u32 = 3;

fn moved(points: &[Vec3], by: Vec3) -> Vec<Vec3> {
    points.iter().map(|p| *p + by).collect()
}

/// Triangles that exercise each way the hull is grown: a large one moving sideways and up
/// (mitered corners), a sliver with a sharp corner (exact square corners), one smaller than a
/// pixel, and one that flies from in front of the camera to behind it (near-plane crossings).
fn moving_triangles() -> Vec<(Vec<Vec3>, Vec<Vec3>)> {
    let big = vec![
        Vec3::new(-3.0, 0.0, -1.0),
        Vec3::new(-1.0, 0.0, 2.0),
        Vec3::new(0.0, 0.0, -2.0),
    ];
    let sliver = vec![
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(4.0, 0.0, 0.15),
        Vec3::new(4.0, 0.0, -0.05),
    ];
    let tiny = vec![
        Vec3::new(2.0, 0.0, 2.0),
        Vec3::new(2.06, 0.0, 2.0),
        Vec3::new(2.0, 0.0, 2.05),
    ];
    // The support camera sits at (0, 6, 8) looking at the origin.
    let eye = Vec3::new(0.0, 6.0, 8.0);
    let forward = (-eye).normalize();
    let (right, up) = (Vec3::X, forward.cross(Vec3::X));
    let facing = |centre: Vec3| {
        vec![
            centre + 0.4 * right,
            centre - 0.25 * right + 0.3 * up,
            centre - 0.25 * right - 0.3 * up,
        ]
    };
    vec![
        (big.clone(), moved(&big, Vec3::new(2.0, 1.0, 0.5))),
        (sliver.clone(), moved(&sliver, Vec3::new(0.0, 0.0, 1.5))),
        (tiny.clone(), moved(&tiny, Vec3::new(0.3, 0.0, 0.0))),
        // Beside the eye when it passes it, so it does not cover the whole image then.
        (
            facing(eye + 2.0 * forward + 1.2 * right),
            facing(eye - 0.5 * forward + 1.2 * right),
        ),
    ]
}

#[test]
fn every_sample_sees_what_its_ray_meets_at_its_time() {
    let ctx = context();
    let triangles = moving_triangles();
    let meshes = triangles
        .iter()
        .enumerate()
        .map(|(i, (t0, t1))| mesh(&format!("moving-{i}"), t0.clone(), t1.clone(), false))
        .collect();
    let s = scene("moving-triangles", overhead_directional(8.0), meshes);
    let settings = RenderSettings {
        width: SIZE.0,
        height: SIZE.1,
        spp: SPP,
        seed: SEED,
        shadow_size: Some((32, 32)),
        method: Method::Plain { time: 0.5 },
        ..RenderSettings::default()
    };
    let result = render(&ctx, &s, &settings);

    let rays = CameraRays::of(&camera_view(&s, SIZE), SIZE);
    let at = |(t0, t1): &(Vec<Vec3>, Vec<Vec3>), t: f32| -> [DVec3; 3] {
        [0, 1, 2].map(|i| t0[i].lerp(t1[i], t).as_dvec3())
    };

    let (mut partial, mut unsure_samples) = (0, 0);
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let key = pixel_key(x, y, SEED);
            let (mut sure, mut unsure) = (0u32, 0u32);
            for k in 0..SPP {
                let (t, offset) = pixel_sample(key, k, SPP);
                let dir = rays.direction(x as f32 + offset[0], y as f32 + offset[1]);
                let answers: Vec<_> = triangles
                    .iter()
                    .map(|tri| hits(&rays, dir, at(tri, t), 1e-4))
                    .collect();
                if answers.contains(&Some(true)) {
                    sure += 1;
                } else if answers.contains(&None) {
                    unsure += 1;
                }
            }
            let share = result.moving_coverage[(y * SIZE.0 + x) as usize];
            let got = (share * SPP as f32).round() as u32;
            assert!(
                (sure..=sure + unsure).contains(&got),
                "pixel ({x},{y}): {got} of {SPP} samples see a triangle, the rays say {sure} \
                 (+{unsure} too close to an edge to tell)"
            );
            partial += usize::from(0 < got && got < SPP);
            unsure_samples += unsure;
        }
    }
    eprintln!("{partial} pixels partly covered; {unsure_samples} samples too close to call");
    assert!(partial > 300, "only {partial} motion-blurred pixels");
    // Rounding decides at most a few samples in ten thousand; more would mean the margin
    // (or the model) hides real differences.
    let samples = SIZE.0 * SIZE.1 * SPP;
    assert!(
        unsure_samples * 1000 < samples,
        "{unsure_samples} of {samples} samples too close to call"
    );
    assert_no_validation_messages(&ctx);
}
