//! What the keys and the mouse do: the state they change (camera, method, animation time,
//! shutter angle, overlay, screenshot) and the key map, apart from the window so that it can
//! be tested without one.

use super::camera::CameraControl;
use super::method::ViewMethod;
use crate::scene::Scene;
use motion_shadows::technique::{ShadowEstimator, ShadowFilter};
use winit::keyboard::{Key, NamedKey};

/// Seconds one arrow key press moves the animation.
pub const SCRUB_STEP_S: f64 = 1.0 / 24.0;
/// Degrees one bracket key press changes the shutter angle.
pub const SHUTTER_STEP_DEG: f32 = 45.0;
/// The shutter angle's range: 360 is the scene's own shutter.
pub const MIN_SHUTTER_DEG: f32 = 45.0;
pub const MAX_SHUTTER_DEG: f32 = 360.0;

/// A key's action.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Action {
    Quit,
    PlayPause,
    /// Moves the animation by this many scrub steps (and pauses it).
    Scrub(f64),
    /// Changes the shutter angle by this many steps.
    Shutter(f32),
    NextMethod,
    /// The split view's right-hand method: the next other method, or off.
    NextSplit,
    /// The stochastic frame instead of the deferred one, or back.
    ToggleFrame,
    /// The stochastic frame's shadow estimator: sampled or analytic.
    NextEstimator,
    /// The stochastic frame's shadow filter: none, bilinear, footprint.
    NextFilter,
    ToggleOverlay,
    Screenshot,
    ResetCamera,
    /// Flies: forward, right, up (in tenths of the distance to the target).
    Fly(f32, f32, f32),
    PrintKeys,
}

/// The keys, as `--help`-style lines (printed at the start and on H).
pub const KEYS: &[&str] = &[
    "mouse drag: orbit   wheel: dolly   W/S A/D Q/E: fly   R: reset camera",
    "space: play/pause   left/right: scrub time   [ ]: shutter angle",
    "M: method (temporal, temporal-exact, TSM-N, plain)   F: stochastic/deferred frame",
    "V: split view, right half: the next other method, then off (deferred frame)",
    "G: estimator (sampled/analytic)   B: filter (none/bilinear/footprint), stochastic frame",
    "O: overlay",
    "P: screenshot (PNG of what is shown)   H: keys   Esc: quit",
];

pub fn action_for_key(key: &Key) -> Option<Action> {
    Some(match key {
        Key::Named(NamedKey::Escape) => Action::Quit,
        Key::Named(NamedKey::Space) => Action::PlayPause,
        Key::Named(NamedKey::ArrowLeft) => Action::Scrub(-1.0),
        Key::Named(NamedKey::ArrowRight) => Action::Scrub(1.0),
        Key::Character(c) => match c.to_lowercase().as_str() {
            "[" => Action::Shutter(-1.0),
            "]" => Action::Shutter(1.0),
            "m" => Action::NextMethod,
            "v" => Action::NextSplit,
            "f" => Action::ToggleFrame,
            "g" => Action::NextEstimator,
            "b" => Action::NextFilter,
            "o" => Action::ToggleOverlay,
            "p" => Action::Screenshot,
            "r" => Action::ResetCamera,
            "h" => Action::PrintKeys,
            "w" => Action::Fly(1.0, 0.0, 0.0),
            "s" => Action::Fly(-1.0, 0.0, 0.0),
            "d" => Action::Fly(0.0, 1.0, 0.0),
            "a" => Action::Fly(0.0, -1.0, 0.0),
            "e" => Action::Fly(0.0, 0.0, 1.0),
            "q" => Action::Fly(0.0, 0.0, -1.0),
            _ => return None,
        },
        _ => return None,
    })
}

/// What the controls set.
#[derive(Debug, Clone)]
pub struct ViewState {
    pub camera: CameraControl,
    pub method: ViewMethod,
    pub tsm_maps: u32,
    /// The split view's right-hand method (None: no split).
    pub split: Option<ViewMethod>,
    pub playing: bool,
    /// Seconds of animation since the start.
    pub time: f64,
    pub shutter_deg: f32,
    pub overlay: bool,
    /// The stochastic frame (the papers' lighting pass) instead of the deferred one.
    pub stochastic: bool,
    /// Its shadow estimator and filter.
    pub estimator: ShadowEstimator,
    pub filter: ShadowFilter,
    /// The scene must be posed again (time or shutter changed).
    pub scene_changed: bool,
    /// A screenshot was asked for and not taken yet.
    pub screenshot: bool,
    pub quit: bool,
    pub print_keys: bool,
}

impl ViewState {
    pub fn new(camera: CameraControl, method: ViewMethod, tsm_maps: u32, overlay: bool) -> Self {
        Self {
            camera,
            method,
            tsm_maps,
            split: None,
            stochastic: false,
            estimator: ShadowEstimator::Sampled,
            filter: ShadowFilter::None,
            playing: false,
            time: 0.0,
            shutter_deg: MAX_SHUTTER_DEG,
            overlay,
            scene_changed: false,
            screenshot: false,
            quit: false,
            print_keys: false,
        }
    }

