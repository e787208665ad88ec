//! The command line: a public interface (documented in the README), change it only on purpose.

use clap::parser::ValueSource;
use clap::{ArgMatches, Args, CommandFactory, FromArgMatches, Parser, Subcommand, ValueEnum};
use std::ffi::OsString;
use std::path::PathBuf;

// Re-exported: `args::` names every command's arguments and their value parsers.
pub use super::technique_args::{
    EstimatorArg, FilterArg, LookupArg, MethodArg, PrismsArg, PruningArg, RangeStorageArg,
    ReceiverArg, StaticLayerArg, TruthArg,
};
pub use super::value_parsers::{MAX_EXPOSURE_STOPS, parse_exposure, parse_size};
pub use super::view_args::{MAX_VIEW_FRAMES, OnOff, ViewArgs, ViewMethodArg};

#[derive(Debug, Parser)]
#[command(
    name = "motion-shadows",
    version,
    about = "Motion-blurred shadows with the temporal (depth-time ranges) shadow map of Hong & Oh",
    long_about = "Motion-blurred shadows with the temporal (depth-time ranges) shadow map of \
                  Hong & Oh, on Vulkan. Without a subcommand, renders the default scene \
                  (cubes-toward-light) at 1024x768, 8 spp."
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
}

impl Cli {
    /// [`Parser::parse`], recording in `render`'s, `animate`'s and `compare`'s `given` the
    /// options typed on the command line (so that those a frame does not read are refused,
    /// `unread_options.rs`, even when their value is the default).
    pub fn parse_recording_given() -> Self {
        Self::try_parse_recording_given(std::env::args_os()).unwrap_or_else(|e| e.exit())
    }

    /// [`Self::parse_recording_given`] of `args` (the first is the program's name).
    pub fn try_parse_recording_given<I, T>(args: I) -> Result<Self, clap::Error>
    where
        I: IntoIterator<Item = T>,
        T: Into<OsString> + Clone,
    {
        let mut command = <Self as CommandFactory>::command();
        let matches = command.try_get_matches_from_mut(args)?;
        let mut cli = <Self as FromArgMatches>::from_arg_matches(&matches)?;
        if let Some((name, sub)) = matches.subcommand() {
            let given = command
                .find_subcommand(name)
                .map_or_else(Vec::new, |c| typed_options(c, sub));
            match &mut cli.command {
                Some(Command::Render(args)) => args.given = given,
                Some(Command::Animate(args)) => args.render.given = given,
                Some(Command::Compare(args)) => args.given = given,
                _ => {}
            }
        }
        Ok(cli)
    }
}

/// The long names (`--spp`) of the options of `command` that `matches` took from the
/// command line, not from their defaults.
fn typed_options(command: &clap::Command, matches: &ArgMatches) -> Vec<String> {
    matches
        .ids()
        .filter(|id| matches.value_source(id.as_str()) == Some(ValueSource::CommandLine))
        .filter_map(|id| {
            command
                .get_arguments()
                .find(|arg| arg.get_id() == id)
                .and_then(|arg| arg.get_long())
                .map(|long| format!("--{long}"))
        })
        .collect()
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render a scene, write `DIR/<scene>-<method>.png` and `.exr`, print a summary.
    Render(RenderArgs),
    /// Built-in scenes: list them, or export one as a scene file.
    #[command(subcommand)]
    Scene(SceneCommand),
    /// Measure like the papers: per-pass GPU time and memory sweeps, written as CSV and PNG
    /// charts, with the key ratios printed.
    Bench(BenchArgs),
    /// Render consecutive frames of an animated scene: `DIR/<scene>-frame-NNNN.png` and an
    /// animated `DIR/<scene>.gif`.
    Animate(AnimateArgs),
    /// Render reference, temporal and TSM images of one scene; write a side-by-side PNG,
    /// false-colour error images, and a table of errors, times and memory.
    Compare(CompareArgs),
    /// Show the deferred frame (the temporal shadow map's mask, receivers moving) in a
    /// window (X11), as an engine's frame loop runs it; `--frames N --screenshot PATH` runs
    /// it scripted.
    View(ViewArgs),
}

