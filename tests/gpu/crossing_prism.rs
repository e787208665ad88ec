//! The papers' crossing case (Hong & Oh 2018, 4.1, equation (1) and Fig. 6) against the f64
//! oracle of support/coverage_oracle.rs, which shares no code or constant with the shaders or
//! with the CPU prism model (test-support/src/prism_model/, which copies the shader's rule).
//!
//! The motion: one edge of a large level triangle turns 120 degrees about its own midpoint X
//! (the corners move on chords), under an overhead directional light. The edge at t = 0 and
//! the edge at t = 1 cross on the screen at X, and the papers' construction draws that side
//! as two triangles through a crossing vertex at X. The triangle's other edges stay more
//! than 10 units from X, outside the map: within the map only the turning edge changes
//! coverage.
//!
//! What the oracle says there: the edge always passes through X, so a texel is crossed when
//! the edge points at it, and the exact time is the same along each ray from X. The papers'
//! side triangles interpolate time linearly from the swept corners (0 and 1, exact) to the
//! crossing vertex; a linear interpolation agrees with a time that is constant along rays
//! from X only on the ray whose time is the crossing vertex's. The test asserts:
//! - every texel holds the oracle's runs (none, [0, 1], or one end at 0 or 1 exactly, and
//!   the other inside), with the oracle's depths;
//! - where the oracle's time is mid-shutter (within 0.01), the map's time is within 0.01
//!   (plus rounding) of the oracle's;
//! - everywhere else the map's time lies between the oracle's and mid-shutter.
//!
//! A crossing vertex at another time (0.4) puts the map 0.06 or more off the oracle where
//! the oracle says mid-shutter: the test fails, whatever the CPU model says.

use crate::support::coverage_oracle::{
    covered_intervals, margin, plane_depth, scene_triangles, texel_ray,
};
use crate::support::gpu::{assert_no_validation_messages, context};
use crate::support::scene::{light_view, mesh, overhead_directional, scene, temporal_map_with};
use glam::{Quat, Vec3, Vec4};
use motion_shadows::technique::{PrismConstruction, Range};

const SIZE: (u32, u32) = (64, 64);
/// Half the side of the light's box: the map spans [-4, 4] in x and z, 0.125 per texel.
const HALF_EXTENT: f32 = 4.0;
/// The texels whose exact time is within this of mid-shutter.
const MID_WINDOW: f64 = 0.01;
/// f32 interpolation over triangles reaching ten map widths out, and the rasterizer's
/// sub-pixel snapping (the time changes by less than 0.1 per texel this far from X).
const ROUNDING: f64 = 2e-3;
/// Texels closer than this to X (in texels), where the time changes fastest, are skipped.
const NEAR_X: f64 = 3.0;
/// Exact times this close to the shutter's ends are runs a texel may miss (a touch).
const END_MARGIN: f64 = 0.01;

/// The inner end of a run that starts at 0 or ends at 1, and which end that is.
fn inner_end(run: (f64, f64)) -> Option<f64> {
    match run {
        (s, e) if s == 0.0 && e < 1.0 => Some(e),
        (s, e) if e == 1.0 && s > 0.0 => Some(s),
        _ => None,
    }
}

#[test]
fn crossing_vertex_times_match_the_oracle() {
    let ctx = context();
    let height = 2.0;
    let t0 = vec![
        Vec3::new(-40.0, height, 0.0),
        Vec3::new(40.0, height, 0.0),
        Vec3::new(0.0, height, 40.0),
    ];
    // About the vertical through X = (0, height, 0), the midpoint of edge 0-1.
    let turn = Quat::from_rotation_y(120f32.to_radians());
    let t1: Vec<Vec3> = t0.iter().map(|p| turn * *p).collect();
    let s = scene(
        "crossing-vertex",
        overhead_directional(HALF_EXTENT),
        vec![mesh("turning", t0, t1, false)],
    );
    let map = temporal_map_with(&ctx, &s, SIZE, PrismConstruction::Paper, false);
    let light = light_view(&s, SIZE);
    let tri = scene_triangles(&s)[0];

    // X in texel coordinates, from the light's matrices.
    let clip = light.proj * light.view * Vec4::new(0.0, height, 0.0, 1.0);
    let x_texel = (
        (f64::from(clip.x / clip.w) * 0.5 + 0.5) * f64::from(SIZE.0),
        (f64::from(clip.y / clip.w) * 0.5 + 0.5) * f64::from(SIZE.1),
    );

    let (mut swept, mut mid, mut worst_mid) = (0, 0, 0.0_f64);
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let from_x = (f64::from(x) + 0.5 - x_texel.0).hypot(f64::from(y) + 0.5 - x_texel.1);
            let ray = texel_ray(&light, SIZE, x, y);
            let near_edge = [0.0, 1.0]
                .iter()
                .any(|&t| margin(&ray, tri.at(t)).abs() < 1e-4);
            if from_x < NEAR_X || near_edge {
                continue;
            }
            let want = covered_intervals(&ray, &tri);
            let ends = want.iter().filter_map(|&r| inner_end(r));
            if ends
                .clone()
                .any(|t| !(END_MARGIN..=1.0 - END_MARGIN).contains(&t))
            {
                continue;
            }
            let got: Vec<Range> = map.ranges_at(x, y);
            assert_eq!(
                got.len(),
                want.len(),
                "texel ({x},{y}): ranges {got:?}, oracle {want:?}"
            );
            let Some((g, &w)) = got.first().zip(want.first()) else {
                continue;
            };
            let g_run = (f64::from(g.t_s), f64::from(g.t_e));
            for (t, d) in [(g.t_s, g.d_s), (g.t_e, g.d_e)] {
                let truth = plane_depth(&ray, tri.at(f64::from(t))).expect("level triangle");
                assert!(
                    (f64::from(d) - truth).abs() < 1e-4 * truth,
                    "texel ({x},{y}) at t = {t}: depth {d}, oracle {truth}"
                );
            }
            let Some(exact) = inner_end(w) else {
                // Covered all shutter long: the caps alone.
                assert!(
                    g_run.0.abs() < 1e-6 && (g_run.1 - 1.0).abs() < 1e-6,
                    "texel ({x},{y}): {g:?}, oracle {w:?}"
                );
                continue;
            };
            // The shutter's end the run touches is a cap's time: exactly 0 or 1.
            let (fixed_got, fixed_want, papers) = if w.0 == 0.0 {
                (g_run.0, 0.0, g_run.1)
            } else {
                (g_run.1, 1.0, g_run.0)
            };
            assert!(
                (fixed_got - fixed_want).abs() < 1e-6,
                "texel ({x},{y}): {g:?}, oracle {w:?}"
            );
            swept += 1;
            let (low, high) = (exact.min(0.5), exact.max(0.5));
            assert!(
                papers >= low - ROUNDING && papers <= high + ROUNDING,
                "texel ({x},{y}): the map's time {papers} is not between the oracle's \
                 {exact} and mid-shutter"
            );
            if (exact - 0.5).abs() <= MID_WINDOW {
                mid += 1;
                worst_mid = worst_mid.max((papers - exact).abs());
                assert!(
                    (papers - exact).abs() <= MID_WINDOW + ROUNDING,
                    "texel ({x},{y}) on the mid-shutter ray: the map's time {papers}, the \
                     oracle's {exact}"
                );
            }
        }
    }
    eprintln!("{swept} swept texels, {mid} at mid-shutter (largest error there {worst_mid:.1e})");
    assert!(
        swept > 2000 && mid >= 20,
        "{swept} swept, {mid} at mid-shutter"
    );
    assert_no_validation_messages(&ctx);
}

