//! A receiver's own triangle never shadows it, in the mask or the lit fraction.

use super::*;

/// The self-shadow rule: a receiver's own triangle never shadows it. Points just below a
/// moving caster's surface (at a time it covers them, away from its diagonal and from the
/// other casters) and just below the ground (where no caster covers them then) are in the
/// shadow of their own surface by depth: `ms_visibility` must say 1 with their own triangle's
/// id, and 0 without one (`MS_NO_TRIANGLE`). The ground's own test is the static layer's, the
/// caster's its ranges'.
#[test]
fn a_receivers_own_triangle_never_shadows_it() {
    let host = new_host();
    let (engine, frame) = interval_frame(&host);
    // Global ids: the ground's 32 triangles, then two per caster.
    let ground_triangles = 2 * 4 * 4;
    let texel = 2.0 * 6.0 / f64::from(SHADOW.0);
    let z = Z0 + 0.37 * f64::from(SIDE);
    let (mut queries, mut owns) = (Vec::new(), Vec::new());
    for t in [0.2, 0.5, 0.8] {
        for i in 0..240 {
            let x = -5.8 + 11.6 * f64::from(i) / 240.0;
            let covering: Vec<usize> = INTERVAL_CASTERS
                .iter()
                .enumerate()
                .filter(|(_, c)| {
                    let left = c.x0 + c.travel * t;
                    x > left - 2.0 * texel && x < left + c.width + 2.0 * texel
                })
                .map(|(k, _)| k)
                .collect();
            let (position, own) = match covering[..] {
                // Below the ground, its own triangle's id (away from the grid's diagonals and
                // its cells' edges, every 3 units, where a texel may be a neighbour's).
                [] => match ground_triangle(DVec3::new(x, 0.0, z), 2.0 * texel) {
                    Some(id) if ((x + 6.0).rem_euclid(3.0) - 1.5).abs() < 1.5 - 2.0 * texel => {
                        ([x as f32, -0.2, z as f32], id)
                    }
                    _ => continue,
                },
                // Just below a flat caster that alone covers the point, inside it by two
                // texels (the ranges of its texel are its own).
                [k] if INTERVAL_CASTERS[k].h0 == INTERVAL_CASTERS[k].h1 => {
                    let c = &INTERVAL_CASTERS[k];
                    let (u, w) = (
                        (x - c.x0 - c.travel * t) / c.width,
                        (z - Z0) / f64::from(SIDE),
                    );
                    if !(2.0 * texel / c.width..1.0 - 2.0 * texel / c.width).contains(&u)
                        || (u - w).abs() < 2.0 * texel
                    {
                        continue;
                    }
                    // (0, 1, 2) is the half with w > u.
                    let id = ground_triangles + 2 * k as u32 + u32::from(w < u);
                    ([x as f32, (c.h0 - 0.2) as f32, z as f32], id)
                }
                _ => continue,
            };
            for own in [own, u32::MAX] {
                queries.push(Query {
                    position,
                    time: t as f32,
                    normal: [0.0, 1.0, 0.0],
                    own,
                });
                owns.push(own != u32::MAX);
            }
        }
    }
    let lit = probe(&host, engine.shadow_map(frame.slot, 0), &queries);
    let (mut under_ground, mut under_caster) = (0, 0);
    for ((q, &own), &got) in queries.iter().zip(&owns).zip(&lit) {
        let expected = if own { 1.0 } else { 0.0 };
        assert_eq!(
            got, expected,
            "point {:?} at t = {}, own id {}: ms_visibility {got}",
            q.position, q.time, q.own
        );
        if own {
            if q.position[1] < 0.0 {
                under_ground += 1;
            } else {
                under_caster += 1;
            }
        }
    }
    eprintln!(
        "own triangle skipped: {under_ground} points under the ground, {under_caster} under a caster"
    );
    assert!(
        under_ground >= 50 && under_caster >= 50,
        "{under_ground} / {under_caster}"
    );
    drop(engine);
    host.assert_clean_teardown();
}

/// The own-triangle rule in the lit fraction: points 0.2 below the slow wide caster (the only
/// one above them), at texel centres along a row across its path. The square's two triangles
/// pass over such a point one after the other (its diagonal splits each pass), so with the
/// id of one of them `ms_lit_fraction` is 1 minus the time the other covers the point, and
/// with no id 1 minus the time the square does (closed forms from the caster's motion;
/// tolerance 1e-3). Fails when the lit fraction counts the receiver's own ranges.
#[test]
fn a_receivers_own_triangle_never_darkens_its_lit_fraction() {
    let host = new_host();
    let (engine, frame) = interval_frame(&host);
    // Global ids: the ground's 32 triangles, then two per caster ((0, 1, 2) is the half of
    // the square with w > u).
    let ground_triangles = 2 * 4 * 4;
    let k = 1;
    let c = &INTERVAL_CASTERS[k];
    let first = ground_triangles + 2 * k as u32;
    // The time during which the square's u (0 at its leading... trailing edge x0 + travel t,
    // 1 at the other) lies in [a, b] at world x.
    let covered = |x: f64, a: f64, b: f64| {
        let from = ((x - c.x0 - b * c.width) / c.travel).max(0.0);
        let to = ((x - c.x0 - a * c.width) / c.travel).min(1.0);
        (to - from).max(0.0)
    };
    let (mut queries, mut expected) = (Vec::new(), Vec::new());
    let mut decided = 0;
    for q in lit_fraction_queries_along_texel_row(&interval_world(), Z0 + 0.37 * f64::from(SIDE)) {
        let (x, z) = (f64::from(q.position[0]), f64::from(q.position[2]));
        let w = (z - Z0) / f64::from(SIDE);
        // Triangle `first` covers u < w, triangle `first + 1` u > w.
        let (upper, lower) = (covered(x, 0.0, w), covered(x, w, 1.0));
        if upper + lower == 0.0 {
            continue;
        }
        let position = [q.position[0], (c.h0 - 0.2) as f32, q.position[2]];
        for (own, lit) in [
            (u32::MAX, 1.0 - (upper + lower)),
            (first, 1.0 - lower),
            (first + 1, 1.0 - upper),
        ] {
            queries.push(Query {
                position,
                time: -1.0,
                normal: [0.0, 1.0, 0.0],
                own,
            });
            expected.push(lit);
        }
        decided += usize::from(upper > 0.05) + usize::from(lower > 0.05);
    }
    let got = probe(&host, engine.shadow_map(frame.slot, 0), &queries);
    for ((q, &want), &got) in queries.iter().zip(&expected).zip(&got) {
        assert!(
            (f64::from(got) - want).abs() <= 1e-3,
            "point {:?}, own id {}: ms_lit_fraction {got}, closed form {want}",
            q.position,
            q.own
        );
    }
    eprintln!(
        "{} queries; {decided} where the own triangle covers the point 5% of the shutter or more",
        queries.len()
    );
    assert!(decided >= 20, "{decided}");
    drop(engine);
    host.assert_clean_teardown();
}