#[derive(Debug, Args, Clone)]
pub struct BenchArgs {
    /// Every preset at reduced resolution and sweep sizes (CI, a first look).
    #[arg(long)]
    pub quick: bool,
    /// Presets to run (default: all but hard): spp, random-cubes, speed, cube-size,
    /// equal-quality, shadow-pass, scaling, characters, game, engine, hard.
    #[arg(long = "preset")]
    pub presets: Vec<String>,
    /// Shadow term of the presets' temporal and coverage renders (equal-quality sweeps both).
    #[arg(long, value_enum, default_value_t = EstimatorArg::Sampled)]
    pub shadow_estimator: EstimatorArg,
    /// Prism construction of the presets' temporal and coverage renders.
    #[arg(long, value_enum, default_value_t = PrismsArg::Exact)]
    pub prisms: PrismsArg,
    /// Receiver test of the presets' renders (see `render --receiver`).
    #[arg(long, value_enum, default_value_t = ReceiverArg::Auto)]
    pub receiver: ReceiverArg,
    /// Shadow-map lookups: `none` (the receiver's texel), `bilinear` (2x2 texels weighted
    /// by overlap, PCF) or `footprint` (bilinear over the pixel's footprint); each texel
    /// integrated over the shutter with the analytic estimator.
    #[arg(long, value_enum, default_value_t = FilterArg::None)]
    pub shadow_filter: FilterArg,
    #[arg(long, default_value = "bench")]
    pub out: PathBuf,
    /// Print the results as one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
}

/// The papers' image experiments.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Preset {
    /// 2018 paper, Fig. 9: cubes-toward-light at 8 spp.
    Fig9,
    /// 2018 paper, Fig. 10: a character's leg moving toward the light (walker-toward-light,
    /// the animated CesiumMan) at 20 spp.
    Fig10,
}

#[derive(Debug, Args, Clone)]
pub struct CompareArgs {
    /// A paper experiment: sets the scene and spp (explicit --scene/--spp override it; the
    /// deferred frame takes its scene, having no spp).
    #[arg(long, value_enum)]
    pub preset: Option<Preset>,
    /// Built-in scene (default: cubes-toward-light, or the preset's).
    #[arg(long, conflicts_with = "scene_file")]
    pub scene: Option<String>,
    #[arg(long)]
    pub scene_file: Option<PathBuf>,
    #[arg(long, default_value_t = 1024)]
    pub width: u32,
    #[arg(long, default_value_t = 768)]
    pub height: u32,
    /// Samples per pixel of temporal and TSM (default 8, or the preset's).
    #[arg(long)]
    pub spp: Option<u32>,
    #[arg(long, default_value_t = 1)]
    pub seed: u32,
    #[arg(long, value_parser = parse_size)]
    pub shadow_size: Option<(u32, u32)>,
    /// Time slices of the brute-force reference (the papers use 3000).
    #[arg(long, default_value_t = 1024)]
    pub slices: u32,
    /// Shadow term of the temporal method: sampled (the papers') or analytic.
    #[arg(long, value_enum, default_value_t = EstimatorArg::Sampled)]
    pub shadow_estimator: EstimatorArg,
    /// Prism construction of the temporal method: exact or the papers'.
    #[arg(long, value_enum, default_value_t = PrismsArg::Exact)]
    pub prisms: PrismsArg,
    /// Receiver test of every map lookup: `plane` (the receiver's plane's depth at the
    /// shadow texel's centre, no normal offset: keeps contact shadows at grazing light),
    /// `offset` (one shadow texel along the normal, the papers'), or `auto` (plane where the
    /// maps hold triangle ids, offset for TSM).
    #[arg(long, value_enum, default_value_t = ReceiverArg::Auto)]
    pub receiver: ReceiverArg,
    /// Shadow-map lookups: `none` (the receiver's texel), `bilinear` (2x2 texels weighted
    /// by overlap, PCF) or `footprint` (bilinear over the pixel's footprint); each texel
    /// integrated over the shutter with the analytic estimator.
    #[arg(long, value_enum, default_value_t = FilterArg::None)]
    pub shadow_filter: FilterArg,
    /// The same as `--receiver plane` (kept for scripts written before `--receiver`).
    #[arg(long, conflicts_with = "receiver")]
    pub receiver_plane: bool,
    /// Temporal: keep static triangles in the static layer (`on`, the nearest one per texel)
    /// or in the lists as the papers do (`off`); `kept`: the layer drawn before the timed
    /// shadow pass, which draws only what moves (an engine's frames after the first).
    #[arg(long, value_enum, default_value_t = StaticLayerArg::On)]
    pub static_layer: StaticLayerArg,
    /// Temporal: how the ranges the collection stores are kept: `sorted` (each texel's
    /// ranges contiguous, in order of start time) or `lists` (per-texel linked lists in the
    /// order the collection appended them).
    #[arg(long, value_enum, default_value_t = RangeStorageArg::Sorted)]
    pub range_storage: RangeStorageArg,
    /// Temporal, sorted ranges: which ranges the sort leaves out: `static-layer` (those
    /// behind the static layer, with the plane test) or `cover` (also those that nearer
    /// ranges of two other triangles cover all along: less memory on deep scenes, a slower
    /// sort). The image is the same.
    #[arg(long, value_enum, default_value_t = PruningArg::StaticLayer)]
    pub pruning: PruningArg,
    /// `exact` adds the temporal map read with the exact lookup (`temporal-exact`: the
    /// forward frame's samples, or the deferred frame's mask) to the methods; `depth` (the
    /// default) compares the papers' depth lines only. The lookups: `depth` (the papers'
    /// depth lines, per texel, with the receiver offset and bias) or `exact` (the receiver's
    /// shadow ray against the triangles the map names, corners at t = 0 and t = 1: no texels,
    /// no offset, no bias; the map's collection is conservative, still triangles in its
    /// static name lists with the static layer; no --shadow-filter).
    #[arg(long, value_enum, default_value_t = LookupArg::Depth)]
    pub lookup: LookupArg,
    /// What the other methods are measured against: the brute-force reference, or the ray
    /// tracer (then the reference is one more method measured against it).
    #[arg(long, value_enum, default_value_t = TruthArg::Reference)]
    pub truth: TruthArg,
    /// `deferred`: compare the engine's frame instead (see `render --frame deferred`):
    /// temporal, TSM-N and plain masks against the exact truth.
    #[arg(long, value_enum, default_value_t = FrameArg::Forward)]
    pub frame: FrameArg,
    /// Deferred: the shutter time the G-buffer shows.
    #[arg(long, default_value_t = 1.0)]
    pub camera_time: f32,
    /// Deferred: TSM's maps (1 to 1024).
    #[arg(long, default_value_t = 8)]
    pub tsm_maps: u32,
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Print the table as one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub random: RandomCubesArgs,
    /// The options typed on the command line (`--spp`), set by
    /// [`Cli::parse_recording_given`]; empty otherwise.
    #[arg(skip)]
    pub given: Vec<String>,
}

