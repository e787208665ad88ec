//! `bench --preset hard`: every hard scene of issue 11 (`hard-*`, see `scene::HARD_NAMES`)
//! rendered by each shadow method and measured against a truth image, with the images side
//! by side. The truth is chosen in one place, [`truth`]; the preset's sizes are
//! [`HardParams`].

use super::{Bench, RESULTS, bench_error, builtin_scene, chart, ratio, series, target};
use crate::chart::{Table, fmt_num};
use crate::compare::{Rgb8Image, rmse, side_by_side};
use crate::error::Result;
use crate::output::{RadianceImage, auto_exposure};
use crate::render::upload::check_moving_light_forward;
use crate::render::{Method, RenderSettings};
use crate::scene::{BuiltinOptions, HARD_NAMES};
use motion_shadows::technique::{Lookup, PrismConstruction, ShadowFilter};

/// What the methods are measured against.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Truth {
    /// The brute-force reference at `slices` times. It shares the shadow maps' resolution,
    /// receiver offset and near plane with the methods, so errors common to all shadow-map
    /// methods are invisible to it.
    #[allow(dead_code)]
    Reference { slices: u32 },
    /// The CPU ray tracer (`--method raytrace`): the same samples, no shadow map; exact.
    Raytrace,
}

impl Truth {
    fn method(self) -> Method {
        match self {
            Truth::Reference { slices } => Method::Reference { slices },
            Truth::Raytrace => Method::Raytrace,
        }
    }

    fn label(self) -> String {
        match self {
            Truth::Reference { slices } => format!("reference ({slices} slices)"),
            Truth::Raytrace => "raytrace".to_owned(),
        }
    }

    /// The label of its panel in the side-by-side images (short: the panels are narrow).
    fn panel_label(self) -> String {
        match self {
            Truth::Reference { slices } => format!("truth ref M={slices}"),
            Truth::Raytrace => "truth raytrace".to_owned(),
        }
    }

    /// Whether the truth is exact (independent of shadow maps); only then are the issue's
    /// targets (temporal RMSE <= 0.005, and <= the brute-force reference's) checked.
    fn exact(self) -> bool {
        match self {
            Truth::Reference { .. } => false,
            Truth::Raytrace => true,
        }
    }
}

/// The truth of the preset: the exact ray tracer (`Truth::Reference` measures against the
/// brute-force reference instead).
fn truth() -> Truth {
    Truth::Raytrace
}

/// The preset's sizes.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct HardParams {
    pub width: u32,
    pub height: u32,
    pub shadow_size: (u32, u32),
    /// Samples per pixel of every method but the brute-force reference (and of the truth
    /// where it takes samples), all at the same positions and times (seed 1).
    pub spp: u32,
    /// Time slices of the brute-force reference, measured or truth.
    pub reference_slices: u32,
    pub truth: Truth,
}

impl HardParams {
    /// The measurement: 256 x 192, 2048 x 2048 shadow maps, 64 spp, the reference at
    /// 1,024 slices.
    pub fn full() -> Self {
        Self::new((256, 192), (2048, 2048), 64, 1024)
    }

    /// A first look and the test: 64 x 48, 256 x 256 shadow maps, 4 spp, 32 slices.
    pub fn quick() -> Self {
        Self::new((64, 48), (256, 256), 4, 32)
    }

    fn new(image: (u32, u32), shadow_size: (u32, u32), spp: u32, reference_slices: u32) -> Self {
        Self {
            width: image.0,
            height: image.1,
            shadow_size,
            spp,
            reference_slices,
            truth: truth(),
        }
    }

    fn settings(&self, method: Method, b: &Bench) -> RenderSettings {
        self.row_settings(Row::of(method), b)
    }

    fn row_settings(&self, row: Row, b: &Bench) -> RenderSettings {
        let method = row.method;
        RenderSettings {
            lookup: row.lookup,
            // The exact lookup tests each sample's ray: it has no texels to filter (its row is
            // unfiltered whatever `--shadow-filter` says; the notes say so).
            shadow_filter: match row.lookup {
                Lookup::Exact => ShadowFilter::None,
                Lookup::DepthLine => b.scale.shadow_filter_for(&method),
            },
            prisms: row.prisms,
            width: self.width,
            height: self.height,
            spp: self.spp,
            seed: 1,
            shadow_size: Some(self.shadow_size),
            method,
            shadow_estimator: b.scale.shadow_estimator,
            receiver: b.scale.receiver,
            ..RenderSettings::default()
        }
    }

