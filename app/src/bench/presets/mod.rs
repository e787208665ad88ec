//! The presets: what each sweeps, what it writes, which ratios it reports (one file each).

mod characters;
mod cubes;
mod engine;
mod engine_ghosting;
mod engine_verdict;
mod equal_quality;
mod frame;
mod game;
mod hard;
mod scaling;
mod shadow_pass;
mod spp;

use super::Scale;
use super::measure::{Measurement, measure};
use crate::chart::{LineChart, Series, Table, fmt_num, render};
use crate::error::{Error, Result};
use crate::output::{write_file_atomically, write_rgb8_png, write_through_temp};
use crate::render::{Method, RenderSettings, Renderer};
use crate::scene::{BuiltinOptions, Scene, builtin};
use serde::Serialize;
use std::path::PathBuf;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Preset {
    /// The default frame pass by pass: temporal, TSM and plain at 1, 8 and 16 spp.
    Frame,
    /// 2018 paper Figs. 11-12: time per step and memory, temporal vs TSM, as spp grows.
    Spp,
    /// 2017 paper Figs. 9-10: memory and time vs number of random cubes, with/without the
    /// coverage map.
    RandomCubes,
    /// 2017 paper Figs. 11-12: the same vs cube speed.
    Speed,
    /// The coverage map's saving vs cube size (the paper gives count and speeds, not size).
    CubeSize,
    /// Time each method needs to get within a given RMSE of a high-slice reference.
    EqualQuality,
    /// The temporal shadow pass against an ordinary depth-only shadow map of the same scene.
    ShadowPass,
    /// Frame time against triangle count.
    Scaling,
    /// Each hard scene (issue 11), every method's RMSE against a truth image.
    Hard,
    /// The animated character at its size and subdivided to the papers' (75k, 300k):
    /// temporal vs TSM time and memory.
    Characters,
    /// `game-level` (static level, a tenth of it moving) at 1080p: the temporal shadow pass
    /// against an ordinary map, the temporal frame against TSM's.
    Game,
    /// The engine's deferred frame: the temporal mask against engine TSM-N at equal quality,
    /// each against the exact truth (game-level, walker- and cubes-toward-light).
    Engine,
}

/// Every preset, in the order a run without `--preset` takes them (those of
/// [`Preset::by_default`]).
pub const PRESETS: &[Preset] = &[
    Preset::Frame,
    Preset::Spp,
    Preset::RandomCubes,
    Preset::Speed,
    Preset::CubeSize,
    Preset::EqualQuality,
    Preset::ShadowPass,
    Preset::Scaling,
    Preset::Characters,
    Preset::Game,
    Preset::Engine,
    Preset::Hard,
];

impl Preset {
    pub fn name(self) -> &'static str {
        match self {
            Preset::Frame => "frame",
            Preset::Spp => "spp",
            Preset::RandomCubes => "random-cubes",
            Preset::Speed => "speed",
            Preset::CubeSize => "cube-size",
            Preset::EqualQuality => "equal-quality",
            Preset::ShadowPass => "shadow-pass",
            Preset::Scaling => "scaling",
            Preset::Hard => "hard",
            Preset::Characters => "characters",
            Preset::Game => "game",
            Preset::Engine => "engine",
        }
    }

    /// Every file the preset writes into `--out` (`<preset>-results.csv`, ...): the one list
    /// that `bench` checks before it renders anything (a target it could not replace is
    /// refused up front) and that the preset's writers take their names from (writing a
    /// name not in it is an error), so the check and the files cannot drift apart.
    pub fn outputs(self) -> Vec<String> {
        let stems = match self {
            Preset::Frame => frame::outputs(),
            Preset::Spp => spp::outputs(),
            Preset::RandomCubes => cubes::outputs(cubes::Sweep::Count),
            Preset::Speed => cubes::outputs(cubes::Sweep::Speed),
            Preset::CubeSize => cubes::outputs(cubes::Sweep::Size),
            Preset::EqualQuality => equal_quality::outputs(),
            Preset::ShadowPass => shadow_pass::outputs(),
            Preset::Scaling => scaling::outputs(),
            Preset::Characters => characters::outputs(),
            Preset::Game => game::outputs(),
            Preset::Engine => engine::outputs(),
            Preset::Hard => hard::outputs(),
        };
        stems
            .into_iter()
            .map(|stem| format!("{}-{stem}", self.name()))
            .collect()
    }

    pub fn from_name(name: &str) -> Option<Self> {
        PRESETS.iter().copied().find(|p| p.name() == name)
    }

    /// Whether a run without `--preset` includes it. `hard` runs only when named: at its
    /// full size (the brute-force reference at 1,024 slices of 2048 x 2048 maps for each of
    /// nine scenes) it took 31 minutes on lavapipe.
    pub fn by_default(self) -> bool {
        self != Preset::Hard
    }
}

/// A key figure of a preset and, where the project set one, its target.
#[derive(Debug, Clone, Serialize)]
pub struct Ratio {
    pub name: String,
    pub value: f64,
    pub target: Option<String>,
    pub met: Option<bool>,
}

