//! The temporal shadow pass against the ordinary shadow maps of the same scene, drawn as
//! anyone would draw them (a D32 attachment, LESS test): one depth-only map (the floor any
//! shadow pass is measured against) and the plain map (depth and triangle id).

use super::{
    Bench, Measurement, RESULTS, TIME_CHART, bench_error, builtin_scene, chart, ratio, series,
    target,
};
use crate::chart::{LineChart, Table, fmt_num};
use crate::error::Result;
use crate::render::{Method, RenderSettings};
use crate::scene::BuiltinOptions;

/// The files it writes (see `Preset::outputs`).
pub(super) fn outputs() -> Vec<String> {
    [RESULTS, TIME_CHART].map(String::from).to_vec()
}

/// The scenes and each one's target for temporal shadow pass / one depth-only map.
const TARGETS: [(&str, f64); 3] = [
    ("cubes-toward-light", 10.0),
    ("random-cubes", 10.0),
    ("game-level", 3.0),
];

pub(super) fn shadow_pass(b: &mut Bench) -> Result<()> {
    let mut table = Table::new(
        [
            "scene",
            "triangles",
            "temporal_shadow_ms",
            "collection_ms",
            "generation_ms",
            "temporal_lists_shadow_ms",
            "temporal_kept_shadow_ms",
            "depth_only_map_ms",
            "plain_map_ms",
            "ratio",
        ]
        .map(String::from)
        .to_vec(),
    );
    let cubes = b.scale.pick(1000, 4000);
    let mut bars = Vec::new();
    for (name, bound) in TARGETS {
        let options = BuiltinOptions {
            cube_count: cubes,
            ..BuiltinOptions::default()
        };
        let scene = builtin_scene(name, &options)?;
        let layered = b.settings(Method::Temporal, 1);
        let in_lists = RenderSettings {
            static_layer: false,
            ..layered.clone()
        };
        let kept_layer = RenderSettings {
            keep_static_layer: true,
            ..layered.clone()
        };
        let plain = b.settings(Method::Plain { time: 0.5 }, 1);
        let temporal = b.measure(&format!("{name} temporal"), &scene, &layered);
        let lists = b.measure(
            &format!("{name} temporal, static triangles in the lists"),
            &scene,
            &in_lists,
        );
        let kept = b.measure(
            &format!("{name} temporal, static layer kept from the frame before"),
            &scene,
            &kept_layer,
        );
        let plain = b.measure(&format!("{name} plain"), &scene, &plain);
        let floor = b.depth_only_map_ms(&scene, layered.shadow_size());
        let (Some(t), Some(floor)) = (temporal, floor) else {
            continue;
        };
        let shadow = t.shadow_ms();
        let ms =
            |m: &Option<Measurement>| m.as_ref().map_or(String::new(), |m| fmt_num(m.shadow_ms()));
        table
            .push(vec![
                name.to_owned(),
                scene.triangle_count().to_string(),
                fmt_num(shadow),
                fmt_num(t.gpu_ms_where(|n| n == "collection")),
                fmt_num(t.gpu_ms_where(|n| n == "generation")),
                ms(&lists),
                ms(&kept),
                fmt_num(floor),
                ms(&plain),
                fmt_num(shadow / floor),
            ])
            .map_err(bench_error)?;
        bars.push((
            shadow,
            kept.as_ref().map_or(f64::NAN, |k| k.shadow_ms()),
            floor,
        ));
        b.report.ratios.push(target(
            format!("{name}: shadow pass / one depth-only shadow map"),
            shadow / floor,
            bound,
            true,
        ));
        if let Some(k) = &kept {
            b.report.ratios.push(target(
                format!(
                    "{name}: shadow pass with the static layer kept from the frame before / one depth-only shadow map"
                ),
                k.shadow_ms() / floor,
                bound,
                true,
            ));
        }
        if let Some(l) = &lists {
            b.report.ratios.push(ratio(
                format!(
                    "{name}: shadow pass with static triangles in the lists / with the static layer"
                ),
                l.shadow_ms() / shadow,
            ));
        }
    }
    b.write_table(RESULTS, &table)?;
    let points = |f: &dyn Fn(&(f64, f64, f64)) -> f64| {
        bars.iter()
            .enumerate()
            .map(|(i, v)| (i as f64 + 1.0, f(v)))
            .filter(|(_, ms)| ms.is_finite())
            .collect()
    };
    // A log axis: the depth-only map is a hundredth of the temporal pass on some scenes.
    b.write_chart(
        TIME_CHART,
        &LineChart {
            log_y: true,
            ..chart(
                "Shadow pass (1 cubes, 2 random cubes, 3 game-level)",
                "scene",
                "GPU ms",
                vec![
                    series("temporal", points(&|v| v.0)),
                    series("temporal, layer kept", points(&|v| v.1)),
                    series("depth-only map", points(&|v| v.2)),
                ],
            )
        },
    )?;
    b.report.notes.push(
        "the ordinary maps are drawn into a D32 depth attachment with the LESS test (depth-only: no fragment shader; plain: the id in an R32_UINT attachment); the copy of the attachments into the lookups' buffers is not counted".into(),
    );
    Ok(())
}