/// Most frames `animate` renders in one run (25 s at 24 fps).
pub const MAX_ANIMATE_FRAMES: u32 = 600;

/// Highest `animate --fps`: a GIF's frame delays are in hundredths of a second.
pub const MAX_ANIMATE_FPS: f32 = 100.0;

/// Longest frame a GIF can hold: its delays are 16-bit counts of hundredths of a second.
pub const MAX_GIF_DELAY_S: f64 = 655.35;

/// Lowest `animate --fps` (about 0.001526): one frame a `MAX_GIF_DELAY_S`. Slower rates
/// cannot be written (the GIF would silently play faster), and ones near 0 made the delay
/// overflow a `Duration` (a panic).
pub const MIN_ANIMATE_FPS: f64 = 1.0 / MAX_GIF_DELAY_S;

#[derive(Debug, Args, Clone)]
#[command(mut_arg("scene", |a| a.default_value("walker-toward-light")))]
pub struct AnimateArgs {
    /// Number of frames, 1 to 600.
    // Hyphen values allowed here and on --fps: `--frames -3` is then refused as a value of
    // this option, not as an unknown flag `-3`.
    #[arg(long, default_value_t = 24, allow_hyphen_values = true, value_parser = clap::value_parser!(u32).range(1..=MAX_ANIMATE_FRAMES as i64))]
    pub frames: u32,
    /// Frames per second: frame i's shutter opens at START + i / FPS; from 0.001526 (one frame
    /// in 655.35 s, the longest a GIF frame lasts) to 100.
    #[arg(long, default_value_t = 24.0, allow_hyphen_values = true, value_parser = parse_fps)]
    pub fps: f32,
    /// Animation time of frame 0's shutter opening, seconds (default: the scene's own time,
    /// for a scene file each glTF model's `time`).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_start)]
    pub start: Option<f64>,
    #[command(flatten)]
    pub render: RenderArgs,
}

/// Parses `animate --fps`: a number in [`MIN_ANIMATE_FPS`, `MAX_ANIMATE_FPS`], both set by
/// what a GIF's frame delay can say (clap puts the option's name before the message).
pub fn parse_fps(text: &str) -> Result<f32, String> {
    let fps: f32 = text.trim().parse().map_err(|e| format!("{e}"))?;
    if f64::from(fps) >= MIN_ANIMATE_FPS && fps <= MAX_ANIMATE_FPS {
        Ok(fps)
    } else {
        Err(format!(
            "must be at least {MIN_ANIMATE_FPS:.6} (a GIF frame lasts at most {MAX_GIF_DELAY_S} \
             s) and at most {MAX_ANIMATE_FPS} (its delays are in hundredths of a second)"
        ))
    }
}