#[derive(Debug, Clone, Serialize)]
pub struct Report {
    pub preset: &'static str,
    /// The image sizes (width, height) the preset measured, in the order first rendered
    /// (many presets set their own, not the run's default; the depth-only maps' tiny frames,
    /// only their shadow pass read, are left out).
    pub image_sizes: Vec<[u32; 2]>,
    pub files: Vec<PathBuf>,
    pub ratios: Vec<Ratio>,
    /// Configurations that could not be measured, and why.
    pub notes: Vec<String>,
}

pub(super) const MIB: f64 = 1024.0 * 1024.0;
/// The file most presets write their table to, and the name of their usual chart.
pub(super) const RESULTS: &str = "results.csv";
pub(super) const TIME_CHART: &str = "time.png";
const CHART_SIZE: (u32, u32) = (800, 500);

pub(super) fn ratio(name: impl Into<String>, value: f64) -> Ratio {
    Ratio {
        name: name.into(),
        value,
        target: None,
        met: None,
    }
}

/// A ratio with a target: `at_most` (the value must not exceed it) or at least.
pub(super) fn target(name: impl Into<String>, value: f64, bound: f64, at_most: bool) -> Ratio {
    Ratio {
        name: name.into(),
        value,
        target: Some(format!(
            "{} {}",
            if at_most { "<=" } else { ">=" },
            fmt_num(bound)
        )),
        met: Some(if at_most {
            value <= bound
        } else {
            value >= bound
        }),
    }
}

pub(super) fn bench_error(e: impl std::fmt::Display) -> Error {
    Error::Bench(e.to_string())
}

pub(super) struct Bench<'a, 'r> {
    renderer: &'a mut Renderer<'r>,
    scale: &'a Scale,
    progress: &'a mut dyn FnMut(&str),
    report: Report,
    /// The files the preset may write ([`Preset::outputs`]).
    declared: Vec<String>,
}

impl Bench<'_, '_> {
    pub(super) fn settings(&self, method: Method, spp: u32) -> RenderSettings {
        RenderSettings {
            width: self.scale.width,
            height: self.scale.height,
            spp,
            seed: 1,
            method,
            shadow_estimator: self.scale.shadow_estimator,
            prisms: self.scale.prisms,
            receiver: self.scale.receiver,
            shadow_filter: self.scale.shadow_filter_for(&method),
            ..RenderSettings::default()
        }
    }

    fn measure(
        &mut self,
        what: &str,
        scene: &Scene,
        settings: &RenderSettings,
    ) -> Option<Measurement> {
        self.measure_runs(what, scene, settings, self.scale.runs)
    }

    /// One render, for presets that measure images rather than time (its time includes any
    /// first-use cost).
    fn measure_once(
        &mut self,
        what: &str,
        scene: &Scene,
        settings: &RenderSettings,
    ) -> Option<Measurement> {
        self.measure_runs(what, scene, settings, 1)
    }

    fn measure_runs(
        &mut self,
        what: &str,
        scene: &Scene,
        settings: &RenderSettings,
        runs: u32,
    ) -> Option<Measurement> {
        self.record_size(settings.width, settings.height);
        self.measure_unrecorded(what, scene, settings, runs)
    }

    /// Records that the preset renders `width` x `height` images (its report's
    /// `image_sizes`).
    pub(super) fn record_size(&mut self, width: u32, height: u32) {
        let size = [width, height];
        if !self.report.image_sizes.contains(&size) {
            self.report.image_sizes.push(size);
        }
    }

    /// [`Self::measure_runs`] of a frame whose image is not the preset's (not recorded).
    fn measure_unrecorded(
        &mut self,
        what: &str,
        scene: &Scene,
        settings: &RenderSettings,
        runs: u32,
    ) -> Option<Measurement> {
        (self.progress)(&format!("bench {}: {what}", self.report.preset));
        match measure(self.renderer, scene, settings, runs) {
            Ok(m) => Some(m),
            Err(e) => {
                self.report.notes.push(format!("{what}: {e}"));
                None
            }
        }
    }

    /// The floor any shadow pass is measured against: one depth-only shadow map of `scene` at
    /// `shadow_size` (TSM with one map: a D32 attachment, LESS test, no fragment shader),
    /// GPU ms, fastest of the runs. The frame around it is 1 spp of a small image: only its
    /// shadow pass is read.
    pub(super) fn depth_only_map_ms(
        &mut self,
        scene: &Scene,
        shadow_size: (u32, u32),
    ) -> Option<f64> {
        let settings = RenderSettings {
            width: 64,
            height: 48,
            shadow_size: Some(shadow_size),
            ..self.settings(Method::Tsm, 1)
        };
        let what = format!("{}, one depth-only map", scene.name);
        let runs = self.scale.runs;
        self.measure_unrecorded(&what, scene, &settings, runs)
            .map(|m| m.shadow_ms())
    }

