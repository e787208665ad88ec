//! Options a frame does not read, refused by name before anything is loaded or rendered
//! (nothing a user asks for is dropped silently). One table per command: an option is listed
//! with the frames, and for the deferred frame the methods, that read it; an option not
//! listed is read by every frame and method of its command.

use super::args::{FrameArg, MethodArg};

/// Who reads an option.
#[derive(Debug, Clone, Copy)]
pub struct Readers {
    /// The forward frame reads it (with at least one of its methods; those an option does
    /// not apply to are refused by the forward frame's own checks).
    pub forward: bool,
    /// The deferred methods that read it (`compare --frame deferred`: empty when it does not
    /// read it, any method when it does).
    pub deferred: &'static [MethodArg],
}

/// An option of a command and who reads it.
#[derive(Debug, Clone, Copy)]
pub struct UnreadOption {
    /// The option as typed, `--spp`.
    pub flag: &'static str,
    pub readers: Readers,
    /// What it is for, so the refusal says why it does not apply.
    pub why: &'static str,
}

const NONE: &[MethodArg] = &[];
const ALL: &[MethodArg] = &[
    MethodArg::Temporal,
    MethodArg::Tsm,
    MethodArg::Plain,
    MethodArg::Raytrace,
];
/// The deferred methods that draw shadow maps (all but the ray-traced truth).
const MAPS: &[MethodArg] = &[MethodArg::Temporal, MethodArg::Tsm, MethodArg::Plain];
const TEMPORAL: &[MethodArg] = &[MethodArg::Temporal];
const TSM: &[MethodArg] = &[MethodArg::Tsm];

const fn option(
    flag: &'static str,
    forward: bool,
    deferred: &'static [MethodArg],
    why: &'static str,
) -> UnreadOption {
    UnreadOption {
        flag,
        readers: Readers { forward, deferred },
        why,
    }
}

const SPP: &str = "samples per pixel of the forward frame (a deferred frame shades one G-buffer \
                   point per pixel)";
const SEED: &str = "the seed of the forward frame's sample positions and times (a deferred \
                    frame has none)";
const SLICES: &str = "time slices of the forward frame's brute-force reference";
const ESTIMATOR: &str = "the forward frame's shadow term (a deferred mask takes each point's \
                         exact lit share of the shutter)";
const FILTER: &str = "the forward frame's filtered map lookups (the deferred mask reads its \
                      texels unfiltered)";
const PRISMS: &str = "how the temporal map's collection builds moving triangles";
const STORAGE: &str = "how the temporal map keeps its ranges";
const PRUNING: &str = "which ranges the temporal map's sort leaves out";
const STATIC_LAYER: &str = "the shadow maps' static layer (the ray-traced truth draws no map)";
const RECEIVER: &str = "how a shadow map tests a receiver (the ray-traced truth draws no map)";
const CAMERA_TIME: &str = "the time of the deferred frame's G-buffer (the forward frame's \
                           samples each have their own time)";
const TSM_MAPS: &str = "the depth maps of the deferred frame's TSM";
const STATIC_RECEIVERS: &str = "whether the deferred frame's receivers move (the forward \
                                frame's samples see every receiver where it is at their time)";
const HEATMAPS: &str = "heat maps of the forward frame's temporal map (the deferred frame \
                        writes its mask instead)";
const LOOKUP: &str = "how the temporal map is read (the other methods have no such lookup)";
const TRUTH: &str = "what the forward comparison measures against (the deferred one is always \
                     against the ray-traced truth)";

/// `render` (and `animate`, which takes its options).
pub const RENDER_OPTIONS: &[UnreadOption] = &[
    option("--spp", true, NONE, SPP),
    option("--seed", true, NONE, SEED),
    option("--slices", true, NONE, SLICES),
    option("--shadow-estimator", true, NONE, ESTIMATOR),
    option("--shadow-filter", true, NONE, FILTER),
    option("--heatmaps", true, NONE, HEATMAPS),
    option("--prisms", true, TEMPORAL, PRISMS),
    option("--range-storage", true, TEMPORAL, STORAGE),
    option("--pruning", true, TEMPORAL, PRUNING),
    option("--static-layer", true, MAPS, STATIC_LAYER),
    option("--receiver", true, MAPS, RECEIVER),
    option("--receiver-plane", true, MAPS, RECEIVER),
    option("--camera-time", false, ALL, CAMERA_TIME),
    option("--tsm-maps", false, TSM, TSM_MAPS),
    option("--static-receivers", false, ALL, STATIC_RECEIVERS),
    option("--lookup", true, TEMPORAL, LOOKUP),
];

