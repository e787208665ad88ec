//! The sorted range storage, pruned (docs/src/pruning.md: by the static rule, the default, and
//! by the cover rule, `--pruning cover`), answers every lookup as the linked lists do: on every built-in scene and two examples
//! (deep lists; plates under a static roof, a third of their ranges pruned), the same image
//! bit for bit with the papers' sampled test, and on scenes with moving and static receivers
//! also with it filtered (one texel at a time, `ms_shadowed`), with the analytic estimator
//! (static receivers' lit fraction, the footprint filter) and in the deferred frame, whose
//! moving receivers walk a texel's ranges once per texel crossed (`ms_lit_fraction_moving`,
//! which stops at the first sorted range past its window; on two built-in scenes and both
//! examples). The lists are the oracle here: the sorted map holds exactly their ranges but
//! those pruned (tests/gpu/sorted_ranges.rs), so any difference is a lookup that read the
//! order wrongly (stopped too early) or a pruned range that decided a test.

use crate::support::gpu::{assert_no_validation_messages, context};
use crate::support::ray_traced::rmse_against_the_ray_tracer;
use motion_shadows::technique::{Pruning, RangeStorage, ShadowEstimator, ShadowFilter};
use motion_shadows_app::render::deferred::DeferredSettings;
use motion_shadows_app::render::{Method, ReceiverTest, RenderSettings, Renderer, stats};
use motion_shadows_app::scene::{BUILTIN_NAMES, BuiltinOptions, builtin, load_scene_file};
use std::path::Path;

fn settings((range_storage, pruning): (RangeStorage, Pruning)) -> RenderSettings {
    RenderSettings {
        width: 64,
        height: 48,
        spp: 4,
        seed: 5,
        shadow_size: Some((128, 128)),
        method: Method::Temporal,
        range_storage,
        pruning,
        ..RenderSettings::default()
    }
}

/// The storages compared: the lists (the oracle), then sorted ranges pruned by each rule.
const LISTS: (RangeStorage, Pruning) = (RangeStorage::Lists, Pruning::StaticLayer);
const SORTED: [(RangeStorage, Pruning); 3] = [
    (RangeStorage::Sorted, Pruning::StaticLayer),
    (RangeStorage::Sorted, Pruning::Cover),
    (RangeStorage::Sorted, Pruning::Coverage),
];