    /// The rows measured: every method except the truth's own, and the temporal method with
    /// the papers' prisms and with the exact lookup too.
    fn methods(&self) -> Vec<Row> {
        [
            Row::of(Method::Temporal),
            Row {
                prisms: PrismConstruction::Paper,
                ..Row::of(Method::Temporal)
            },
            Row {
                lookup: Lookup::Exact,
                ..Row::of(Method::Temporal)
            },
            Row::of(Method::Coverage),
            Row::of(Method::Tsm),
            Row::of(Method::Plain { time: 0.5 }),
            Row::of(Method::Reference {
                slices: self.reference_slices,
            }),
        ]
        .into_iter()
        .filter(|r| r.method != self.truth.method())
        .collect()
    }
}

/// One row of the table: a method, and for the temporal one its prism construction and its
/// lookup.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Row {
    method: Method,
    prisms: PrismConstruction,
    lookup: Lookup,
}

impl Row {
    fn of(method: Method) -> Self {
        Self {
            method,
            prisms: PrismConstruction::Exact,
            lookup: Lookup::DepthLine,
        }
    }

    fn name(&self) -> String {
        match (self.method, self.prisms, self.lookup) {
            (Method::Temporal, PrismConstruction::Paper, _) => "temporal-paper-prisms".to_owned(),
            (Method::Temporal, _, Lookup::Exact) => "temporal-exact".to_owned(),
            (m, _, _) => m.name().to_owned(),
        }
    }
}

/// Issue 35's target for the exact lookup against an exact truth (the same samples).
const EXACT_LOOKUP_RMSE: f64 = 0.0005;

/// A pixel is in the moving-object mask when more than half of the truth's samples see a
/// moving triangle (as `compare` does).
const MASK_COVERAGE: f32 = 0.5;

const RMSE_CHART: &str = "rmse.png";

/// The files it writes (see `Preset::outputs`): the table, the chart and each scene's
/// panels (`hard-<rest of the scene's name>.png`, the preset's name standing for its
/// `hard-`).
pub(super) fn outputs() -> Vec<String> {
    let pictures = HARD_NAMES.iter().map(|name| scene_picture(name));
    [RESULTS, RMSE_CHART]
        .map(String::from)
        .into_iter()
        .chain(pictures)
        .collect()
}

fn scene_picture(scene: &str) -> String {
    format!("{}.png", scene.strip_prefix("hard-").unwrap_or(scene))
}

pub(super) fn hard(b: &mut Bench) -> Result<()> {
    let params = b.scale.pick(HardParams::quick(), HardParams::full());
    hard_with(b, &params)
}