/// Largest |`animate --start`|, seconds (~32 years). Frame times are f64, which resolves
/// 1e9 s to 1.2e-7 s, far finer than a shutter; further out nothing is gained and the
/// resolution keeps falling.
pub const MAX_ANIMATE_START_S: f64 = 1e9;

/// Parses `animate --start`: a finite number of seconds, |start| <= `MAX_ANIMATE_START_S`.
pub fn parse_start(text: &str) -> Result<f64, String> {
    let start: f64 = text.trim().parse().map_err(|e| format!("{e}"))?;
    if start.is_finite() && start.abs() <= MAX_ANIMATE_START_S {
        Ok(start)
    } else {
        Err(format!(
            "must be a finite number of seconds in [-{MAX_ANIMATE_START_S:e}, \
             {MAX_ANIMATE_START_S:e}]"
        ))
    }
}

#[derive(Debug, Subcommand)]
pub enum SceneCommand {
    /// Print the names of the built-in scenes.
    List,
    /// Write a built-in scene as a JSON scene file (to stdout without --out).
    Export {
        name: String,
        #[arg(long)]
        out: Option<PathBuf>,
        #[command(flatten)]
        random: RandomCubesArgs,
    },
}

#[derive(Debug, Args, Clone)]
pub struct RandomCubesArgs {
    /// random-cubes: number of cubes.
    #[arg(long, default_value_t = 4000)]
    pub cubes: usize,
    /// random-cubes: smallest displacement of a cube over the shutter.
    #[arg(long, default_value_t = 4.0)]
    pub speed_min: f32,
    /// random-cubes: largest displacement of a cube over the shutter.
    #[arg(long, default_value_t = 8.0)]
    pub speed_max: f32,
    /// random-cubes: edge length of each cube.
    #[arg(long, default_value_t = 1.0)]
    pub cube_size: f32,
    /// random-cubes: seed of the placement.
    #[arg(long, default_value_t = 1)]
    pub scene_seed: u64,
    /// walker-toward-light, fox-run, game-level: levels of midpoint subdivision of the
    /// character, 0 to 8 (each multiplies its triangles by 4).
    #[arg(long, default_value_t = 0)]
    pub subdivide: u32,
}

