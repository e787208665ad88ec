//! The generation sub-pass against a CPU model of it: per pixel, group the stored fragments by
//! triangle, order each group by time (then depth), pair 1st-2nd, 3rd-4th, ...; an odd group's
//! latest fragment becomes a zero-length range.

use crate::support::gpu::{
    assert_no_validation_messages, context, mesh, overhead_directional, overhead_spot, scene,
    temporal_map, temporal_map_with,
};
use glam::Vec3;
use motion_shadows::Error;
use motion_shadows::technique::{
    MAX_LIST_NODES, Node, PrismConstruction, Range, ShadowMapContents,
};
use motion_shadows_app::Error as AppError;
use motion_shadows_app::render::{RenderSettings, Renderer};
use motion_shadows_app::scene::{BuiltinOptions, builtin};
use std::collections::BTreeMap;

fn expected_ranges(nodes: &[Node]) -> Vec<Range> {
    let mut groups: BTreeMap<u32, Vec<Node>> = BTreeMap::new();
    for n in nodes {
        groups.entry(n.id).or_default().push(*n);
    }
    let mut out = Vec::new();
    for (id, mut group) in groups {
        group.sort_by(|a, b| a.time.total_cmp(&b.time).then(a.depth.total_cmp(&b.depth)));
        for pair in group.chunks(2) {
            let (a, b) = (pair[0], *pair.get(1).unwrap_or(&pair[0]));
            let (s, e) = if a.time <= b.time { (a, b) } else { (b, a) };
            out.push(Range {
                t_s: s.time,
                t_e: e.time,
                d_s: s.depth,
                d_e: e.depth,
                id,
                next: 0,
            });
        }
    }
    out
}

fn key(r: &Range) -> (u32, u32, u32, u32, u32) {
    (
        r.id,
        r.t_s.to_bits(),
        r.t_e.to_bits(),
        r.d_s.to_bits(),
        r.d_e.to_bits(),
    )
}

/// Returns how many pixels had an odd fragment group.
fn check_every_pixel(map: &ShadowMapContents) -> usize {
    let mut odd_pixels = 0;
    for y in 0..map.height {
        for x in 0..map.width {
            let nodes = map.nodes_at(x, y);
            let mut want: Vec<_> = expected_ranges(&nodes).iter().map(key).collect();
            let mut got: Vec<_> = map.ranges_at(x, y).iter().map(key).collect();
            want.sort();
            got.sort();
            assert_eq!(got, want, "pixel ({x},{y}), fragments {nodes:?}");
            let mut per_id: BTreeMap<u32, usize> = BTreeMap::new();
            for n in &nodes {
                *per_id.entry(n.id).or_default() += 1;
            }
            odd_pixels += usize::from(per_id.values().any(|c| c % 2 == 1));
        }
    }
    odd_pixels
}

/// The generation pass's pairing of every pixel's list, on the default scene with its static
/// triangles in the lists (with the static layer, the collection stores ranges itself: see
/// `collected_ranges_are_the_pairs_of_the_lists`).
#[test]
fn ranges_pair_fragments_on_the_default_scene() {
    let ctx = context();
    let s = builtin("cubes-toward-light", &BuiltinOptions::default()).unwrap();
    let map = temporal_map_with(&ctx, &s, (96, 72), PrismConstruction::Exact, false);
    assert!(map.nodes.len() > 10_000, "{} fragments", map.nodes.len());
    check_every_pixel(&map);
    assert_no_validation_messages(&ctx);
}

/// Where the collection stores each covered run as its range (the exact construction with
/// the static layer, the default), the ranges are the generation pass's pairs of the same runs
/// stored as nodes (static triangles in the lists): per pixel, the moving triangles' ranges
/// agree bit for bit.
#[test]
fn collected_ranges_are_the_pairs_of_the_lists() {
    let ctx = context();
    let s = builtin("cubes-toward-light", &BuiltinOptions::default()).unwrap();
    let direct = temporal_map(&ctx, &s, (96, 72));
    let lists = temporal_map_with(&ctx, &s, (96, 72), PrismConstruction::Exact, false);
    assert!(direct.nodes.is_empty(), "the collection stored nodes");
    // Global ids are given per mesh in order; a mesh whose positions do not move is static.
    let mut static_ids = Vec::new();
    let mut first = 0u32;
    for mesh in &s.meshes {
        let count = mesh.t0.len() as u32 / 3;
        if mesh.t0 == mesh.t1 {
            static_ids.push(first..first + count);
        }
        first += count;
    }
    let moving = |r: &&Range| !static_ids.iter().any(|ids| ids.contains(&r.id));
    let mut compared = 0;
    for y in 0..direct.height {
        for x in 0..direct.width {
            let mut got: Vec<_> = direct.ranges_at(x, y).iter().map(key).collect();
            let mut want: Vec<_> = lists
                .ranges_at(x, y)
                .iter()
                .filter(moving)
                .map(key)
                .collect();
            got.sort();
            want.sort();
            assert_eq!(got, want, "pixel ({x},{y})");
            compared += got.len();
        }
    }
    assert!(compared > 5_000, "only {compared} ranges compared");
    assert_no_validation_messages(&ctx);
}

