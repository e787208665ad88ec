//! The sorted range storage (`RangeStorage::Sorted`) against the linked lists it is sorted
//! from: the same frame collected into a map of each kind must hold, per texel, the same
//! ranges (bit for bit, in any order) but those pruning drops by the map's rule, each of
//! `Pruning`'s (the CPU model of `pruning_model.rs`), and the sorted map must hold them as the header's
//! `MS_SORTED_RANGES` says: each texel's ranges in consecutive places of the range buffer,
//! in order of (t_s, t_e, d_s, d_e, id), linked in that order, every place of the buffer
//! used exactly once (no room left between texels, none past the count).

use crate::pruning_model;
use crate::support::gpu::{assert_no_validation_messages, context};
use crate::support::scene::{
    Scene, light_view, mesh, overhead_directional, scene, square, temporal_map_stored, translated,
};
use glam::Vec3;
use motion_shadows::technique::{LightView, Pruning, Range, RangeStorage};

const SIZE: (u32, u32) = (64, 64);

/// A static ground and 12 stacked plates of 6 x 6 small squares, each sliding 1.5 units in
/// its own direction: texels under the stack hold dozens of ranges (the sort's second tier),
/// its edges a few, the plates' outskirts one or two.
fn stacked_plates() -> Scene {
    let mut meshes = vec![mesh(
        "ground",
        square(-8.0, -8.0, 16.0, 0.0),
        square(-8.0, -8.0, 16.0, 0.0),
        false,
    )];
    for i in 0..12 {
        let angle = i as f32 * std::f32::consts::TAU / 12.0;
        let step = Vec3::new(angle.cos(), 0.0, angle.sin()) * 0.75;
        let y = 1.0 + 0.25 * i as f32;
        let plate: Vec<Vec3> = (0..36)
            .flat_map(|k| {
                square(
                    -1.5 + 0.5 * (k % 6) as f32,
                    -1.5 + 0.5 * (k / 6) as f32,
                    0.5,
                    y,
                )
            })
            .collect();
        meshes.push(mesh(
            &format!("plate-{i}"),
            translated(&plate, -step),
            translated(&plate, step),
            false,
        ));
    }
    scene("stacked-plates", overhead_directional(4.0), meshes)
}

/// A range's contents without its link, as bits (so that equal means bit for bit).
fn key(r: &Range) -> [u32; 5] {
    [
        r.t_s.to_bits(),
        r.t_e.to_bits(),
        r.d_s.to_bits(),
        r.d_e.to_bits(),
        r.id,
    ]
}

/// The sort's order on contents.
fn order(r: &Range) -> (f32, f32, f32, f32, u32) {
    (r.t_s, r.t_e, r.d_s, r.d_e, r.id)
}

#[test]
fn sorted_storage_holds_the_lists_ranges_contiguous_and_in_start_order() {
    let ctx = context();
    let scene = stacked_plates();
    let light = light_view(&scene, SIZE);
    let pixels = SIZE.0 * SIZE.1;
    let (lists, list_counts) = temporal_map_stored(
        &ctx,
        &scene,
        SIZE,
        &light,
        RangeStorage::Lists,
        Pruning::default(),
        pixels,
    );
    assert_eq!(list_counts.sorted_count, 0, "lists are not sorted");
    for pruning in [Pruning::StaticLayer, Pruning::Cover, Pruning::Coverage] {
        sorted_like_lists(
            &ctx,
            &scene,
            &light,
            &lists,
            list_counts.range_count,
            pruning,
        );
    }

    // Where the generation pairs nodes (static triangles in the lists), a map made for sorted
    // storage holds what a map of lists holds: the sorting runs only on collected ranges, and
    // leaves the generation's own long-list dispatch alone (with the cover rule asked for).
    let nodes = LightView {
        static_layer: false,
        ..light
    };
    let stored = |storage, pruning| {
        temporal_map_stored(&ctx, &scene, SIZE, &nodes, storage, pruning, pixels)
    };
    let (paired_lists, _) = stored(RangeStorage::Lists, Pruning::default());
    let (paired, paired_counts) = stored(RangeStorage::Sorted, Pruning::Cover);
    assert_eq!(paired_counts.sorted_count, 0, "nothing sorted");
    assert!(
        paired_counts.longest_list > 32,
        "the generation's second tier pairs lists"
    );
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let keys = |map: &motion_shadows::technique::ShadowMapContents| {
                let mut k: Vec<[u32; 5]> = map.ranges_at(x, y).iter().map(key).collect();
                k.sort_unstable();
                k
            };
            assert_eq!(
                keys(&paired),
                keys(&paired_lists),
                "texel ({x}, {y}), paired"
            );
        }
    }
    assert_no_validation_messages(&ctx);
}

