//! The measurement plumbing: the counters agree with the lists they count. (The quick bench
//! presets' files are checked in app/tests/cli/scripted/bench_presets.rs.)

use crate::support::gpu::{
    assert_no_validation_messages, context, temporal_map, temporal_map_with,
};
use motion_shadows::technique::{PrismConstruction, ShadowMapContents};
use motion_shadows_app::render::equation_2_bytes;
use motion_shadows_app::render::range_ceiling::ranges_at_most;
use motion_shadows_app::render::upload::light_view;
use motion_shadows_app::scene::{BuiltinOptions, builtin};

/// N_f from the atomic counter equals the fragments found by walking every pixel's list (the
/// numbers a heat map would sum), and N_r likewise; equation (2) by hand on those figures.
/// With static triangles in the lists (so that the collection stores nodes and the
/// generation pass pairs them), and with the default static layer, where the collection
/// stores the ranges itself: no list, every range linked. The counts against the scene: two
/// fragments per range, at most the CPU ceiling, and with the static layer exactly the lists'
/// ranges of the triangles that move (fails when still meshes are drawn as moving).
#[test]
fn counters_equal_the_lists_they_count() {
    let ctx = context();
    let s = builtin("cubes-toward-light", &BuiltinOptions::default()).unwrap();
    let lists = temporal_map_with(&ctx, &s, (48, 36), PrismConstruction::Exact, false);
    let count = |map: &ShadowMapContents| {
        let (mut fragments, mut ranges) = (0usize, 0usize);
        for y in 0..map.height {
            for x in 0..map.width {
                fragments += map.nodes_at(x, y).len();
                ranges += map.ranges_at(x, y).len();
            }
        }
        (fragments, ranges)
    };
    let (fragments, ranges) = count(&lists);
    assert_eq!(fragments, lists.nodes.len(), "fragments linked vs counted");
    assert_eq!(ranges, lists.ranges.len(), "ranges linked vs counted");
    // The exact construction stores both ends of every run, and the scene's triangles bound
    // the runs from above (the CPU ceiling of tests/gpu/range_bound.rs).
    let light = light_view(&s, (48, 36));
    let at_most = |layer| ranges_at_most(&s, &light, (48, 36), layer).expect("exact") as usize;
    assert_eq!(fragments, 2 * ranges, "a fragment at each end of each run");
    assert!(
        ranges <= at_most(false),
        "{ranges} ranges, the scene's ceiling {}",
        at_most(false)
    );
    let pixels = 48 * 36;
    assert_eq!(
        equation_2_bytes(fragments as u64, ranges as u64, pixels),
        fragments as u64 * 16 + ranges as u64 * 24 + 2 * pixels * 4
    );

    let direct = temporal_map(&ctx, &s, (48, 36));
    let (fragments, ranges) = count(&direct);
    assert_eq!(fragments, 0, "no fragment is stored");
    assert_eq!(ranges, direct.ranges.len(), "ranges linked vs counted");
    // The static layer takes exactly the ranges of the scene's still meshes (those whose
    // positions do not move): the rest are the lists' ranges of the moving triangles.
    let mut still = Vec::new();
    let mut first = 0u32;
    for mesh in &s.meshes {
        let count = mesh.t0.len() as u32 / 3;
        if mesh.t0 == mesh.t1 {
            still.push(first..first + count);
        }
        first += count;
    }
    let moving = (lists.ranges.iter())
        .filter(|r| !still.iter().any(|ids| ids.contains(&r.id)))
        .count();
    assert!(!still.is_empty() && moving > 0 && moving < lists.ranges.len());
    assert_eq!(ranges, moving, "the ranges left beside the static layer");
    assert!(
        ranges <= at_most(true),
        "{ranges} ranges, the ceiling {}",
        at_most(true)
    );
    assert_no_validation_messages(&ctx);
}