/// In the papers' construction a triangle reaching through the light's near plane is cut
/// there, so pixels see an odd number of its fragments: each becomes ranges as documented,
/// with one zero-length range. (The exact construction is not clipped by the near plane:
/// tests/gpu/exact_prisms.rs.)
#[test]
fn odd_fragment_counts_from_near_plane_clipping() {
    let ctx = context();
    // The spot is at y = 10 with near = 0.5: the triangle's t = 1 position pokes above y = 9.5.
    let p0 = vec![
        Vec3::new(-1.0, 8.0, -1.0),
        Vec3::new(-1.0, 8.0, 1.0),
        Vec3::new(1.0, 8.0, 0.0),
    ];
    let p1: Vec<Vec3> = p0.iter().map(|p| *p + Vec3::new(0.3, 1.8, 0.0)).collect();
    let s = scene(
        "near-plane",
        overhead_spot(10.0, 45.0),
        vec![mesh("t", p0, p1, false)],
    );
    let map = temporal_map_with(&ctx, &s, (64, 64), PrismConstruction::Paper, true);
    let odd = check_every_pixel(&map);
    assert!(
        odd > 20,
        "expected odd fragment counts where the prism is clipped, got {odd}"
    );
    let zero_length = map
        .ranges
        .iter()
        .filter(|r| r.t_s == r.t_e && r.d_s == r.d_e)
        .count();
    assert!(
        zero_length >= odd,
        "{zero_length} zero-length ranges for {odd} odd pixels"
    );
    assert_no_validation_messages(&ctx);
}

fn stack_of_squares(count: usize) -> motion_shadows_app::scene::Scene {
    let meshes = (0..count)
        .map(|i| {
            let sq = crate::support::gpu::square(-1.0, -1.0, 2.0, 1.0 + 0.02 * i as f32);
            mesh("layer", sq.clone(), sq, false)
        })
        .collect();
    scene("stack", overhead_spot(10.0, 30.0), meshes)
}

/// Lists up to MAX_LIST_NODES long are paired exactly: 250 stacked static squares, kept in
/// the lists (no static layer), give 500 fragments per covered pixel. (On lavapipe this also
/// proves that the pass stays below the driver's cap of 65535 loop iterations per
/// invocation, past which loops silently stop.)
#[test]
fn long_lists_are_paired_exactly() {
    let ctx = context();
    let s = stack_of_squares(250);
    let map = temporal_map_with(&ctx, &s, (32, 32), PrismConstruction::Exact, false);
    let longest = (0..32 * 32)
        .map(|i| map.nodes_at(i % 32, i / 32).len())
        .max()
        .unwrap_or(0);
    assert!(longest == 500, "longest list {longest}");
    check_every_pixel(&map);
    assert_no_validation_messages(&ctx);
}

/// The refusal of a stack of 300 layers: many pixels, the longest list 600 fragments.
fn assert_too_long_with_600(err: AppError) {
    match err {
        AppError::Library(Error::FragmentListTooLong {
            pixels,
            longest,
            limit,
            ..
        }) => {
            assert!(pixels > 10, "{pixels}");
            assert_eq!(longest, 600);
            assert_eq!(limit, MAX_LIST_NODES);
        }
        other => panic!("expected FragmentListTooLong, got {other}"),
    }
}

/// Past MAX_LIST_NODES fragments in one pixel the frame is refused with the figures, never
/// rendered with ranges missing. (Static triangles in the static layer take no list room: the
/// same stack then renders.)
#[test]
fn overlong_lists_are_an_error_with_figures() {
    let ctx = context();
    let s = stack_of_squares(300);
    let settings = RenderSettings {
        width: 8,
        height: 8,
        spp: 1,
        shadow_size: Some((32, 32)),
        static_layer: false,
        ..RenderSettings::default()
    };
    let layered = RenderSettings {
        static_layer: true,
        ..settings.clone()
    };
    let rendered = Renderer::new(&ctx)
        .unwrap()
        .render(&s, &layered, &mut |_| {});
    assert_eq!(
        rendered.expect("the static layer holds it").stats.fragments,
        0
    );
    let err = Renderer::new(&ctx)
        .unwrap()
        .render(&s, &settings, &mut |_| {})
        .err()
        .expect("must fail");
    assert_too_long_with_600(err);
    assert_no_validation_messages(&ctx);
}

