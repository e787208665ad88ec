//! What a render reports: the paper's figures (N_f, N_r, equation (2)) and timings.

use serde::Serialize;

/// Bytes per fragment node and per range, as in the paper's equation (2).
pub const NODE_BYTES: u64 = 16;
pub const RANGE_BYTES: u64 = 24;

/// The name `--shadow-filter` and the JSON outputs give a filter.
pub fn filter_name(filter: motion_shadows::technique::ShadowFilter) -> &'static str {
    match filter {
        motion_shadows::technique::ShadowFilter::None => "none",
        motion_shadows::technique::ShadowFilter::Bilinear => "bilinear",
        motion_shadows::technique::ShadowFilter::Footprint => "footprint",
    }
}

/// The name `--prisms` and the JSON outputs give a construction.
pub fn prisms_name(construction: motion_shadows::technique::PrismConstruction) -> &'static str {
    match construction {
        motion_shadows::technique::PrismConstruction::Exact => "exact",
        motion_shadows::technique::PrismConstruction::Paper => "paper",
    }
}

/// The name `--lookup` and the JSON outputs give the lookup of a frame of `method`.
pub fn lookup_name(
    method: super::Method,
    lookup: motion_shadows::technique::Lookup,
) -> &'static str {
    use motion_shadows::technique::Lookup;
    match (method, lookup) {
        (super::Method::Temporal | super::Method::Coverage, Lookup::DepthLine) => "depth",
        (super::Method::Temporal | super::Method::Coverage, Lookup::Exact) => "exact",
        _ => "none",
    }
}