#[derive(Debug, Args, Clone)]
pub struct RenderArgs {
    /// Built-in scene name (see `motion-shadows scene list`).
    #[arg(
        long,
        default_value = "cubes-toward-light",
        conflicts_with = "scene_file"
    )]
    pub scene: String,
    /// A JSON scene file (format in docs/scene-format.md).
    #[arg(long)]
    pub scene_file: Option<PathBuf>,
    #[arg(long, default_value_t = 1024)]
    pub width: u32,
    #[arg(long, default_value_t = 768)]
    pub height: u32,
    /// Samples per pixel, 1 to 64.
    #[arg(long, default_value_t = 8)]
    pub spp: u32,
    /// Seed of the sample positions and times.
    #[arg(long, default_value_t = 1)]
    pub seed: u32,
    /// Shadow map resolution WxH (default: the image resolution).
    #[arg(long, value_parser = parse_size)]
    pub shadow_size: Option<(u32, u32)>,
    #[arg(long, value_enum, default_value_t = MethodArg::Temporal)]
    pub method: MethodArg,
    /// Shadow term of the temporal and coverage methods: sampled (the papers') or analytic.
    #[arg(long, value_enum, default_value_t = EstimatorArg::Sampled)]
    pub shadow_estimator: EstimatorArg,
    /// Prism construction of the temporal and coverage methods: exact (closed-form covered
    /// times per texel) or the papers' triangulated prism.
    #[arg(long, value_enum, default_value_t = PrismsArg::Exact)]
    pub prisms: PrismsArg,
    /// Receiver test of every map lookup: `plane` (the receiver's plane's depth at the
    /// shadow texel's centre, no normal offset: keeps contact shadows at grazing light),
    /// `offset` (one shadow texel along the normal, the papers'), or `auto` (plane where the
    /// maps hold triangle ids, offset for TSM).
    #[arg(long, value_enum, default_value_t = ReceiverArg::Auto)]
    pub receiver: ReceiverArg,
    /// Shadow-map lookups: `none` (the receiver's texel), `bilinear` (2x2 texels weighted
    /// by overlap, PCF) or `footprint` (bilinear over the pixel's footprint); each texel
    /// integrated over the shutter with the analytic estimator.
    #[arg(long, value_enum, default_value_t = FilterArg::None)]
    pub shadow_filter: FilterArg,
    /// The same as `--receiver plane` (kept for scripts written before `--receiver`).
    #[arg(long, conflicts_with = "receiver")]
    pub receiver_plane: bool,
    /// Temporal: keep static triangles in the static layer (`on`, the nearest one per texel)
    /// or in the lists as the papers do (`off`); `kept`: the layer drawn before the timed
    /// shadow pass, which draws only what moves (an engine's frames after the first).
    #[arg(long, value_enum, default_value_t = StaticLayerArg::On)]
    pub static_layer: StaticLayerArg,
    /// Temporal: how the ranges the collection stores are kept: `sorted` (each texel's
    /// ranges contiguous, in order of start time) or `lists` (per-texel linked lists in the
    /// order the collection appended them).
    #[arg(long, value_enum, default_value_t = RangeStorageArg::Sorted)]
    pub range_storage: RangeStorageArg,
    /// Temporal, sorted ranges: which ranges the sort leaves out: `static-layer` (those
    /// behind the static layer, with the plane test) or `cover` (also those that nearer
    /// ranges of two other triangles cover all along: less memory on deep scenes, a slower
    /// sort). The image is the same.
    #[arg(long, value_enum, default_value_t = PruningArg::StaticLayer)]
    pub pruning: PruningArg,
    /// Temporal: how the map is read (the forward frame's samples, the deferred frame's
    /// mask): `depth` (the papers' depth lines, per texel, with the receiver offset and bias)
    /// or `exact` (the receiver's shadow ray against the triangles the map names, corners at
    /// t = 0 and t = 1: no texels, no offset, no bias; the map's collection is conservative,
    /// still triangles in its static name lists with the static layer; the forward frame's
    /// method is then named `temporal-exact` and takes no --shadow-filter, --range-storage or
    /// --pruning).
    #[arg(long, value_enum, default_value_t = LookupArg::Depth)]
    pub lookup: LookupArg,
    /// Render the frame this many times (1 to 100) and report the fastest, as `bench` does:
    /// the first frame's GPU times include first-use costs (lavapipe compiles shader variants
    /// at the first draw).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=100))]
    pub runs: u32,
    /// Reference: number of time slices averaged (the papers use 3000).
    #[arg(long, default_value_t = 1024)]
    pub slices: u32,
    /// Output directory.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// PNG exposure in stops, -64 to 64; automatic (99th percentile to 90% white) when
    /// absent.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_exposure)]
    pub exposure: Option<f32>,
    /// Print the summary as one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    /// Temporal/coverage: also write heat maps of the ranges stored per shadow-map pixel
    /// (for coverage, with and without the coverage map, on one scale).
    #[arg(long)]
    pub heatmaps: bool,
    /// `forward`: stochastic rasterization, each sample at its own time (the papers').
    /// `deferred`: an engine's frame: a G-buffer at --camera-time, each pixel lit by the share
    /// of the shutter its (moving) point sees the light; methods temporal, tsm (--tsm-maps
    /// maps), plain or raytrace (the exact truth).
    #[arg(long, value_enum, default_value_t = FrameArg::Forward)]
    pub frame: FrameArg,
    /// Deferred: the shutter time in [0, 1] the G-buffer shows (1: shutter close, as an
    /// engine draws its current frame).
    #[arg(long, default_value_t = 1.0)]
    pub camera_time: f32,
    /// Deferred TSM: the number of depth maps (1 to 1024), at the centres of equal strata.
    #[arg(long, default_value_t = 8)]
    pub tsm_maps: u32,
    /// Deferred: every receiver stands still where the G-buffer shows it (the mask before
    /// receivers could move), instead of moving as the G-buffer's motion says.
    #[arg(long)]
    pub static_receivers: bool,
    #[command(flatten)]
    pub random: RandomCubesArgs,
    /// The options typed on the command line (`--spp`), set by
    /// [`Cli::parse_recording_given`]; empty otherwise.
    #[arg(skip)]
    pub given: Vec<String>,
}

/// `render --frame`: how the camera side of the frame is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum FrameArg {
    /// Stochastic rasterization: every sample at its own time.
    Forward,
    /// A G-buffer at one time, lit by each pixel's lit share of the shutter.
    Deferred,
}

impl Default for RenderArgs {
    fn default() -> Self {
        match Cli::parse_from(["motion-shadows", "render"]).command {
            Some(Command::Render(args)) => args,
            _ => unreachable!("`render` parses to Command::Render"),
        }
    }
}