/// Sample times this close to a change of the oracle's coverage are not compared.
const NEAR_CHANGE: f64 = 0.01;

/// A triangle whose base slides one way while its apex slides the other, through it (the
/// apex and the base swap sides at mid-shutter): both slanted edges turn about their fixed
/// midpoints (the papers' crossing case), the base translates. Texels between the apex's
/// and the base's paths are covered at the start, uncovered when the base passes, covered
/// again when a slanted edge comes back: two runs of one triangle, four fragments (the caps
/// first in the list, then the sides), which the generation must pair in time order. At 64
/// times per texel, every time farther than `NEAR_CHANGE` from the oracle's changes is covered
/// by the map's ranges exactly when the oracle covers it, except, where a slanted edge makes
/// the change, between its time and mid-shutter (where the first test puts the papers' time;
/// the base translates, and there the papers' prism is exact).
#[test]
fn two_runs_through_crossing_sides_are_paired_in_time_order() {
    let ctx = context();
    let (height, d) = (2.0, Vec3::new(0.0, 0.0, 4.0));
    let t0 = [
        Vec3::new(-3.0, height, -2.0),
        Vec3::new(3.0, height, -2.0),
        Vec3::new(0.0, height, 2.0),
    ];
    let t1 = [t0[0] + d, t0[1] + d, t0[2] - d];
    let s = scene(
        "apex-through-base",
        overhead_directional(HALF_EXTENT),
        vec![mesh("flipping", t0.to_vec(), t1.to_vec(), false)],
    );
    let map = temporal_map_with(&ctx, &s, SIZE, PrismConstruction::Paper, false);
    let light = light_view(&s, SIZE);
    let tri = scene_triangles(&s)[0];
    let (mut two_runs, mut gaps_checked) = (0, 0);
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let ray = texel_ray(&light, SIZE, x, y);
            let want = covered_intervals(&ray, &tri);
            let got = map.ranges_at(x, y);
            let changes: Vec<f64> = want
                .iter()
                .flat_map(|&(s, e)| [s, e])
                .filter(|&t| t > 0.0 && t < 1.0)
                .collect();
            // The base (z = -2 + 4t, x within +-3) passes the texel centre at this time.
            let centre = ray.origin;
            let base_time = (centre.z + 2.0) / 4.0;
            let by_base = |c: f64| centre.x.abs() < 3.0 && (c - base_time).abs() < 1e-6;
            let mut gap_checked = false;
            for k in 0..64 {
                let t = (f64::from(k) + 0.5) / 64.0;
                let uncertain = changes.iter().any(|&c| {
                    (c - t).abs() <= NEAR_CHANGE
                        || (!by_base(c)
                            && t >= c.min(0.5) - NEAR_CHANGE
                            && t <= c.max(0.5) + NEAR_CHANGE)
                });
                if uncertain {
                    continue;
                }
                let oracle = want.iter().any(|&(s, e)| s <= t && t <= e);
                let ranges = got
                    .iter()
                    .any(|r| f64::from(r.t_s) <= t && t <= f64::from(r.t_e));
                assert_eq!(
                    ranges, oracle,
                    "texel ({x},{y}) at t = {t}: ranges {got:?}, oracle {want:?}"
                );
                gap_checked |= want.len() == 2 && !oracle && t > want[0].1 && t < want[1].0;
            }
            two_runs += usize::from(want.len() == 2);
            gaps_checked += usize::from(gap_checked);
        }
    }
    eprintln!("{two_runs} texels with two runs, {gaps_checked} with their gap checked");
    assert!(
        gaps_checked >= 50,
        "{two_runs} two-run texels, {gaps_checked} gaps checked"
    );
    assert_no_validation_messages(&ctx);
}