pub(super) fn hard_with(b: &mut Bench, params: &HardParams) -> Result<()> {
    let methods = params.methods();
    let mut table = Table::new(
        [
            "scene",
            "method",
            "rmse",
            "rmse_moving",
            "rmse_static",
            "frame_ms",
        ]
        .map(String::from)
        .to_vec(),
    );
    // Per method, (scene index, RMSE).
    let mut curves: Vec<Vec<(f64, f64)>> = vec![Vec::new(); methods.len()];
    for (index, &name) in HARD_NAMES.iter().enumerate() {
        let scene = builtin_scene(name, &BuiltinOptions::default())?;
        let truth_settings = params.settings(params.truth.method(), b);
        let Some(truth) = b.measure_once(
            &format!("{name}: truth, {}", params.truth.label()),
            &scene,
            &truth_settings,
        ) else {
            continue;
        };
        let moving: Vec<bool> = truth
            .moving_coverage
            .iter()
            .map(|&c| c > MASK_COVERAGE)
            .collect();
        let still: Vec<bool> = moving.iter().map(|&m| !m).collect();
        let exposure = auto_exposure(&truth.image);
        let mut panels = Vec::new();
        let mut errors = Vec::new();
        for (k, &row) in methods.iter().enumerate() {
            let settings = params.row_settings(row, b);
            // A method that does not take the scene's moving light (hard-turning-light): said
            // in the notes, no row (the other scenes' rows are as before).
            if let Err(e) = check_moving_light_forward(&scene, &settings) {
                b.report.notes.push(format!(
                    "{name}: {} not measured, it does not take the scene's turning light: {e}",
                    row.name()
                ));
                continue;
            }
            let Some(m) = b.measure_once(&format!("{name}: {}", row.name()), &scene, &settings)
            else {
                continue;
            };
            let e = rmse(&m.image, &truth.image, None).map_err(bench_error)?;
            let cell = |v: Option<f64>| v.map_or_else(String::new, fmt_num);
            table
                .push(vec![
                    name.to_string(),
                    row.name(),
                    fmt_num(e),
                    cell(masked_rmse(&m.image, &truth.image, &moving)?),
                    cell(masked_rmse(&m.image, &truth.image, &still)?),
                    fmt_num(m.frame_ms()),
                ])
                .map_err(bench_error)?;
            curves[k].push(((index + 1) as f64, e));
            errors.push((row, e));
            panels.push((
                format!("{} {e:.4}", row.name()),
                Rgb8Image::from_radiance(&m.image, exposure).map_err(bench_error)?,
            ));
        }
        panels.push((
            params.truth.panel_label(),
            Rgb8Image::from_radiance(&truth.image, exposure).map_err(bench_error)?,
        ));
        let refs: Vec<(&str, &Rgb8Image)> = panels.iter().map(|(l, i)| (l.as_str(), i)).collect();
        let side = side_by_side(&refs, [24, 24, 24]);
        b.write_picture(&scene_picture(name), side.width, side.height, &side.data)?;
        push_ratios(b, params, name, &errors);
    }
    b.write_table(RESULTS, &table)?;
    let last = HARD_NAMES.len();
    let x_label = format!(
        "scene (1 = {}, ..., {last} = {})",
        HARD_NAMES[0],
        HARD_NAMES[last - 1]
    );
    let lines = methods
        .iter()
        .zip(curves)
        .map(|(m, points)| series(&m.name(), points))
        .collect();
    let title = format!("RMSE against the truth, {}", params.truth.label());
    b.write_chart(RMSE_CHART, &chart(&title, &x_label, "RMSE", lines))?;
    b.report.notes.push(format!(
        "{}x{}, shadow maps {}x{}, {} spp, seed 1; temporal-exact: the temporal map read with \
         the exact lookup (unfiltered: it has no texels); truth: {}{}",
        params.width,
        params.height,
        params.shadow_size.0,
        params.shadow_size.1,
        params.spp,
        params.truth.label(),
        if params.truth.exact() {
            ""
        } else {
            " (not exact: it shares the shadow maps' errors, so no targets are checked)"
        }
    ));
    Ok(())
}

/// RMSE over the pixels of `mask`; `None` when it selects none.
fn masked_rmse(image: &RadianceImage, truth: &RadianceImage, mask: &[bool]) -> Result<Option<f64>> {
    if mask.contains(&true) {
        Ok(Some(rmse(image, truth, Some(mask)).map_err(bench_error)?))
    } else {
        Ok(None)
    }
}

/// The temporal method's RMSE per scene; against an exact truth, with the targets
/// (at most 0.005, and at most the brute-force reference's error).
fn push_ratios(b: &mut Bench, params: &HardParams, scene: &str, errors: &[(Row, f64)]) {
    let of = |name: &str| {
        errors
            .iter()
            .find(|(m, _)| m.name() == name)
            .map(|&(_, e)| e)
    };
    if let (Some(exact), true) = (of("temporal-exact"), params.truth.exact()) {
        b.report.ratios.push(target(
            format!("{scene}: temporal-exact RMSE"),
            exact,
            EXACT_LOOKUP_RMSE,
            true,
        ));
    }
    let Some(temporal) = of("temporal") else {
        return;
    };
    let what = format!("{scene}: temporal RMSE");
    if !params.truth.exact() {
        b.report.ratios.push(ratio(what, temporal));
        return;
    }
    b.report.ratios.push(target(what, temporal, 0.005, true));
    if let Some(reference) = of("reference") {
        b.report.ratios.push(target(
            format!("{scene}: temporal / reference RMSE"),
            temporal / reference.max(f64::MIN_POSITIVE),
            1.0,
            true,
        ));
    }
}