#[test]
fn sorted_ranges_render_what_the_lists_render() {
    let ctx = context();
    let options = BuiltinOptions {
        cube_count: 300,
        ..BuiltinOptions::default()
    };
    // The receiver test too: the static rule prunes with the plane test alone, the cover
    // rule with either, and only under the offset test does a receiver on a covering
    // triangle lie behind its own stored depth (where one cover would not suffice).
    let (plane, offset) = (ReceiverTest::Auto, ReceiverTest::Offset);
    let variants = [
        (
            "sampled",
            ShadowEstimator::Sampled,
            ShadowFilter::None,
            plane,
        ),
        (
            "offset",
            ShadowEstimator::Sampled,
            ShadowFilter::None,
            offset,
        ),
        (
            "bilinear",
            ShadowEstimator::Sampled,
            ShadowFilter::Bilinear,
            plane,
        ),
        (
            "analytic",
            ShadowEstimator::Analytic,
            ShadowFilter::None,
            plane,
        ),
        (
            "analytic offset",
            ShadowEstimator::Analytic,
            ShadowFilter::None,
            offset,
        ),
        (
            "footprint",
            ShadowEstimator::Analytic,
            ShadowFilter::Footprint,
            plane,
        ),
    ];
    // One renderer for every frame (its pipelines are made once).
    let mut renderer = Renderer::new(&ctx).expect("renderer");
    let mut render = |scene: &motion_shadows_app::scene::Scene, settings: &RenderSettings| {
        motion_shadows_app::frame::render(Some(&mut renderer), scene, settings, &mut |_| {})
            .expect("render")
    };
    let mut compared = 0;
    let mut pruned = [0; 3];
    // Every built-in scene, and two of the docs' examples: deep lists, and plates sliding
    // under a static roof (a third of their ranges pruned).
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/examples");
    let files = ["stacked-plates", "plates-under-roof"];
    // And cubes of edge 16, whose faces hold texels all frame: the coverage rule's case.
    let big_cubes = BuiltinOptions {
        cube_size: 16.0,
        ..options.clone()
    };
    // Not moving-light: its light moves (no static layer, none of the pruning rules' cases;
    // its map is checked against the ray tracer in moving_light.rs). Not camera-pan: its map
    // is the default scene's (the camera does not change the map).
    let scenes = (BUILTIN_NAMES
        .iter()
        .map(|&name| (name, builtin(name, &options).unwrap()))
        .filter(|(_, scene)| !scene.light.moves() && !scene.camera.moves()))
    .chain(files.iter().map(|&name| {
        let path = examples.join(format!("{name}.json"));
        (name, load_scene_file(&path).unwrap())
    }))
    .chain([(
        "random-cubes-16",
        builtin("random-cubes", &big_cubes).unwrap(),
    )]);
    for (name, scene) in scenes {
        // Every scene with the papers' test; five with the others too (the stacked plates
        // and random-cubes: many ranges the cover rule prunes, under lookups that measure
        // the union of the shadowing intervals).
        let all = [
            "cubes-toward-light",
            "leg-toward-light",
            "hard-rotating-triangle",
            "random-cubes",
            "random-cubes-16",
            "stacked-plates",
            "plates-under-roof",
        ];
        for (what, estimator, filter, receiver) in variants {
            if what != "sampled" && !all.contains(&name) {
                continue;
            }
            let at = |storage| RenderSettings {
                shadow_estimator: estimator,
                shadow_filter: filter,
                receiver,
                ..settings(storage)
            };
            let lists = render(&scene, &at(LISTS));
            assert_eq!(lists.stats.range_storage, "lists");
            assert_eq!(lists.stats.pruning, "none");
            assert_eq!(lists.stats.ranges_pruned, 0);
            // Per rule (static, cover): the ranges pruned.
            let mut by_rule = [0; 3];
            for (k, storage) in SORTED.into_iter().enumerate() {
                let sorted = render(&scene, &at(storage));
                let rule = stats::pruning_name(storage.1);
                assert_eq!(sorted.stats.range_storage, "sorted", "{name}");
                assert_eq!(sorted.stats.pruning, rule, "{name}");
                assert_eq!(
                    lists.stats.ranges, sorted.stats.ranges,
                    "{name}: the same frame"
                );
                assert!(
                    lists.image.rgb == sorted.image.rgb,
                    "{name}, {what}, {rule}: the sorted ranges' image differs from the lists'"
                );
                if name == "cubes-toward-light" && what == "sampled" {
                    // The lists and the sorted ranges share the lookup, so their agreement
                    // cannot see it break: the image must also be as near the ray tracer's
                    // (the same samples, no shadow map) as texel-sized shadow edges allow.
                    // Measured (lavapipe, 2026-12-07): RMSE 0.0087 under every rule; with a
                    // range that shadows past its end time (the mutant
                    // `lighting-lookup-range-past-its-end`, in both storages) 0.0161.
                    let rmse = rmse_against_the_ray_tracer(&scene, &at(storage), &sorted.image);
                    assert!(
                        rmse < 0.012,
                        "{name}, {rule}: RMSE {rmse} against the ray tracer"
                    );
                }
                compared += 1;
                pruned[k] += sorted.stats.ranges_pruned;
                by_rule[k] = sorted.stats.ranges_pruned;
                if what == "sampled" || what == "offset" {
                    println!(
                        "{name}, {what}, {rule}: {} of {} ranges pruned",
                        sorted.stats.ranges_pruned, sorted.stats.ranges
                    );
                }
                // (The static rule prunes only where receivers are tested at their plane.)
                if name == "plates-under-roof" && (storage.1 == Pruning::Cover || receiver == plane)
                {
                    assert!(
                        sorted.stats.ranges_pruned * 5 > sorted.stats.ranges,
                        "{name}"
                    );
                    assert!(
                        sorted.stats.shadow_map_bytes_eq2
                            < sorted.stats.shadow_map_bytes_eq2_unpruned
                    );
                }
            }
            // The cover and coverage rules drop what the static rule drops, and more.
            assert!(by_rule[1] >= by_rule[0], "{name}, {what}: {by_rule:?}");
            assert!(by_rule[2] >= by_rule[0], "{name}, {what}: {by_rule:?}");
            if name == "random-cubes-16" {
                assert!(
                    by_rule[2] > by_rule[0] + 1000,
                    "{name}, {what}: the coverage rule drops {by_rule:?}"
                );
            }
        }
    }
    assert!(compared >= 2 * (BUILTIN_NAMES.len() - 1 + 32));
    println!("ranges pruned in all (static, cover, coverage rule): {pruned:?}");
    assert!(pruned[1] > 2 * pruned[0], "{pruned:?}");

    // The deferred frame: receivers moving through the map (on the stacked plates, through
    // texels whose deep lists the cover rule prunes).
    let deferred_scenes = ["cubes-toward-light", "leg-toward-light"]
        .map(|name| (name, builtin(name, &options).unwrap()))
        .into_iter()
        .chain(files.iter().map(|&name| {
            let path = examples.join(format!("{name}.json"));
            (name, load_scene_file(&path).unwrap())
        }));
    for (name, scene) in deferred_scenes {
        let mut lit = |storage| {
            motion_shadows_app::frame::render_deferred(
                Some(&mut renderer),
                &scene,
                &settings(storage),
                &DeferredSettings::default(),
                &mut |_| {},
            )
            .expect("deferred frame")
            .lit
        };
        let lists = lit(LISTS);
        assert!(
            lists.iter().any(|&l| l > 0.0 && l < 1.0),
            "{name}: partly lit pixels"
        );
        for storage in SORTED {
            assert!(
                lists == lit(storage),
                "{name}, {storage:?}: the deferred frame's lit shares differ"
            );
        }
    }
    assert_no_validation_messages(&ctx);
}

/// A map whose ranges lie in more tiles than one row of the sort's dispatch holds (128 tiles
/// across, `gpu_constants::SORT_TILE_ROW`; the sort visits the tiles the collection listed):
/// 300 cubes over a 512 x 512 map (4,096 tiles), the sorted ranges' image against the lists'.
/// A tile past the first row left unsorted would read the collection's list indices as
/// sorted places.
#[test]
fn ranges_in_more_tiles_than_a_row_are_all_sorted() {
    let ctx = context();
    let options = BuiltinOptions {
        cube_count: 300,
        ..BuiltinOptions::default()
    };
    let scene = builtin("cubes-toward-light", &options).unwrap();
    let mut renderer = Renderer::new(&ctx).expect("renderer");
    let mut render = |storage| {
        let settings = RenderSettings {
            shadow_size: Some((512, 512)),
            ..settings(storage)
        };
        motion_shadows_app::frame::render(Some(&mut renderer), &scene, &settings, &mut |_| {})
            .expect("render")
    };
    let lists = render(LISTS);
    let sorted = render(SORTED[0]);
    assert_eq!(lists.stats.ranges, sorted.stats.ranges, "the same frame");
    assert!(
        lists.image.rgb == sorted.image.rgb,
        "the sorted ranges' image differs from the lists'"
    );
    assert_no_validation_messages(&ctx);
}
