//! The temporal shadow pass against an ordinary shadow map of the same scene.

use super::{Bench, bench_error, builtin_scene, chart, series, target};
use crate::chart::{Table, fmt_num};
use crate::error::Result;
use crate::render::Method;
use crate::scene::BuiltinOptions;

pub(super) fn shadow_pass(b: &mut Bench) -> Result<()> {
    let mut table = Table::new(
        [
            "scene",
            "temporal_shadow_ms",
            "collection_ms",
            "generation_ms",
            "plain_depth_map_ms",
            "ratio",
        ]
        .map(String::from)
        .to_vec(),
    );
    let cubes = b.scale.pick(1000, 4000);
    let scenes = [
        builtin_scene("cubes-toward-light", &BuiltinOptions::default())?,
        builtin_scene(
            "random-cubes",
            &BuiltinOptions {
                cube_count: cubes,
                ..BuiltinOptions::default()
            },
        )?,
    ];
    let mut bars = Vec::new();
    for scene in &scenes {
        let temporal = b.measure(
            &format!("{} temporal", scene.name),
            scene,
            &b.settings(Method::Temporal, 1),
        );
        let plain = b.measure(
            &format!("{} plain", scene.name),
            scene,
            &b.settings(Method::Plain { time: 0.5 }, 1),
        );
        let (Some(t), Some(p)) = (temporal, plain) else {
            continue;
        };
        let (shadow, floor) = (t.shadow_ms(), p.shadow_ms());
        table
            .push(vec![
                scene.name.clone(),
                fmt_num(shadow),
                fmt_num(t.gpu_ms_where(|n| n == "collection")),
                fmt_num(t.gpu_ms_where(|n| n == "generation")),
                fmt_num(floor),
                fmt_num(shadow / floor),
            ])
            .map_err(bench_error)?;
        bars.push((scene.name.clone(), shadow, floor));
        b.report.ratios.push(target(
            format!("{}: shadow pass / plain shadow map", scene.name),
            shadow / floor,
            3.0,
            true,
        ));
    }
    b.write_table("results", &table)?;
    let points = |f: &dyn Fn(&(String, f64, f64)) -> f64| {
        bars.iter()
            .enumerate()
            .map(|(i, v)| (i as f64 + 1.0, f(v)))
            .collect()
    };
    b.write_chart(
        "time",
        &chart(
            "Shadow pass vs an ordinary shadow map (1 = cubes-toward-light, 2 = random cubes)",
            "scene",
            "GPU ms",
            vec![
                series("temporal: collection + generation", points(&|v| v.1)),
                series("plain shadow map", points(&|v| v.2)),
            ],
        ),
    )?;
    b.report.notes.push(
        "the plain shadow map is this project's ordinary map (nearest depth and id per texel by 64-bit atomics, no depth attachment)".into(),
    );
    Ok(())
}
