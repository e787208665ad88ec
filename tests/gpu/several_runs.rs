//! A triangle whose coverage of a texel comes and goes during the shutter (several covered
//! runs per texel) while its depth there rises and falls, against a brute-force oracle that
//! shares nothing with the shaders: the texel centre's coverage and depth sampled densely in
//! f64 from the vertices' linear motion, each change of coverage located by bisection.
//!
//! What it decides: the generation pass must pair a texel's fragments in time order (pairing
//! by depth, here, pairs the runs' ends across runs), and the exact construction must find
//! every run and its depths; both the lists (static triangles in the lists, so the collection
//! stores nodes and the generation pairs them) and the ranges the collection stores itself.

use crate::support::gpu::{assert_no_validation_messages, context};
use crate::support::scene::{
    Scene, light_view, mesh, overhead_directional, scene, temporal_map, temporal_map_with,
};
use glam::{DVec2, DVec3, Vec3, Vec4};
use motion_shadows::technique::{PrismConstruction, Range, ShadowMapContents};

const SIZE: (u32, u32) = (64, 64);
/// The directional light's plane is at y = 10 (`overhead_directional`): depth = 10 - y.
const LIGHT_HEIGHT: f64 = 10.0;

/// One triangle, every corner moving linearly (found by a search for a motion that covers
/// many texel centres twice with the depth order of the runs' ends unlike their time order).
fn twice_covering_triangle() -> Scene {
    let t0 = [
        (-1.48, 1.75, 0.05),
        (1.73, 0.76, 1.56),
        (-1.62, 1.16, -0.99),
    ];
    let t1 = [(0.07, 2.68, 1.66), (-1.0, 1.06, -0.67), (1.98, 2.19, -1.84)];
    let points = |c: [(f32, f32, f32); 3]| c.map(|(x, y, z)| Vec3::new(x, y, z)).to_vec();
    scene(
        "twice-covering",
        overhead_directional(8.0),
        vec![mesh("triangle", points(t0), points(t1), false)],
    )
}

/// World x and z of the centre of shadow-map texel (x, y), by inverting the light's matrices.
fn texel_centre(scene: &Scene, x: u32, y: u32) -> DVec2 {
    let light = light_view(scene, SIZE);
    let ndc = glam::Vec2::new(
        (x as f32 + 0.5) / SIZE.0 as f32 * 2.0 - 1.0,
        (y as f32 + 0.5) / SIZE.1 as f32 * 2.0 - 1.0,
    );
    let world = (light.proj * light.view).inverse() * Vec4::new(ndc.x, ndc.y, 0.5, 1.0);
    DVec2::new(f64::from(world.x / world.w), f64::from(world.z / world.w))
}

/// A covered run of the oracle: from `start` to `end`, the depth at each end.
#[derive(Debug, Clone, Copy)]
struct Run {
    start: f64,
    end: f64,
    depth_start: f64,
    depth_end: f64,
}

/// The triangle's corners at time t (xz) and their depths.
fn corners_at(scene: &Scene, t: f64) -> ([DVec2; 3], [f64; 3]) {
    let m = &scene.meshes[0];
    let at = |i: usize| m.t0[i].as_dvec3().lerp(m.t1[i].as_dvec3(), t);
    let c: [DVec3; 3] = [at(0), at(1), at(2)];
    (
        c.map(|p| DVec2::new(p.x, p.z)),
        c.map(|p| LIGHT_HEIGHT - p.y),
    )
}

/// The depth of the triangle at p at time t if it covers p then.
fn covered_depth(scene: &Scene, p: DVec2, t: f64) -> Option<f64> {
    let (c, d) = corners_at(scene, t);
    let cross = |o: DVec2, u: DVec2, v: DVec2| (u - o).perp_dot(v - o);
    let e = [
        cross(c[1], c[2], p),
        cross(c[2], c[0], p),
        cross(c[0], c[1], p),
    ];
    let area = e[0] + e[1] + e[2];
    let same_sign = e.iter().all(|&x| x >= 0.0) || e.iter().all(|&x| x <= 0.0);
    (area != 0.0 && same_sign).then(|| (e[0] * d[0] + e[1] * d[1] + e[2] * d[2]) / area)
}

