//! `motion-shadows view`: the deferred frame in a window, one more host of the library's
//! public API. The viewer makes its own instance, device and swapchain as an engine does
//! ([`device`], [`swapchain`]), and runs a frame loop with frames in flight ([`frame_loop`],
//! [`frame_slot`]): per frame the library's shadow pass and visibility mask with moving
//! receivers ([`record`]), its own shading ([`shade`]), the blit into the swapchain image.
//! [`window`] is the event loop. The split view draws a second method's shadows with its
//! own maps ([`room`] readies each side's) and shades the right half with them. What it allocates is counted ([`allocations`]): nothing per
//! frame after the first.

pub mod allocations;
pub mod camera;
pub mod controls;
pub mod device;
pub mod frame_loop;
pub mod frame_slot;
pub mod method;
pub mod overlay;
pub mod record;
pub mod room;
pub mod shade;
pub mod split;
pub mod swapchain;
pub mod window;

use crate::render::RenderSettings;
use crate::render::deferred::DeferredSettings;
use crate::scene::{AnimatedScene, Scene};
use allocations::AllocationCounts;
use frame_loop::{FrameSettings, FrameStats, Screenshot};
use method::ViewMethod;

pub use window::run;

/// What the viewer shows and how it runs.
pub struct ViewOptions {
    pub scene: Scene,
    /// The window's first size (`width`, `height`) and the frame's settings.
    pub settings: RenderSettings,
    /// The deferred frame's shutter time and receivers (its method is `method`'s).
    pub deferred: DeferredSettings,
    pub frame: FrameSettings,
    /// The method shown first (the method key cycles through the others).
    pub method: ViewMethod,
    /// N of TSM-N when the method key reaches TSM.
    pub tsm_maps: u32,
    /// The split view's right-hand method at the start (the split key changes it).
    pub split: Option<ViewMethod>,
    pub overlay: bool,
    /// Start with the stochastic frame (the temporal map's lighting pass).
    pub stochastic: bool,
    /// Its samples per pixel.
    pub spp: u32,
    /// The scene's animation, where it has one (play and scrub keys).
    pub animation: Option<AnimatedScene>,
    /// A scripted run: this many frames presented, then the viewer closes.
    pub frames: Option<u32>,
    /// With `frames`: keep the last presented frame ([`ViewReport::screenshot`]).
    pub screenshot: Option<std::path::PathBuf>,
    /// With `frames`: after the first frame, ask the window system for this size; the run
    /// ends only once frames are presented at it.
    pub resize: Option<(u32, u32)>,
    /// The Khronos validation layer with synchronization validation.
    pub validation: bool,
}

/// What a run measured.
pub struct ViewReport {
    pub device: String,
    /// Frames presented.
    pub frames: u64,
    /// Seconds from the first frame's presentation to the last frame's completion.
    pub seconds_after_first: f64,
    /// The size presented last.
    pub size: (u32, u32),
    pub allocations: AllocationCounts,
    pub stats: FrameStats,
    pub screenshot: Option<Screenshot>,
    /// Every warning and error of the validation layer, the teardown's included.
    pub validation_messages: Vec<String>,
}

impl ViewReport {
    /// Frames per second after the first (which builds pipelines' first use and the maps).
    pub fn fps(&self) -> f64 {
        if self.seconds_after_first > 0.0 && self.frames > 1 {
            (self.frames - 1) as f64 / self.seconds_after_first
        } else {
            0.0
        }
    }
}