/// The same limit where the collection stores the ranges itself (moving squares, the static
/// layer): 300 runs per covered pixel are 600 fragments of its list, an error with the same
/// figures, and 250 (500 fragments) are not.
#[test]
fn overlong_collected_ranges_are_an_error_with_figures() {
    let ctx = context();
    let moving = |count: usize| {
        let meshes = (0..count)
            .map(|i| {
                let sq = crate::support::gpu::square(-1.0, -1.0, 2.0, 1.0 + 0.02 * i as f32);
                let t1 = sq.iter().map(|p| *p + Vec3::new(0.05, 0.0, 0.0)).collect();
                mesh("moving-layer", sq, t1, false)
            })
            .collect();
        scene("moving-stack", overhead_spot(10.0, 30.0), meshes)
    };
    let settings = RenderSettings {
        width: 8,
        height: 8,
        spp: 1,
        shadow_size: Some((32, 32)),
        ..RenderSettings::default()
    };
    let fits = Renderer::new(&ctx)
        .unwrap()
        .render(&moving(250), &settings, &mut |_| {})
        .expect("500 fragments per pixel fit");
    assert_eq!(
        fits.stats.fragments_stored, 0,
        "the collection stored nodes"
    );
    let err = Renderer::new(&ctx)
        .unwrap()
        .render(&moving(300), &settings, &mut |_| {})
        .err()
        .expect("must fail");
    assert_too_long_with_600(err);
    assert_no_validation_messages(&ctx);
}

/// A triangle whose coverage of many texels comes and goes during the shutter (several runs
/// of one triangle in one texel, the depth order of the runs' ends unlike their time order:
/// the motion `tests/gpu/several_runs.rs` found by search), kept in the lists, with either
/// construction: every pixel's ranges are the model's time-ordered pairs of its fragments.
/// Where a triangle has one run per texel every pairing order agrees, so this is the case
/// that tells them apart: it asserts that pairing by depth (both constructions) or in list
/// order (the papers' prisms, whose surfaces do not come in time order) would differ at many
/// pixels. Fails when the pass pairs by depth or in list order.
#[test]
fn ranges_pair_the_runs_of_a_triangle_covering_texels_twice() {
    let ctx = context();
    let corners = |c: [(f32, f32, f32); 3]| c.map(|(x, y, z)| Vec3::new(x, y, z)).to_vec();
    let t0 = corners([
        (-1.48, 1.75, 0.05),
        (1.73, 0.76, 1.56),
        (-1.62, 1.16, -0.99),
    ]);
    let t1 = corners([(0.07, 2.68, 1.66), (-1.0, 1.06, -0.67), (1.98, 2.19, -1.84)]);
    let s = scene(
        "twice-covering",
        overhead_directional(8.0),
        vec![mesh("triangle", t0, t1, false)],
    );
    // One triangle: pairing in another order is consecutive pairs of the list so ordered.
    let pairs = |nodes: &[Node]| {
        let mut keys: Vec<_> = (nodes.chunks(2))
            .flat_map(expected_ranges)
            .map(|r| key(&r))
            .collect();
        keys.sort();
        keys
    };
    for construction in [PrismConstruction::Exact, PrismConstruction::Paper] {
        let map = temporal_map_with(&ctx, &s, (64, 64), construction, false);
        // Pixels whose fragments the depth order, or the list's, pairs otherwise than time.
        let (mut by_depth, mut by_list) = (0, 0);
        for y in 0..map.height {
            for x in 0..map.width {
                let mut nodes = map.nodes_at(x, y);
                let mut by_time = nodes.clone();
                by_time.sort_by(|a, b| a.time.total_cmp(&b.time));
                let by_time = pairs(&by_time);
                by_list += usize::from(pairs(&nodes) != by_time);
                nodes.sort_by(|a, b| a.depth.total_cmp(&b.depth));
                by_depth += usize::from(pairs(&nodes) != by_time);
            }
        }
        // (21 and 0 with the exact construction, whose pieces come in time order; 22 and
        // 41 with the papers', on lavapipe.)
        let list_matters = construction == PrismConstruction::Paper;
        assert!(
            by_depth > 10 && (by_list > 10 || !list_matters),
            "{construction:?}: only {by_depth} pixels where pairing by depth differs, {by_list} \
             in list order"
        );
        check_every_pixel(&map);
    }
    assert_no_validation_messages(&ctx);
}
