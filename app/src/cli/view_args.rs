//! `motion-shadows view`'s arguments (re-exported from [`super::args`], where the other
//! commands' are): a public interface, documented in docs/src/cli.md.

use super::args::{EstimatorArg, FilterArg, FrameArg, RandomCubesArgs};
use super::value_parsers::{parse_exposure, parse_size};
use clap::{Args, ValueEnum};
use std::path::PathBuf;

/// `view --method`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ViewMethodArg {
    Temporal,
    TemporalExact,
    Tsm,
    Plain,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum OnOff {
    On,
    Off,
}

/// Most frames a scripted `view` run presents.
pub const MAX_VIEW_FRAMES: u32 = 100_000;

#[derive(Debug, Args, Clone)]
pub struct ViewArgs {
    /// Built-in scene (`motion-shadows scene list`).
    #[arg(
        long,
        default_value = "cubes-toward-light",
        conflicts_with = "scene_file"
    )]
    pub scene: String,
    /// A scene file (JSON, see the scene format) instead of a built-in scene.
    #[arg(long)]
    pub scene_file: Option<PathBuf>,
    /// The window's width in pixels (at the start).
    #[arg(long, default_value_t = 640)]
    pub width: u32,
    /// The window's height in pixels (at the start).
    #[arg(long, default_value_t = 360)]
    pub height: u32,
    /// Shadow map size (default: the window's first size, as `render` takes the image's).
    #[arg(long, value_parser = parse_size)]
    pub shadow_size: Option<(u32, u32)>,
    /// The shutter time the G-buffer shows, in [0, 1] (engines draw at shutter close, 1).
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    pub camera_time: f32,
    /// Receivers stand still where the G-buffer shows them (default: they move as the
    /// G-buffer's motion says).
    #[arg(long)]
    pub static_receivers: bool,
    /// The method shown first (M cycles: temporal, temporal-exact, tsm, plain): the
    /// temporal map with the papers' depth lines or with the exact lookup, TSM-N
    /// (`--tsm-maps`), or one plain map at mid-shutter.
    #[arg(long, value_enum, default_value_t = ViewMethodArg::Temporal)]
    pub method: ViewMethodArg,
    /// The split view at the start: the left half shows `--method`'s deferred frame, the
    /// right half this method's (V cycles it, and turns it off); not with `--frame forward`.
    #[arg(long, value_enum)]
    pub split: Option<ViewMethodArg>,
    /// N of TSM-N (1 to 1024).
    #[arg(long, default_value_t = 8)]
    pub tsm_maps: u32,
    /// The frame shown first (F switches): `deferred` (the engine's frame) or `forward` (the
    /// papers' stochastic frame, as `render` draws it; the temporal methods only).
    #[arg(long, value_enum, default_value_t = FrameArg::Deferred)]
    pub frame: FrameArg,
    /// Samples per pixel of the stochastic frame (1 to 64).
    #[arg(long, default_value_t = 4)]
    pub spp: u32,
    /// The stochastic frame's shadow term (G switches): sampled (the papers') or analytic.
    #[arg(long, value_enum, default_value_t = EstimatorArg::Sampled)]
    pub shadow_estimator: EstimatorArg,
    /// The stochastic frame's shadow-map lookups (B cycles): none, bilinear or footprint
    /// (not with the exact lookup, which the viewer then reads unfiltered).
    #[arg(long, value_enum, default_value_t = FilterArg::None)]
    pub shadow_filter: FilterArg,
    /// The overlay (method, time, frame rate, per-pass GPU ms, map memory); O toggles it.
    #[arg(long, value_enum, default_value_t = OnOff::On)]
    pub overlay: OnOff,
    /// Exposure in stops: radiance times 2^EXPOSURE before the sRGB curve (as `render
    /// --exposure`).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = parse_exposure)]
    pub exposure: f32,
    /// Scripted run: present this many frames (1 to 100000), then close and print a summary
    /// with the frame rate.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=MAX_VIEW_FRAMES as i64))]
    pub frames: Option<u32>,
    /// Scripted run: write the last presented frame, exactly as presented, to this PNG.
    #[arg(long, requires = "frames")]
    pub screenshot: Option<PathBuf>,
    /// Scripted run: after the first frame, resize the window to WxH; the run ends only
    /// after frames presented at that size.
    #[arg(long, requires = "frames", value_parser = parse_size)]
    pub resize: Option<(u32, u32)>,
    /// Print the summary as one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub random: RandomCubesArgs,
}
