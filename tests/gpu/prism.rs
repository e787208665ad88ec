//! The GPU's prisms in the papers' construction (`PrismConstruction::Paper`) against an independent CPU model of the geometry shader's triangulation
//! (test-support/src/prism_model/): same fragment count, times and depths at every pixel whose
//! centre is clear of all prism edges, in the centre-vertex case and in the crossing case.

use crate::support::gpu::{assert_no_validation_messages, context};
use crate::support::prism_model::{
    EdgeCase, edge_cases, edge_margin_at_pixel, fragments_at_pixel, prism_triangles,
};
use crate::support::scene::{light_setup, mesh, overhead_spot, scene, temporal_map_with};
use glam::{Quat, Vec3};
use motion_shadows::technique::PrismConstruction;

const SIZE: (u32, u32) = (96, 96);

fn compare_with_model(p0: [Vec3; 3], p1: [Vec3; 3], want: EdgeCase) {
    let ctx = context();
    let s = scene(
        "prism",
        overhead_spot(10.0, 30.0),
        vec![mesh("moving", p0.to_vec(), p1.to_vec(), false)],
    );
    let setup = light_setup(&s, SIZE);
    assert!(
        edge_cases(&setup, p0, p1).contains(&want),
        "the test motion must exercise {want:?}"
    );
    let model = prism_triangles(&setup, p0, p1, false);
    let map = temporal_map_with(&ctx, &s, SIZE, PrismConstruction::Paper, true);

    // A rasterizer snaps each vertex to its sub-pixel grid (up to half a step in x and in y),
    // which moves an interpolated attribute by up to its screen gradient times that shift:
    // steep side surfaces (edge-on to the light) need more than the 2e-3 rounding allowance.
    let snap =
        std::f32::consts::FRAC_1_SQRT_2 / (1u32 << ctx.info().sub_pixel_precision_bits) as f32;
    let (mut probes, mut with_fragments, mut worst) = (0, 0, 0.0_f32);
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            if edge_margin_at_pixel(&model, &setup, x, y) < 0.02 {
                continue;
            }
            let mut want_frags = fragments_at_pixel(&model, &setup, x, y);
            let mut got = map.nodes_at(x, y);
            assert_eq!(
                got.len(),
                want_frags.len(),
                "pixel ({x},{y}): GPU {got:?}, model {want_frags:?}"
            );
            got.sort_by(|a, b| a.time.total_cmp(&b.time).then(a.depth.total_cmp(&b.depth)));
            want_frags.sort_by(|a, b| a.time.total_cmp(&b.time).then(a.depth.total_cmp(&b.depth)));
            for (g, w) in got.iter().zip(&want_frags) {
                let time_tolerance = 2e-3 + 2.0 * snap * w.time_per_pixel;
                let depth_tolerance = 2e-3 * w.depth + 2.0 * snap * w.depth_per_pixel;
                worst = worst
                    .max((g.time - w.time).abs() / time_tolerance)
                    .max((g.depth - w.depth).abs() / depth_tolerance);
                assert!(
                    (g.time - w.time).abs() < time_tolerance
                        && (g.depth - w.depth).abs() < depth_tolerance,
                    "pixel ({x},{y}): GPU {g:?}, model {w:?}"
                );
            }
            probes += 1;
            with_fragments += usize::from(!got.is_empty());
        }
    }
    eprintln!("largest error: {worst:.1e} of its tolerance ({probes} probes)");
    assert!(
        with_fragments > 200,
        "only {with_fragments} covered probes of {probes}"
    );
    assert_no_validation_messages(&ctx);
}

#[test]
fn centre_vertex_prism_matches_cpu_model() {
    let p0 = [
        Vec3::new(-2.0, 2.0, -1.0),
        Vec3::new(-0.5, 2.0, 1.5),
        Vec3::new(0.5, 2.0, -1.5),
    ];
    // Moves sideways and toward the light: four triangles around each side's centre.
    let p1 = p0.map(|p| p + Vec3::new(2.5, 1.5, 0.5));
    compare_with_model(p0, p1, EdgeCase::Centre);
}

#[test]
fn crossing_edge_prism_matches_cpu_model() {
    let p0 = [
        Vec3::new(-1.5, 2.0, 0.0),
        Vec3::new(1.5, 2.0, 0.0),
        Vec3::new(0.0, 2.0, 2.0),
    ];
    // A 60 degree turn about the vertical through the midpoint of edge 0-1: that edge at t=0
    // and at t=1 cross on the screen.
    let turn = Quat::from_rotation_y(60f32.to_radians());
    let p1 = p0.map(|p| turn * p + Vec3::new(0.3, 0.5, 0.0));
    compare_with_model(p0, p1, EdgeCase::Crossing);
}