/// The stacked plates' map sorted and pruned by `pruning` against `lists`, the same frame's
/// lists (`range_count` ranges): texel for texel what the model keeps, contiguous, in order,
/// every place used once.
fn sorted_like_lists(
    ctx: &motion_shadows::gpu::Context,
    scene: &Scene,
    light: &LightView,
    lists: &motion_shadows::technique::ShadowMapContents,
    range_count: u32,
    pruning: Pruning,
) {
    // The sorted map starts with room for one range: its first run overflows, and the sort
    // must leave that run alone (the frame is recorded again with room, the rule kept).
    let (sorted, counts) =
        temporal_map_stored(ctx, scene, SIZE, light, RangeStorage::Sorted, pruning, 1);
    assert_eq!(range_count, counts.range_count, "the same frame");
    let mut dropped = 0;
    let mut steps = 0; // the cover sweep's most in one texel
    let mut used = vec![false; sorted.ranges.len()];
    let mut lengths = [0u32; 3]; // texels holding 1-2, 3-16, more than 16 ranges to sort
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            // The default light tests receivers at their own depth: no static rule.
            let all = lists.ranges_at(x, y);
            let model =
                pruning_model::prune(&all, sorted.static_at(x, y), light.receiver_plane, pruning);
            assert!(!model.out_of_budget);
            assert!(pruning_model::runs_disjoint(&all), "texel ({x}, {y})");
            dropped += model.by_static + model.by_cover;
            steps = steps.max(model.steps);
            let mut expected: Vec<[u32; 5]> = model.kept.iter().map(key).collect();
            let got = sorted.ranges_at(x, y);
            let mut got_keys: Vec<[u32; 5]> = got.iter().map(key).collect();
            expected.sort_unstable();
            got_keys.sort_unstable();
            assert_eq!(
                got_keys, expected,
                "texel ({x}, {y}): the lists' ranges kept"
            );
            if all.is_empty() {
                continue;
            }
            lengths[match all.len() {
                1..=2 => 0,
                3..=16 => 1,
                _ => 2,
            }] += 1;
            if got.is_empty() {
                continue;
            }
            let first = sorted.range_heads[(y * SIZE.0 + x) as usize] as usize - 1;
            for (i, r) in got.iter().enumerate() {
                let place = first + i;
                assert_eq!(sorted.ranges[place], *r, "texel ({x}, {y}): contiguous");
                assert!(!used[place], "place {place} used twice");
                used[place] = true;
            }
            for pair in got.windows(2) {
                assert!(
                    order(&pair[0]) <= order(&pair[1]),
                    "texel ({x}, {y}): {:?} before {:?}",
                    pair[0],
                    pair[1]
                );
            }
        }
    }
    assert!(used.iter().all(|&u| u), "every place holds a texel's range");
    assert_eq!(
        counts.sorted_count as usize,
        counts.range_count as usize - dropped,
        "places reserved = ranges kept"
    );
    assert_eq!(sorted.ranges.len(), counts.sorted_count as usize);
    println!(
        "{pruning:?}: texels with 1-2, 3-16, more ranges: {lengths:?}; {dropped} ranges \
         pruned; at most {steps} sweep steps in a texel (budget {})",
        pruning_model::BUDGET
    );
    // Under the offset test only the cover rule drops anything, and on these plates much.
    match pruning {
        Pruning::StaticLayer => assert_eq!(dropped, 0),
        Pruning::Cover => assert!(dropped * 4 > counts.range_count as usize, "{dropped}"),
        // No plate holds a texel all frame here: the slow plates below test that rule.
        Pruning::Coverage => assert_eq!(dropped, 0),
    }
    assert!(
        lengths.iter().all(|&n| n > 50),
        "every tier sorts many texels: {lengths:?}"
    );
}

/// Random plates sliding at random heights, speeds (times `speed`) and directions, tilted
/// through each other's depths, above, below and through a static roof that covers part of
/// the map, over a static ground. Slow plates (`speed` 0.1, under a tenth of a plate's square
/// each way) cover many texels all frame: the coverage rule's case.
fn random_plates(seed: u32, speed: f32) -> Scene {
    let mut state = seed.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let mut random = move || {
        state = state.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
        (state >> 8) as f32 / (1u32 << 24) as f32
    };
    let roof = square(-3.0, -3.0, 4.0, 5.0);
    let ground = square(-8.0, -8.0, 16.0, 0.0);
    let mut meshes = vec![
        mesh("ground", ground.clone(), ground, false),
        mesh("roof", roof.clone(), roof, false),
    ];
    for i in 0..10 {
        let angle = random() * std::f32::consts::TAU;
        let step = Vec3::new(angle.cos(), 0.0, angle.sin()) * (0.3 + random()) * speed;
        // Heights from under the roof (depth 5) to above it; a tilt through it.
        let y = 1.0 + 6.0 * random();
        let tilt = Vec3::new(0.0, 2.0 * random() - 1.0, 0.0);
        let plate: Vec<Vec3> = (0..16)
            .flat_map(|k| {
                let (x, z) = (-2.0 + (k % 4) as f32, -2.0 + (k / 4) as f32);
                square(x, z, 1.0, y)
            })
            .map(|p| p + tilt * (p.x / 2.0))
            .collect();
        meshes.push(mesh(
            &format!("plate-{i}"),
            translated(&plate, -step),
            translated(&plate, step),
            false,
        ));
    }
    scene("roof", overhead_directional(4.0), meshes)
}

