//! The library's per-texel sample test against `ms_texel_shadowed`, through a probe shader.

use super::*;

/// The lighting pass tests a pixel's samples per texel (`ms_samples_shadowed`, glsl/
/// temporal_samples.glsl, not part of the public include); each sample must get exactly what
/// `ms_texel_shadowed` answers for it alone. Groups of 8 receivers around one point (within
/// a texel or two, so some share a texel and some do not), at random times, on the ground or
/// just below a caster, with their own triangle's id, another triangle's, or none: the two
/// answers agree for every one, and the own ids decide many of them (the test fails when
/// either function drops the own-triangle skip, or the static layer, coverage or time test).
#[test]
fn per_texel_sample_tests_answer_as_ms_texel_shadowed() {
    let host = new_host();
    let (engine, frame) = interval_frame(&host);
    let texel = 2.0 * 6.0 / f64::from(SHADOW.0);
    let mut rng = 0x2545_f491_4f6c_dd1du64;
    let mut uniform = move || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        (rng >> 11) as f64 / (1u64 << 53) as f64
    };
    // Global ids: the ground's 32 triangles, then two per caster.
    let ground_triangles = 2 * 4 * 4;
    let ids: Vec<u32> = (0..ground_triangles + 6).collect();
    let mut queries = Vec::new();
    for _ in 0..400 {
        let (x, z) = (-5.5 + 11.0 * uniform(), Z0 + f64::from(SIDE) * uniform());
        // Below the ground, below the low caster, or below the high one.
        let surface = (uniform() * 3.0) as usize;
        let height = [-0.2, 0.8, 1.8][surface];
        for _ in 0..8 {
            let (px, pz) = (
                x + 2.0 * texel * (uniform() - 0.5),
                z + 2.0 * texel * (uniform() - 0.5),
            );
            // A third each: the id of the surface just above (either triangle of a caster),
            // any id, none.
            let own = match (uniform() * 3.0) as usize {
                0 if surface == 0 => ground_triangle(DVec3::new(px, 0.0, pz), 0.0).unwrap_or(0),
                0 => ground_triangles + 2 * (surface as u32 - 1) + u32::from(uniform() < 0.5),
                1 => ids[(uniform() * ids.len() as f64) as usize],
                _ => u32::MAX,
            };
            queries.push(Query {
                position: [px as f32, height as f32, pz as f32],
                time: uniform() as f32,
                normal: [0.0, 1.0, 0.0],
                own,
            });
        }
    }
    let map = engine.shadow_map(frame.slot, 0);
    let answers = run_probe(
        &host,
        map,
        &queries,
        SAMPLES_PROBE_COMP,
        Shape {
            per_invocation: 8,
            workgroup: 16,
            results_per_query: 2,
        },
    );
    // The same receivers without their own ids: how many answers the ids decide.
    let anonymous: Vec<Query> = queries
        .iter()
        .map(|q| Query {
            own: u32::MAX,
            ..*q
        })
        .collect();
    let without_ids = probe(&host, map, &anonymous);
    let (mut shadowed, mut decided_by_id) = (0, 0);
    for (i, (q, pair)) in queries.iter().zip(answers.chunks_exact(2)).enumerate() {
        assert_eq!(
            pair[0], pair[1],
            "query {i} {q:?}: per texel {}, alone {}",
            pair[0], pair[1]
        );
        shadowed += usize::from(pair[1] == 1.0);
        // Shadowed without an id (probe gives visibility: 0), lit with its own.
        decided_by_id += usize::from(pair[1] == 0.0 && without_ids[i] == 0.0);
    }
    eprintln!(
        "{} receivers: {shadowed} shadowed, {decided_by_id} lit only by their own id",
        queries.len()
    );
    assert!(
        shadowed >= 300 && queries.len() - shadowed >= 300 && decided_by_id >= 100,
        "{shadowed} shadowed, {decided_by_id} decided by the id"
    );
    drop(engine);
    host.assert_clean_teardown();
}
