//! The measurement plumbing: the counters agree with the lists they count. (The quick bench
//! presets' files are checked in app/tests/cli.rs.)

use crate::support::gpu::{
    assert_no_validation_messages, context, temporal_map, temporal_map_with,
};
use motion_shadows::technique::{PrismConstruction, ShadowMapContents};
use motion_shadows_app::render::equation_2_bytes;
use motion_shadows_app::scene::{BuiltinOptions, builtin};

/// N_f from the atomic counter equals the fragments found by walking every pixel's list (the
/// numbers a heat map would sum), and N_r likewise; equation (2) by hand on those figures.
/// With static triangles in the lists (so that the collection stores nodes and the
/// generation pass pairs them), and with the default static layer, where the collection
/// stores the ranges itself: no list, every range linked.
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
    assert!(fragments > 1000);
    let pixels = 48 * 36;
    assert_eq!(
        equation_2_bytes(fragments as u64, ranges as u64, pixels),
        fragments as u64 * 16 + ranges as u64 * 24 + 2 * pixels * 4
    );

    let direct = temporal_map(&ctx, &s, (48, 36));
    let (fragments, ranges) = count(&direct);
    assert_eq!(fragments, 0, "no fragment is stored");
    assert_eq!(ranges, direct.ranges.len(), "ranges linked vs counted");
    assert!(ranges > 500);
    assert_no_validation_messages(&ctx);
}