    pub fn apply(&mut self, action: Action) {
        match action {
            Action::Quit => self.quit = true,
            Action::PlayPause => self.playing = !self.playing,
            Action::Scrub(steps) => {
                self.playing = false;
                self.time += steps * SCRUB_STEP_S;
                self.scene_changed = true;
            }
            Action::Shutter(steps) => {
                let angle = (self.shutter_deg + steps * SHUTTER_STEP_DEG)
                    .clamp(MIN_SHUTTER_DEG, MAX_SHUTTER_DEG);
                self.scene_changed |= angle != self.shutter_deg;
                self.shutter_deg = angle;
            }
            Action::NextMethod => {
                self.method = self.method.next(self.tsm_maps);
                // The split's right side stays another method.
                if self.split == Some(self.method) {
                    self.split = self.method.next_split(self.split, self.tsm_maps);
                }
            }
            Action::NextSplit => self.split = self.method.next_split(self.split, self.tsm_maps),
            Action::ToggleFrame => self.stochastic = !self.stochastic,
            Action::NextEstimator => {
                self.estimator = match self.estimator {
                    ShadowEstimator::Sampled => ShadowEstimator::Analytic,
                    ShadowEstimator::Analytic => ShadowEstimator::Sampled,
                }
            }
            Action::NextFilter => {
                self.filter = match self.filter {
                    ShadowFilter::None => ShadowFilter::Bilinear,
                    ShadowFilter::Bilinear => ShadowFilter::Footprint,
                    ShadowFilter::Footprint => ShadowFilter::None,
                }
            }
            Action::ToggleOverlay => self.overlay = !self.overlay,
            Action::Screenshot => self.screenshot = true,
            Action::ResetCamera => self.camera.reset(),
            Action::Fly(forward, right, up) => self.camera.fly(forward, right, up),
            Action::PrintKeys => self.print_keys = true,
        }
    }

    /// Moves a playing animation on by `seconds` of wall time.
    pub fn advance(&mut self, seconds: f64) {
        if self.playing {
            self.time += seconds;
            self.scene_changed = true;
        }
    }

    /// The filter the stochastic frame reads its map with: none with the exact lookup,
    /// which has no texels to filter (the overlay says so).
    pub fn effective_filter(&self) -> ShadowFilter {
        match self.method {
            ViewMethod::TemporalExact => ShadowFilter::None,
            _ => self.filter,
        }
    }

    /// The share of the scene's shutter shown.
    pub fn shutter_fraction(&self) -> f32 {
        self.shutter_deg / MAX_SHUTTER_DEG
    }
}

/// `scene` with a shorter shutter: each vertex's shutter-close position moved to where its
/// linear motion is at `fraction` of the shutter (the motion the shadow map assumes between
/// the two positions). 1 leaves the scene as it is.
pub fn with_shutter(mut scene: Scene, fraction: f32) -> Scene {
    if fraction >= 1.0 {
        return scene;
    }
    for mesh in &mut scene.meshes {
        for (p1, p0) in mesh.t1.iter_mut().zip(&mesh.t0) {
            *p1 = *p0 + (*p1 - *p0) * fraction;
        }
    }
    scene
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{BuiltinOptions, builtin};

    #[test]
    fn keys_map_to_their_actions() {
        let key = |c: &str| Key::Character(c.into());
        assert_eq!(action_for_key(&key("M")), Some(Action::NextMethod));
        assert_eq!(action_for_key(&key("]")), Some(Action::Shutter(1.0)));
        assert_eq!(
            action_for_key(&Key::Named(NamedKey::ArrowLeft)),
            Some(Action::Scrub(-1.0))
        );
        assert_eq!(action_for_key(&key("z")), None);
    }

    #[test]
    fn shutter_and_time_keys_change_the_scene_within_their_range() {
        let scene = builtin("cubes-toward-light", &BuiltinOptions::default()).unwrap();
        let mut state = ViewState::new(
            CameraControl::new(&scene.camera),
            ViewMethod::Temporal,
            8,
            true,
        );
        // Already the widest: nothing changes.
        state.apply(Action::Shutter(1.0));
        assert!(!state.scene_changed);
        for _ in 0..20 {
            state.apply(Action::Shutter(-1.0));
        }
        assert_eq!(state.shutter_deg, MIN_SHUTTER_DEG);
        assert!(state.scene_changed);
        state.apply(Action::PlayPause);
        state.apply(Action::Scrub(2.0));
        assert!(!state.playing);
        assert!((state.time - 2.0 * SCRUB_STEP_S).abs() < 1e-12);
        state.advance(1.0);
        assert!((state.time - 2.0 * SCRUB_STEP_S).abs() < 1e-12, "paused");
    }

    #[test]
    fn estimator_and_filter_keys_cycle_and_the_exact_lookup_reads_unfiltered() {
        let scene = builtin("cubes-toward-light", &BuiltinOptions::default()).unwrap();
        let mut state = ViewState::new(
            CameraControl::new(&scene.camera),
            ViewMethod::Temporal,
            8,
            true,
        );
        state.apply(Action::NextEstimator);
        assert_eq!(state.estimator, ShadowEstimator::Analytic);
        state.apply(Action::NextFilter);
        state.apply(Action::NextFilter);
        assert_eq!(state.effective_filter(), ShadowFilter::Footprint);
        state.apply(Action::NextMethod);
        assert_eq!(state.method, ViewMethod::TemporalExact);
        assert_eq!(state.effective_filter(), ShadowFilter::None);
        state.apply(Action::NextFilter);
        assert_eq!(state.filter, ShadowFilter::None);
    }

    #[test]
    fn a_half_shutter_ends_the_motion_half_way() {
        let scene = builtin("cubes-toward-light", &BuiltinOptions::default()).unwrap();
        let half = with_shutter(scene.clone(), 0.5);
        let mut moving = 0;
        for (a, b) in scene.meshes.iter().zip(&half.meshes) {
            assert_eq!(a.t0, b.t0);
            for ((p0, p1), q1) in a.t0.iter().zip(&a.t1).zip(&b.t1) {
                assert!((*q1 - (*p0 + *p1) * 0.5).length() < 1e-5);
                moving += usize::from(p0 != p1);
            }
        }
        assert!(moving > 0, "the scene moves");
        assert_eq!(with_shutter(scene.clone(), 1.0), scene);
    }
}