/// The covered runs at p: coverage sampled at 4,096 steps, each change located by bisection.
fn oracle_runs(scene: &Scene, p: DVec2) -> Vec<Run> {
    const STEPS: u32 = 4096;
    let covered = |t: f64| covered_depth(scene, p, t).is_some();
    let boundary = |mut lo: f64, mut hi: f64| {
        // covered(lo) != covered(hi): the change lies between.
        let at_lo = covered(lo);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if covered(mid) == at_lo {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    };
    let mut changes = Vec::new();
    let mut was = covered(0.0);
    for i in 1..=STEPS {
        let t = f64::from(i) / f64::from(STEPS);
        let now = covered(t);
        if now != was {
            changes.push(boundary(f64::from(i - 1) / f64::from(STEPS), t));
        }
        was = now;
    }
    let mut bounds = Vec::new();
    if covered(0.0) {
        bounds.push(0.0);
    }
    bounds.extend(changes);
    if covered(1.0) {
        bounds.push(1.0);
    }
    // The depth at a run's end, from just inside it (the end itself lies on an edge).
    let depth_near = |t: f64, inward: f64| {
        covered_depth(scene, p, (t + inward).clamp(0.0, 1.0))
            .or_else(|| covered_depth(scene, p, t))
            .expect("inside the run")
    };
    bounds
        .chunks_exact(2)
        .map(|b| Run {
            start: b[0],
            end: b[1],
            depth_start: depth_near(b[0], 1e-9),
            depth_end: depth_near(b[1], -1e-9),
        })
        .collect()
}

/// Whether pairing the runs' ends by depth (ties by time) pairs them differently than by
/// time: a generation pass that did would store wrong ranges here.
fn depth_order_pairs_differently(runs: &[Run]) -> bool {
    let mut ends: Vec<(f64, f64)> = runs
        .iter()
        .flat_map(|r| [(r.start, r.depth_start), (r.end, r.depth_end)])
        .collect();
    let by_time: Vec<(u64, u64)> = runs
        .iter()
        .map(|r| (r.start.to_bits(), r.end.to_bits()))
        .collect();
    ends.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.total_cmp(&b.0)));
    let by_depth: Vec<(u64, u64)> = ends
        .chunks_exact(2)
        .map(|p| {
            let (a, b) = (p[0].0.min(p[1].0), p[0].0.max(p[1].0));
            (a.to_bits(), b.to_bits())
        })
        .collect();
    by_depth.iter().any(|pair| !by_time.contains(pair))
}

/// Compares the map's ranges at every texel with the oracle's runs; returns how many texels
/// held several runs and how many of those a depth-order pairing would get wrong.
fn check_map(what: &str, scene: &Scene, map: &ShadowMapContents) -> (usize, usize) {
    // Times: f32 roots of the edge quadratics; depths: f32 interpolation, 10 units deep.
    const TIME_TOLERANCE: f64 = 1e-3;
    const DEPTH_TOLERANCE: f64 = 2e-3;
    // Runs or gaps shorter than this are where a nearly tangent edge makes f32 and f64 see
    // different numbers of roots: such texels are not compared.
    const MIN_PIECE: f64 = 0.01;
    let (mut several, mut by_depth_wrong) = (0, 0);
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let p = texel_centre(scene, x, y);
            let want = oracle_runs(scene, p);
            let pieces_ok = want.iter().all(|r| r.end - r.start >= MIN_PIECE)
                && want.windows(2).all(|w| w[1].start - w[0].end >= MIN_PIECE)
                && want.iter().all(|r| {
                    (r.start == 0.0 || r.start >= MIN_PIECE)
                        && (r.end == 1.0 || r.end <= 1.0 - MIN_PIECE)
                });
            if !pieces_ok {
                continue;
            }
            let mut got: Vec<Range> = map.ranges_at(x, y);
            got.sort_by(|a, b| a.t_s.total_cmp(&b.t_s));
            assert_eq!(
                got.len(),
                want.len(),
                "{what}: texel ({x},{y}) holds {got:?}, the oracle {want:?}"
            );
            for (g, w) in got.iter().zip(&want) {
                let close = (f64::from(g.t_s) - w.start).abs() <= TIME_TOLERANCE
                    && (f64::from(g.t_e) - w.end).abs() <= TIME_TOLERANCE
                    && (f64::from(g.d_s) - w.depth_start).abs() <= DEPTH_TOLERANCE
                    && (f64::from(g.d_e) - w.depth_end).abs() <= DEPTH_TOLERANCE;
                assert!(
                    close,
                    "{what}: texel ({x},{y}): range {g:?}, oracle run {w:?}"
                );
            }
            if want.len() >= 2 {
                several += 1;
                by_depth_wrong += usize::from(depth_order_pairs_differently(&want));
            }
        }
    }
    (several, by_depth_wrong)
}

#[test]
fn texels_covered_twice_hold_the_oracles_runs() {
    let ctx = context();
    let s = twice_covering_triangle();
    // Lists and the generation pass (no static layer), then the collection's own ranges.
    let lists = temporal_map_with(&ctx, &s, SIZE, PrismConstruction::Exact, false);
    assert!(!lists.nodes.is_empty(), "the lists hold no node");
    let (several, wrong_by_depth) = check_map("lists", &s, &lists);
    eprintln!("{several} texels covered more than once, {wrong_by_depth} paired wrong by depth");
    assert!(
        several >= 20 && wrong_by_depth >= 10,
        "{several} / {wrong_by_depth}"
    );
    let direct = temporal_map(&ctx, &s, SIZE);
    assert!(direct.nodes.is_empty(), "the collection stored nodes");
    assert_eq!(
        check_map("collected ranges", &s, &direct),
        (several, wrong_by_depth)
    );
    assert_no_validation_messages(&ctx);
}
