//! The generation sub-pass against a CPU model of it: per pixel, group the stored fragments by
//! triangle, order each group by depth, pair 1st-2nd, 3rd-4th, ...; an odd group's farthest
//! fragment becomes a zero-length range.

use crate::support::gpu::{
    assert_no_validation_messages, context, mesh, overhead_spot, scene, temporal_map,
};
use glam::Vec3;
use motion_shadows::scene::{BuiltinOptions, builtin};
use motion_shadows::technique::{Node, Range, ShadowMapContents};
use std::collections::BTreeMap;

fn expected_ranges(nodes: &[Node]) -> Vec<Range> {
    let mut groups: BTreeMap<u32, Vec<Node>> = BTreeMap::new();
    for n in nodes {
        groups.entry(n.id).or_default().push(*n);
    }
    let mut out = Vec::new();
    for (id, mut group) in groups {
        group.sort_by(|a, b| a.depth.total_cmp(&b.depth));
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

#[test]
fn ranges_pair_fragments_on_the_default_scene() {
    let ctx = context();
    let s = builtin("cubes-toward-light", &BuiltinOptions::default()).unwrap();
    let map = temporal_map(&ctx, &s, (96, 72));
    assert!(map.nodes.len() > 10_000, "{} fragments", map.nodes.len());
    check_every_pixel(&map);
    assert_no_validation_messages(&ctx);
}

/// A triangle reaching through the light's near plane is cut there, so pixels see an odd
/// number of its fragments: each becomes ranges as documented, with one zero-length range.
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
    let map = temporal_map(&ctx, &s, (64, 64));
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
