//! The union of a texel's shadowed intervals (`ms_lit_fraction` and, for receivers that move,
//! `ms_texel_lit_span`) where an interval merged later starts before the one it joins: the
//! ranges of a texel are merged in list order (sorted storage: by range start), and a range
//! that crosses the receiver's depth shadows only from the crossing on, so an interval that
//! comes after it in the list may still start before it.

use super::moving::moving_lit;
use super::{
    Caster, SHADOW, caster_frame, caster_interval, caster_world,
    lit_fraction_queries_along_texel_row, new_host, probe, union_length,
};
use glam::{DVec3, Vec3};

/// A square rising through the ground under [-1, 1] (height -3 to 1: its range over those
/// texels is the whole shutter, but it is nearer than the ground only from t = 3/4 on), and a
/// wider one sliding over it at height 2 that reaches each of those texels between t = 1/8
/// and 5/8 and stays past the shutter's end: after the rising square in each texel's list,
/// and shadowing from before its crossing.
const CASTERS: [Caster; 2] = [
    Caster {
        x0: -1.0,
        travel: 0.0,
        h0: -3.0,
        h1: 1.0,
        width: 2.0,
    },
    Caster {
        x0: -5.0,
        travel: 4.0,
        h0: 2.0,
        h1: 2.0,
        width: 3.5,
    },
];

/// At the texel centres of a row across both casters, through the host's probe shader
/// (`ms_lit_fraction`) and its moving probe for receivers that stand still
/// (`ms_lit_fraction_moving`), against 1 minus the length of the union of the closed-form
/// intervals during which a caster is nearer than the tested receiver (the ground point moved
/// up by the normal offset of one texel, its depth less the relative bias 1e-4). Over the
/// rising square the union is [start of the sliding one's, 1]: a merge that kept the earlier
/// interval's start would give [3/4, 1], off by 1/8 to 5/8. Tolerance 1e-3 (f32 rounding; at
/// texel centres the map holds the point's own intervals).
#[test]
fn an_interval_merged_later_that_starts_before_a_depth_crossing_extends_the_union() {
    let host = new_host();
    let world = caster_world(&CASTERS);
    let (engine, frame) = caster_frame(&host, &world);
    let map = engine.shadow_map(frame.slot, 0);
    let queries = lit_fraction_queries_along_texel_row(&world, 0.0);
    let still = probe(&host, map, &queries);
    let paths: Vec<(DVec3, DVec3)> = queries
        .iter()
        .map(|q| {
            let p = Vec3::from(q.position).as_dvec3();
            (p, p)
        })
        .collect();
    let moving = moving_lit(&host, map, &paths);
    let texel = 2.0 * 6.0 / f64::from(SHADOW.0);
    let margin = 10.0 - (10.0 - texel) * (1.0 - 1e-4);
    let mut merged_earlier = 0;
    for ((q, &got_still), &got_moving) in queries.iter().zip(&still).zip(&moving) {
        let (x, z) = (f64::from(q.position[0]), f64::from(q.position[2]));
        let [rising, sliding] = CASTERS.map(|c| caster_interval(&c, x, z, margin));
        let intervals: Vec<(f64, f64)> = [rising, sliding].into_iter().flatten().collect();
        let expected = 1.0 - union_length(intervals.clone()).min(1.0);
        for (name, got) in [
            ("ms_lit_fraction", f64::from(got_still)),
            ("ms_lit_fraction_moving", got_moving),
        ] {
            assert!(
                (got - expected).abs() <= 1e-3,
                "texel centre x = {x:.3}: {name} {got}, closed form {expected} \
                 (intervals {intervals:?})"
            );
        }
        if let (Some(r), Some(s)) = (rising, sliding) {
            merged_earlier += usize::from(s.0 + 0.1 < r.0 && s.1 >= r.0);
        }
    }
    assert!(
        merged_earlier >= 30,
        "only {merged_earlier} texels merge an earlier start"
    );
    drop(engine);
    assert_eq!(host.validation_messages(), Vec::<String>::new());
}