    /// Where the preset's file `stem` (`results.csv`) goes: `--out/<preset>-<stem>`, which
    /// must be one of the files the preset declares ([`Preset::outputs`]), the list `bench`
    /// checks before it renders anything.
    fn output_path(&self, stem: &str) -> Result<PathBuf> {
        let name = format!("{}-{stem}", self.report.preset);
        if !self.declared.contains(&name) {
            return Err(bench_error(format!(
                "internal error: the preset {} writes {name}, which is not among the files \
                 it declares (Preset::outputs), so it was not checked before the run",
                self.report.preset
            )));
        }
        Ok(self.scale.out.join(name))
    }

    /// Writes `table` as the preset's file `stem` (a declared `.csv`).
    pub(super) fn write_table(&mut self, stem: &str, table: &Table) -> Result<()> {
        let path = self.output_path(stem)?;
        // Through a temporary file, as every output: never over a device, FIFO or link.
        write_file_atomically(&path, table.to_csv().as_bytes()).map_err(bench_error)?;
        self.report.files.push(path);
        Ok(())
    }

    /// Draws `chart` as the preset's file `stem` (a declared `.png`).
    pub(super) fn write_chart(&mut self, stem: &str, chart: &LineChart) -> Result<()> {
        let image = render(chart, CHART_SIZE.0, CHART_SIZE.1).map_err(bench_error)?;
        self.write_picture(stem, image.width, image.height, &image.data)
    }

    /// Writes an RGB8 picture as the preset's file `stem` (a declared `.png`) through a
    /// temporary file, as every output is: never over a device, FIFO or link, and a failure
    /// leaves an older file as it was.
    pub(super) fn write_picture(
        &mut self,
        stem: &str,
        width: u32,
        height: u32,
        data: &[u8],
    ) -> Result<()> {
        let path = self.output_path(stem)?;
        write_through_temp(&path, |temp| write_rgb8_png(temp, width, height, data))
            .map_err(bench_error)?;
        self.report.files.push(path);
        Ok(())
    }
}

pub(super) fn chart(title: &str, x: &str, y: &str, series: Vec<Series>) -> LineChart {
    LineChart {
        title: title.into(),
        x_label: x.into(),
        y_label: y.into(),
        series,
        log_x: false,
        log_y: false,
    }
}

pub(super) fn series(label: &str, points: Vec<(f64, f64)>) -> Series {
    Series {
        label: label.into(),
        points,
    }
}

pub(super) fn builtin_scene(name: &str, options: &BuiltinOptions) -> Result<Scene> {
    Ok(builtin(name, options)?)
}

/// Runs one preset; its files go to `scale.out`.
pub fn run_preset(
    renderer: &mut Renderer<'_>,
    preset: Preset,
    scale: &Scale,
    progress: &mut dyn FnMut(&str),
) -> Result<Report> {
    std::fs::create_dir_all(&scale.out)
        .map_err(|e| bench_error(format!("cannot create {}: {e}", scale.out.display())))?;
    let mut bench = Bench {
        renderer,
        scale,
        progress,
        report: Report {
            preset: preset.name(),
            image_sizes: Vec::new(),
            files: Vec::new(),
            ratios: Vec::new(),
            notes: Vec::new(),
        },
        declared: preset.outputs(),
    };
    match preset {
        Preset::Frame => frame::frame(&mut bench)?,
        Preset::Spp => spp::spp(&mut bench)?,
        Preset::RandomCubes => cubes::random_cubes(&mut bench, cubes::Sweep::Count)?,
        Preset::Speed => cubes::random_cubes(&mut bench, cubes::Sweep::Speed)?,
        Preset::CubeSize => cubes::random_cubes(&mut bench, cubes::Sweep::Size)?,
        Preset::EqualQuality => equal_quality::equal_quality(&mut bench)?,
        Preset::ShadowPass => shadow_pass::shadow_pass(&mut bench)?,
        Preset::Scaling => scaling::scaling(&mut bench)?,
        Preset::Characters => characters::characters(&mut bench)?,
        Preset::Game => game::game(&mut bench)?,
        Preset::Engine => engine::engine(&mut bench)?,
        Preset::Hard => hard::hard(&mut bench)?,
    }
    Ok(bench.report)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The declared files are what `bench` checks before it runs: each must be a plain name
    /// under its preset's prefix, and no two presets (or the summary) may share one, or one
    /// preset's run would overwrite another's results.
    #[test]
    fn every_presets_files_are_plain_distinct_and_carry_its_name() {
        let mut all = vec!["bench-summary.json".to_owned()];
        for &preset in PRESETS {
            let files = preset.outputs();
            assert!(files.contains(&format!("{}-{RESULTS}", preset.name())));
            for file in files {
                assert!(file.starts_with(&format!("{}-", preset.name())), "{file}");
                assert!(
                    !file.contains('/') && (file.ends_with(".csv") || file.ends_with(".png")),
                    "{file}"
                );
                assert!(!all.contains(&file), "{file} declared twice");
                all.push(file);
            }
        }
    }
}