/// Pruning (docs/src/pruning.md) against the CPU model of both its rules
/// (`pruning_model.rs`), on random plates around a static roof (`random_plates`), with each
/// receiver test. Per texel, the sorted map must hold exactly the lists' ranges that the
/// model keeps (reading the static triangle and its depth from the downloaded layer), for
/// every seed; and each rule must drop many ranges, the cover rule with either test (the
/// static rule only with the plane test), so that the comparison is not vacuous. The
/// default, `Pruning::StaticLayer`, must drop exactly what the static rule drops.
#[test]
fn pruning_drops_exactly_the_ranges_the_model_drops() {
    let ctx = context();
    let static_layer = drops_as_the_model(&ctx, Pruning::StaticLayer);
    assert_eq!(
        static_layer.by_static,
        [62_710, 0],
        "the same as before the cover rule"
    );
    assert_eq!(static_layer.by_cover, [0, 0]);
    let cover = drops_as_the_model(&ctx, Pruning::Cover);
    assert_eq!(
        cover.by_static, static_layer.by_static,
        "the static rule first"
    );
    assert!(
        cover.by_cover.iter().all(|&n| n > 1000),
        "cover rule: {:?}",
        cover.by_cover
    );
    // Slow plates (random_plates' speed 0.1): many texels held all frame by one plate.
    let coverage = drops_as_the_model(&ctx, Pruning::Coverage);
    assert!(
        coverage.by_cover.iter().all(|&n| n > 1000),
        "coverage rule: {:?}",
        coverage.by_cover
    );
    assert_no_validation_messages(&ctx);
}

/// Ranges dropped per receiver test (plane, offset), by each rule.
struct Dropped {
    by_static: [usize; 2],
    by_cover: [usize; 2],
}

/// `pruning_drops_exactly_the_ranges_the_model_drops` with the maps sorted by `pruning`.
fn drops_as_the_model(ctx: &motion_shadows::gpu::Context, pruning: Pruning) -> Dropped {
    let mut by_static = [0; 2];
    let mut by_cover = [0; 2];
    let mut kept_under_roof = 0;
    let mut deep = 0;
    for seed in 1..=4u32 {
        let speed = if pruning == Pruning::Coverage {
            0.1
        } else {
            1.0
        };
        let scene = random_plates(seed, speed);
        for (k, plane) in [true, false].into_iter().enumerate() {
            let light = LightView {
                receiver_plane: plane,
                normal_offset_texels: if plane { 0.0 } else { 1.0 },
                ..light_view(&scene, SIZE)
            };
            let pixels = SIZE.0 * SIZE.1;
            let stored = |storage, pruning| {
                temporal_map_stored(ctx, &scene, SIZE, &light, storage, pruning, pixels)
            };
            let (lists, _) = stored(RangeStorage::Lists, Pruning::default());
            let (sorted, counts) = stored(RangeStorage::Sorted, pruning);
            assert_eq!(sorted.ranges.len(), counts.sorted_count as usize);
            let mut dropped = 0;
            for y in 0..SIZE.1 {
                for x in 0..SIZE.0 {
                    let all = lists.ranges_at(x, y);
                    let model = pruning_model::prune(&all, sorted.static_at(x, y), plane, pruning);
                    assert!(!model.out_of_budget, "seed {seed}, texel ({x}, {y})");
                    assert!(
                        pruning_model::runs_disjoint(&all),
                        "seed {seed}, texel ({x}, {y})"
                    );
                    let mut expected: Vec<[u32; 5]> = model.kept.iter().map(key).collect();
                    let mut got: Vec<[u32; 5]> = sorted.ranges_at(x, y).iter().map(key).collect();
                    expected.sort_unstable();
                    got.sort_unstable();
                    assert_eq!(
                        got, expected,
                        "{pruning:?}, seed {seed}, plane {plane}, texel ({x}, {y})"
                    );
                    dropped += model.by_static + model.by_cover;
                    by_static[k] += model.by_static;
                    by_cover[k] += model.by_cover;
                    deep += usize::from(all.len() > 16);
                    let under_roof = sorted.static_at(x, y).is_some_and(|(_, d)| d < 6.0);
                    if plane && under_roof && !expected.is_empty() {
                        kept_under_roof += 1;
                    }
                }
            }
            assert_eq!(
                counts.range_count as usize - dropped,
                counts.sorted_count as usize,
                "seed {seed}, plane {plane}: the sorted buffer holds the kept ranges"
            );
        }
    }
    println!(
        "{pruning:?}: dropped by the static rule {by_static:?}, by the cover rule \
         {by_cover:?} (plane, offset test); {kept_under_roof} roof texels keep some; {deep} \
         lists over 16"
    );
    assert!(by_static[0] > 1000, "static rule: {by_static:?}");
    assert_eq!(by_static[1], 0, "no static rule with the offset test");
    assert!(
        kept_under_roof > 100,
        "kept under the roof: {kept_under_roof}"
    );
    Dropped {
        by_static,
        by_cover,
    }
}
