//! The lit fraction over overlapping casters: the union of their ranges, cut where a caster's
//! depth crosses the receiver's.

use super::*;

/// `ms_lit_fraction` where the ranges over a receiver overlap, nest, and cross its depth:
/// at the texel centres of a row across every caster's path, through the host's probe shader,
/// against 1 minus the length of the union of the closed-form intervals during which a
/// caster is nearer to the light than the ground point (the sinking square's interval ends
/// where its depth passes the receiver's, near a quarter into the shutter: the receiver is
/// the ground point moved up by the light's normal offset of one texel, its depth less the
/// relative bias of 1e-4).
/// Tolerance 1e-3 (f32 rounding; at texel centres the map holds the point's own intervals).
/// The row is chosen, and checked, to hold texels where intervals overlap partly, where one
/// nests in another, and where the crossing decides: summing instead of uniting, or taking
/// the wrong side of the crossing, moves those by more than 0.1.
#[test]
fn lit_fraction_unites_overlapping_ranges_and_cuts_at_the_depth_crossing() {
    let host = new_host();
    let (engine, frame) = interval_frame(&host);
    let queries =
        lit_fraction_queries_along_texel_row(&interval_world(), Z0 + 0.5 * f64::from(SIDE));
    let lit = probe(&host, engine.shadow_map(frame.slot, 0), &queries);
    // The receiver tested: the ground point moved up by the light's normal offset (one
    // texel: the box is 12 units across the map), its depth less the relative bias 1e-4.
    let texel = 2.0 * 6.0 / f64::from(SHADOW.0);
    let margin = 10.0 - (10.0 - texel) * (1.0 - 1e-4);
    let (mut overlapping, mut nested, mut crossing, mut worst) = (0, 0, 0, 0.0f64);
    let mut wrong = Vec::new();
    for (q, &got) in queries.iter().zip(&lit) {
        let (x, z) = (f64::from(q.position[0]), f64::from(q.position[2]));
        let intervals: Vec<(f64, f64)> = INTERVAL_CASTERS
            .iter()
            .filter_map(|c| caster_interval(c, x, z, margin))
            .collect();
        let expected = 1.0 - union_length(intervals.clone()).min(1.0);
        let error = (f64::from(got) - expected).abs();
        if error > 1e-3 {
            wrong.push(format!(
                "texel centre x = {x:.3}: ms_lit_fraction {got}, closed form {expected} \
                 (intervals {intervals:?})"
            ));
        }
        worst = worst.max(error);
        let summed: f64 = intervals.iter().map(|(a, b)| b - a).sum();
        if summed - union_length(intervals.clone()) > 0.1 {
            let (a, b) = (intervals[0], intervals[1]);
            let nests = (a.0 <= b.0 && b.1 <= a.1) || (b.0 <= a.0 && a.1 <= b.1);
            if nests {
                nested += 1;
            } else {
                overlapping += 1;
            }
        }
        let sinking = &INTERVAL_CASTERS[2];
        if caster_interval(sinking, x, z, margin).is_some()
            && intervals.len() == 1
            && (expected - 0.76).abs() < 0.01
        {
            crossing += 1;
        }
    }
    assert!(
        wrong.is_empty(),
        "{} of {} texel centres off by more than 1e-3:\n{}",
        wrong.len(),
        queries.len(),
        wrong.join("\n")
    );
    eprintln!(
        "ms_lit_fraction at {} texel centres: {overlapping} with overlapping intervals, \
         {nested} nested, {crossing} decided by a depth crossing; max error {worst:.2e}",
        queries.len()
    );
    assert!(
        overlapping >= 15 && nested >= 15 && crossing >= 15,
        "{overlapping} overlapping, {nested} nested, {crossing} crossing"
    );
    drop(engine);
    host.assert_clean_teardown();
}