/// `compare`: its deferred frame renders the truth, temporal, TSM and plain.
pub const COMPARE_OPTIONS: &[UnreadOption] = &[
    option("--spp", true, NONE, SPP),
    option("--seed", true, NONE, SEED),
    option("--slices", true, NONE, SLICES),
    option("--shadow-estimator", true, NONE, ESTIMATOR),
    option("--shadow-filter", true, NONE, FILTER),
    option("--truth", true, NONE, TRUTH),
    option("--camera-time", false, ALL, CAMERA_TIME),
    option("--tsm-maps", false, ALL, TSM_MAPS),
    option("--lookup", true, ALL, LOOKUP),
];

/// Whether `option` is read by `frame` with `method` (`None`: any method, as `compare`).
pub fn reads(option: &UnreadOption, frame: FrameArg, method: Option<MethodArg>) -> bool {
    match (frame, method) {
        (FrameArg::Forward, _) => option.readers.forward,
        (FrameArg::Deferred, Some(method)) => option.readers.deferred.contains(&method),
        (FrameArg::Deferred, None) => !option.readers.deferred.is_empty(),
    }
}

/// Refuses the first of the `given` options (as typed, `--spp`) that `table` says `frame`
/// with `method` does not read; `context` names the frame in the message.
pub fn refuse_unread(
    given: &[String],
    table: &[UnreadOption],
    frame: FrameArg,
    method: Option<MethodArg>,
    context: &str,
) -> anyhow::Result<()> {
    for option in table {
        if given.iter().any(|g| g == option.flag) && !reads(option, frame, method) {
            anyhow::bail!(
                "{} does not apply to {context}: it sets {}; leave it out",
                option.flag,
                option.why
            );
        }
    }
    Ok(())
}

/// How the refusal names `frame` with `method` of `command`.
pub fn context(command: &str, frame: FrameArg, method: Option<&str>) -> String {
    match (frame, method) {
        (FrameArg::Forward, _) => format!("{command} --frame forward"),
        (FrameArg::Deferred, Some(method)) => {
            format!("{command} --frame deferred --method {method}")
        }
        (FrameArg::Deferred, None) => format!("{command} --frame deferred"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The `--options` a message names.
    fn flags(message: &str) -> Vec<&str> {
        message
            .split(|c: char| !(c.is_ascii_alphanumeric() || c == '-'))
            .filter(|w| w.starts_with("--"))
            .collect()
    }

    /// The deferred mask's loop-limit refusal suggests what the deferred frame reads (it
    /// suggested the forward frame's "no shadow filter" and "sampled estimator"): every option
    /// it names is one `render --frame deferred` reads, and it names none the deferred frame
    /// does not read, by flag or in words.
    #[test]
    fn the_deferred_loop_limit_message_names_only_deferred_options() {
        use motion_shadows::technique::Lookup;
        let depth = crate::render::deferred::loop_limit_error(12, 65535, Lookup::DepthLine);
        let exact = crate::render::deferred::loop_limit_error(12, 65535, Lookup::Exact);
        // The exact map's lists are not pruned: --pruning would change nothing there.
        assert!(!exact.to_string().contains("--pruning"), "{exact}");
        assert!(exact.to_string().contains("--lookup depth"), "{exact}");
        let message = format!("{depth} {exact}");
        let named = flags(&message);
        assert!(!named.is_empty(), "suggests no option: {message}");
        for flag in &named {
            let forward_only = RENDER_OPTIONS
                .iter()
                .any(|o| o.flag == *flag && o.readers.deferred.is_empty());
            assert!(!forward_only, "{flag} is forward-only: {message}");
        }
        for option in RENDER_OPTIONS
            .iter()
            .filter(|o| o.readers.deferred.is_empty())
        {
            let words = option.flag.trim_start_matches("--").replace('-', " ");
            assert!(
                !message.contains(option.flag) && !message.contains(&words),
                "names {} ({words:?}): {message}",
                option.flag
            );
        }
    }
}