/// The name `--pruning` and the JSON outputs give a pruning rule.
pub fn pruning_name(pruning: motion_shadows::technique::Pruning) -> &'static str {
    match pruning {
        motion_shadows::technique::Pruning::StaticLayer => "static-layer",
        motion_shadows::technique::Pruning::Cover => "cover",
        motion_shadows::technique::Pruning::Coverage => "coverage",
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct PassTime {
    pub pass: String,
    /// GPU time from timestamp queries, milliseconds.
    pub gpu_ms: f64,
}

/// The pass that copies the ordinary maps' attachments (plain, TSM) into the buffers the
/// lighting pass reads by address. It is this project's plumbing, not part of drawing those
/// maps (an engine samples the depth image directly), so the frame and shadow-pass times
/// leave it out; it is listed with the passes all the same.
pub const MAP_COPY_PASS: &str = "map copy-out";

/// Passes that belong to the lighting side of a frame (everything else is the shadow side).
pub fn is_lighting_pass(name: &str) -> bool {
    name.starts_with("lighting")
}

impl PassTime {
    /// Whether it counts toward the frame's time (all but [`MAP_COPY_PASS`]).
    pub fn counted(&self) -> bool {
        self.pass != MAP_COPY_PASS
    }
}

/// GPU milliseconds of the counted passes that `keep` accepts.
pub fn counted_ms(passes: &[PassTime], keep: impl Fn(&str) -> bool) -> f64 {
    passes
        .iter()
        .filter(|p| p.counted() && keep(&p.pass))
        .fold(0.0, |total, p| total + p.gpu_ms)
}

#[derive(Debug, Clone, Serialize)]
pub struct FrameStats {
    pub scene: String,
    pub method: String,
    /// "sampled" or "analytic" (`--shadow-estimator`; only the temporal and coverage methods
    /// use it).
    pub shadow_estimator: String,
    /// "none" or "bilinear" (`--shadow-filter`; every shadow-map method; the ray tracer has
    /// no map: "none").
    pub shadow_filter: String,
    /// "exact" or "paper" (`--prisms`; only the temporal and coverage methods use it).
    pub prisms: String,
    /// "sorted" or "lists" (`--range-storage`): how the temporal map kept the ranges its
    /// collection stored; "sorted" only where the frame sorted them (the exact construction
    /// with the static layer), "lists" for every other frame and method.
    pub range_storage: String,
    /// "static-layer" or "cover" (`--pruning`): the rule the sort pruned the ranges by, where
    /// `range_storage` is "sorted"; "none" for every other frame and method.
    pub pruning: String,
    /// "depth" or "exact" (`--lookup`): how the temporal map's samples were tested (the
    /// coverage method reads depth lines); "none" for the methods without a temporal map.
    pub lookup: String,
    /// Whether this frame's method tested receivers at their plane's depth at the texel
    /// centre (`--receiver`: `auto` gives it to every method but TSM; never the ray tracer).
    pub receiver_plane: bool,
    pub width: u32,
    pub height: u32,
    pub shadow_width: u32,
    pub shadow_height: u32,
    pub spp: u32,
    pub seed: u32,
    pub triangles: u32,
    /// N_f: prism fragments the collection sub-pass produced (two per range where it
    /// stores the ranges itself).
    pub fragments: u64,
    /// The fragments stored as nodes: N_f, or 0 where the collection stores the ranges
    /// itself (the exact construction with the static layer).
    pub fragments_stored: u64,
    /// N_r: depth-time ranges stored by the generation sub-pass (or the collection).
    pub ranges: u64,
    /// N_r without the coverage map (equal to `ranges` for other methods).
    pub ranges_without_coverage: u64,
    /// Equation (2): N_f * 16 + N_r * 24 + 2 * shadow pixels * 4 bytes; with sorted ranges
    /// ([`sorted_map_bytes`]) what the map holds once sorted and pruned:
    /// (N_r - pruned) * 24 + shadow pixels * 4.
    pub shadow_map_bytes_eq2: u64,
    /// With sorted ranges: what the frame held besides, until the sort (the collection's
    /// lists, N_r * 24, and its per-texel counts, shadow pixels * 4); 0 otherwise.
    pub shadow_map_bytes_transient: u64,
    /// With sorted ranges: the ranges the sort left out because no lookup can be decided by
    /// them (behind the static layer; with `--pruning cover` also those covered by two other
    /// triangles: docs/src/pruning.md); the map holds `ranges - ranges_pruned`. 0 otherwise.
    pub ranges_pruned: u64,
    /// `shadow_map_bytes_eq2` with the pruned ranges kept.
    pub shadow_map_bytes_eq2_unpruned: u64,
    /// The static layer (8 bytes per shadow-map texel: the nearest static triangle, in place
    /// of static triangles' fragments and ranges); 0 where the frame did not use one.
    pub static_layer_bytes: u64,
    /// The timed shadow pass kept a static layer drawn before it (`--static-layer kept`).
    pub static_layer_kept: bool,
    /// Whether the scene's light moves during the shutter (its `t1` pose; only the ray
    /// tracer takes such a scene so far).
    pub light_moves: bool,
    /// Whether the scene's camera moves during the shutter (its `t1` pose, issue 38): only
    /// the ray tracer's forward frame takes it so far.
    pub camera_moves: bool,
    /// Equation (2) with the ranges stored without the coverage map.
    pub shadow_map_bytes_eq2_without_coverage: u64,
    /// The nearest, coverage and cover-depth maps (coverage method; 0 otherwise).
    pub coverage_map_bytes: u64,
    /// Bytes the shadow map's buffers actually occupy.
    pub shadow_map_bytes_allocated: u64,
    /// The most fragments any one shadow-map pixel held (the generation pass pairs up to
    /// `technique::gpu_types::MAX_LIST_NODES`).
    pub longest_fragment_list: u32,
    /// How many times the shadow pass ran (more than 1 when its buffers had to grow).
    pub shadow_pass_attempts: u32,
    /// The upper bound on the ranges the first attempt was sized from
    /// (`technique::RangeCeiling`); None where there is none (the papers' prisms, methods
    /// without a temporal map).
    pub ranges_at_most: Option<u64>,
    pub samples_per_chunk: u32,
    pub passes: Vec<PassTime>,
    /// GPU milliseconds of the shadow side: every counted pass before the lighting pass (the
    /// figure `bench` compares between methods).
    pub shadow_pass_ms: f64,
    /// GPU milliseconds of the lighting pass (raster and shade).
    pub lighting_pass_ms: f64,
    /// GPU milliseconds of the frame: every counted pass ([`MAP_COPY_PASS`] is not).
    pub frame_ms: f64,
    /// Frames rendered (`render --runs`); the figures are the fastest one's.
    pub runs: u32,
    /// Things the frame did that are legal but probably not what was meant (e.g. no
    /// triangle reaching the shadow map); also printed on stderr.
    pub warnings: Vec<String>,
    /// Wall-clock time of the whole render, including uploads and pipeline creation.
    pub wall_ms: f64,
    pub device: String,
}

/// Equation (2) of the 2018 paper, for the fragments stored as nodes and the ranges.
pub fn equation_2_bytes(fragments: u64, ranges: u64, shadow_pixels: u64) -> u64 {
    fragments * NODE_BYTES + ranges * RANGE_BYTES + 2 * shadow_pixels * 4
}

/// Equation (2) for a map whose ranges are sorted (`RangeStorage::Sorted`): no node, and one
/// index per texel (the range heads; the per-texel counts are the frame's, like its lists).
pub fn sorted_map_bytes(ranges: u64, shadow_pixels: u64) -> u64 {
    ranges * RANGE_BYTES + shadow_pixels * 4
}
