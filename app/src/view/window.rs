//! The window and its event loop (winit, X11): the GPU state is made once the window exists,
//! a frame is drawn on every redraw, keys and the mouse change the view ([`super::controls`]),
//! a resize marks the swapchain stale, a minimized window draws nothing, Escape or closing
//! the window ends the run. A scripted run (`--frames`) ends by itself after its frames (and
//! its resize, when asked).

use super::allocations::{AllocationCounter, Phase};
use super::camera::CameraControl;
use super::controls::{KEYS, ViewState, action_for_key, with_shutter};
use super::device::{ViewDevice, ViewInstance};
use super::frame_loop::{Drawn, FrameLoop, FrameRequest, SplitRequest};
use super::method::ViewMethod;
use super::split::split_line;
use super::{ViewOptions, ViewReport};
use crate::output::write_rgb8_png;
use anyhow::{Context as _, anyhow, bail};
use motion_shadows::technique::{LightingView, ShadowEstimator};
use std::time::{Duration, Instant};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::window::{Window, WindowId};

/// How long a scripted run waits past its frames for the window system to resize.
const RESIZE_WAIT: Duration = Duration::from_secs(20);
/// How long the loop sleeps between frames while the surface has no area (minimized).
const NO_AREA_WAIT: Duration = Duration::from_millis(50);
/// Weight of the newest frame in the overlay's frame rate.
const FPS_SMOOTHING: f64 = 0.2;

struct Viewer {
    options: ViewOptions,
    state: ViewState,
    /// Dropped before the window: the surface is made on it.
    frames: Option<FrameLoop>,
    window: Option<Window>,
    counter: AllocationCounter,
    presented: u64,
    /// When the first frame was presented (the frame rate counts the frames after it).
    first_presented: Option<Instant>,
    last_frame: Option<Instant>,
    smoothed_fps: f64,
    resize_requested: Option<Instant>,
    /// Left button held: the cursor's last position.
    dragging: Option<(f64, f64)>,
    cursor: (f64, f64),
    /// Interactive screenshots written so far.
    shots: u32,
    error: Option<anyhow::Error>,
    device_name: String,
}

impl Viewer {
    fn start(&mut self, event_loop: &ActiveEventLoop) -> anyhow::Result<()> {
        let (width, height) = (self.options.settings.width, self.options.settings.height);
        let attributes = Window::default_attributes()
            .with_title(format!("motion-shadows: {}", self.options.scene.name))
            .with_inner_size(PhysicalSize::new(width, height));
        let window = event_loop
            .create_window(attributes)
            .context("creating the window")?;
        let display = window
            .display_handle()
            .map_err(|e| anyhow!("the window's display handle: {e}"))?
            .as_raw();
        let handle = window
            .window_handle()
            .map_err(|e| anyhow!("the window's handle: {e}"))?
            .as_raw();
        let base = ViewInstance::new(display, handle, self.options.validation)?;
        let gpu = ViewDevice::new(base)?;
        let size = window.inner_size();
        let (light, _) = self.state.method.light(
            &self.options.scene,
            &self.options.settings,
            &self.options.deferred,
        )?;
        let frames = FrameLoop::new(
            gpu,
            self.options.scene.clone(),
            self.state.method,
            &light,
            self.options.frame,
            (size.width.max(1), size.height.max(1)),
            &mut self.counter,
        )?;
        self.device_name = frames.device_name().to_owned();
        self.frames = Some(frames);
        window.request_redraw();
        self.window = Some(window);
        Ok(())
    }

    /// The overlay's lines for the frame about to be drawn.
    fn overlay_lines(&self, frames: &FrameLoop, size: PhysicalSize<u32>) -> Vec<String> {
        let stats = frames.stats();
        let gpu_total: f64 = stats
            .last_pass_ms
            .iter()
            .filter(|(p, _)| p != "start")
            .map(|(_, ms)| ms)
            .sum();
        let passes: Vec<String> = stats
            .last_pass_ms
            .iter()
            .filter(|(p, _)| p != "start" && p != "draw list")
            .map(|(p, ms)| format!("{p} {ms:.1}"))
            .collect();
        let time = if self.options.animation.is_some() {
            format!(
                "t {:+.3} s {}",
                self.state.time,
                if self.state.playing {
                    "playing"
                } else {
                    "paused"
                }
            )
        } else {
            "still scene".to_owned()
        };
        let frame = match (self.state.stochastic, self.state.method) {
            (true, _) if self.state.split.is_some() => {
                "deferred (split: stochastic off)".to_owned()
            }
            (true, _) if moves(frames.scene()) => {
                "deferred (stochastic: still light and camera only)".to_owned()
            }
            (false, _) => "deferred".to_owned(),
            (true, ViewMethod::Tsm { .. }) => "deferred (stochastic: temporal only)".to_owned(),
            (true, method) => format!(
                "stochastic {} spp {} {}{}",
                self.options.spp,
                match self.state.estimator {
                    ShadowEstimator::Sampled => "sampled",
                    ShadowEstimator::Analytic => "analytic",
                },
                crate::render::stats::filter_name(self.state.effective_filter()),
                if method == ViewMethod::TemporalExact {
                    " (exact: unfiltered)"
                } else {
                    ""
                }
            ),
        };
        let mut lines = vec![
            format!(
                "{}  {} {frame}  {}x{}  {time}  shutter {:.0} deg",
                frames.scene().name,
                self.state.method.name(),
                size.width,
                size.height,
                self.state.shutter_deg
            ),
            format!(
                "{:.1} fps  gpu {gpu_total:.1} ms  maps {:.1} MiB  {}",
                self.smoothed_fps,
                stats.map_bytes as f64 / f64::from(1 << 20),
                match self.state.method {
                    // TSM stores depths, no ranges.
                    ViewMethod::Tsm { .. } => String::new(),
                    _ => format!("ranges {}", stats.last_ranges),
                }
            ),
            format!("ms: {}", passes.join("  ")),
        ];
        if let Some(right) = self.state.split {
            lines.push(split_line(self.state.method, right, &stats.last_pass_ms));
        }
        lines.push("H: keys on the terminal".to_owned());
        lines
    }

    /// Poses the scene again where the time or the shutter changed.
    fn update_scene(&mut self) -> anyhow::Result<()> {
        if !self.state.scene_changed {
            return Ok(());
        }
        self.state.scene_changed = false;
        let posed = match &self.options.animation {
            Some(animation) => animation.at(None, self.state.time)?,
            None => self.options.scene.clone(),
        };
        let scene = with_shutter(posed, self.state.shutter_fraction());
        if let Some(frames) = self.frames.as_mut() {
            frames.set_scene(scene, &mut self.counter)?;
        }
        Ok(())
    }

    /// Draws one frame; returns whether the run is over.
    fn redraw(&mut self) -> anyhow::Result<bool> {
        let Some(size) = self.window.as_ref().map(Window::inner_size) else {
            return Ok(false);
        };
        if size.width == 0 || size.height == 0 {
            // Minimized: nothing to present to.
            std::thread::sleep(NO_AREA_WAIT);
            return Ok(false);
        }
        let now = Instant::now();
        if let Some(last) = self.last_frame {
            let seconds = now.duration_since(last).as_secs_f64();
            self.state.advance(seconds);
            if seconds > 0.0 {
                self.smoothed_fps += FPS_SMOOTHING * (1.0 / seconds - self.smoothed_fps);
            }
        }
        self.last_frame = Some(now);
        self.update_scene()?;
        let script = self.options.frames;
        let wanted = self.options.resize;
        let scripted_shot = self.options.screenshot.is_some()
            && script.is_some_and(|n| self.presented + 1 >= u64::from(n));
        let Some(frames) = self.frames.as_ref() else {
            return Ok(false);
        };
        let lines = self.state.overlay.then(|| self.overlay_lines(frames, size));
        let (deferred_light, plane_test_where_still) = self.state.method.light(
            frames.scene(),
            &self.options.settings,
            &self.options.deferred,
        )?;
        // The stochastic frame is the temporal map's: with a TSM method the deferred one is
        // shown (the overlay says so).
        let split = match self.state.split {
            Some(method) => {
                let (light, plane_test_where_still) = method.light(
                    frames.scene(),
                    &self.options.settings,
                    &self.options.deferred,
                )?;
                Some(SplitRequest {
                    method,
                    light,
                    plane_test_where_still,
                })
            }
            None => None,
        };
        // A moving light or camera: the deferred frame only (the overlay says so).
        let forward = (self.state.stochastic && split.is_none() && !moves(frames.scene()))
            .then(|| {
                self.state
                    .method
                    .forward_light(frames.scene(), &self.options.settings)
            })
            .flatten();
        let settings = &self.options.settings;
        let stochastic = forward.map(|_| {
            (
                LightingView {
                    camera: self.state.camera.view((size.width, size.height)),
                    seed: settings.seed,
                    ambient: frames.scene().ambient,
                    estimator: self.state.estimator,
                    filter: self.state.effective_filter(),
                },
                self.options.spp,
            )
        });
        let light = forward.unwrap_or(deferred_light);
        let camera = self.state.camera.clone();
        let view = move |size| camera.view(size);
        let request = FrameRequest {
            window: (size.width, size.height),
            camera: &view,
            method: self.state.method,
            light,
            plane_test_where_still,
            overlay: lines.as_deref(),
            screenshot: scripted_shot || self.state.screenshot,
            stochastic,
            split,
        };
        let Some(frames) = self.frames.as_mut() else {
            return Ok(false);
        };
        let drawn = frames.draw(&request, &mut self.counter)?;
        if let Drawn::NoArea = drawn {
            // Minimized: nothing to present to until the window is restored; no busy loop.
            std::thread::sleep(NO_AREA_WAIT);
            return Ok(false);
        }
        if let Drawn::Presented = drawn {
            self.state.screenshot = false;
            self.presented += 1;
            if self.presented == 1 {
                self.first_presented = Some(Instant::now());
                self.counter.set_phase(Phase::Frames);
                if let (Some((w, h)), Some(window)) = (wanted, self.window.as_ref()) {
                    // The window system answers with a Resized event.
                    let _ = window.request_inner_size(PhysicalSize::new(w, h));
                    self.resize_requested = Some(Instant::now());
                }
            }
        }
        if script.is_none()
            && let Some(shot) = frames.take_screenshot()
        {
            self.shots += 1;
            let path = format!("motion-shadows-view-{:03}.png", self.shots);
            write_rgb8_png(
                std::path::Path::new(&path),
                shot.size.0,
                shot.size.1,
                &shot.rgb,
            )?;
            println!("wrote {path}");
        }
        let Some(n) = script else {
            return Ok(false);
        };
        if self.presented < u64::from(n) {
            return Ok(false);
        }
        match wanted {
            Some(w) if frames.size() != Some(w) => {
                if self
                    .resize_requested
                    .is_some_and(|t| t.elapsed() > RESIZE_WAIT)
                {
                    bail!(
                        "the window system did not resize the window to {}x{} within {} s \
                         (--resize)",
                        w.0,
                        w.1,
                        RESIZE_WAIT.as_secs()
                    );
                }
                Ok(false)
            }
            _ => Ok(true),
        }
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, error: anyhow::Error) {
        if self.error.is_none() {
            self.error = Some(error);
        }
        event_loop.exit();
    }
}

impl ApplicationHandler for Viewer {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_none()
            && let Err(e) = self.start(event_loop)
        {
            self.fail(event_loop, e);
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(_) => {
                if let Some(frames) = self.frames.as_mut() {
                    frames.mark_resized();
                }
            }
            WindowEvent::KeyboardInput {
                event,
                is_synthetic,
                ..
                // Synthetic presses stand for keys already down when the window gained
                // focus: not a press of the user's here (each key acted twice under Xvfb).
            } if event.state == ElementState::Pressed && !is_synthetic => {
                if let Some(action) = action_for_key(&event.logical_key) {
                    self.state.apply(action);
                }
                if self.state.print_keys {
                    self.state.print_keys = false;
                    for line in KEYS {
                        println!("{line}");
                    }
                }
                if self.state.quit {
                    event_loop.exit();
                }
            }
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Left,
                ..
            } => {
                self.dragging = (state == ElementState::Pressed).then_some(self.cursor);
            }
            WindowEvent::CursorMoved { position, .. } => {
                self.cursor = (position.x, position.y);
                if let Some((x, y)) = self.dragging {
                    self.state
                        .camera
                        .orbit((position.x - x) as f32, (position.y - y) as f32);
                    self.dragging = Some(self.cursor);
                }
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => (p.y / 40.0) as f32,
                };
                self.state.camera.dolly(steps);
            }
            WindowEvent::RedrawRequested => match self.redraw() {
                Ok(true) => event_loop.exit(),
                Ok(false) => {
                    if let Some(window) = &self.window {
                        window.request_redraw();
                    }
                }
                Err(e) => self.fail(event_loop, e),
            },
            _ => {}
        }
    }
}

/// Opens the window and runs the viewer until it is closed or its script ends.
pub fn run(options: ViewOptions) -> anyhow::Result<ViewReport> {
    if std::env::var_os("DISPLAY").is_none_or(|d| d.is_empty()) {
        bail!(
            "view needs an X11 display and DISPLAY is not set (without a screen, run it under \
             xvfb-run)"
        );
    }
    let event_loop = EventLoop::new().map_err(|e| {
        anyhow!(
            "the X11 display {:?} could not be opened: {e}",
            std::env::var("DISPLAY").unwrap_or_default()
        )
    })?;
    event_loop.set_control_flow(ControlFlow::Poll);
    if options.frames.is_none() {
        for line in KEYS {
            println!("{line}");
        }
    }
    let mut state = ViewState::new(
        // A moving camera starts where it is at the G-buffer's time, as the offline frame's.
        CameraControl::new(&options.scene.camera.at(options.frame.camera_time)),
        options.method,
        options.tsm_maps,
        options.overlay,
    );
    state.stochastic = options.stochastic;
    state.split = options.split;
    state.estimator = options.settings.shadow_estimator;
    state.filter = options.settings.shadow_filter;
    let mut viewer = Viewer {
        options,
        state,
        frames: None,
        window: None,
        counter: AllocationCounter::default(),
        presented: 0,
        first_presented: None,
        last_frame: None,
        smoothed_fps: 0.0,
        resize_requested: None,
        dragging: None,
        cursor: (0.0, 0.0),
        shots: 0,
        error: None,
        device_name: String::new(),
    };
    event_loop
        .run_app(&mut viewer)
        .map_err(|e| anyhow!("the window's event loop: {e}"))?;
    if let Some(e) = viewer.error.take() {
        return Err(e);
    }
    let Some(mut frames) = viewer.frames.take() else {
        bail!("the viewer closed before its window opened");
    };
    frames.finish_all(&mut viewer.counter)?;
    let seconds = viewer
        .first_presented
        .map_or(0.0, |t| t.elapsed().as_secs_f64());
    let mut report = ViewReport {
        device: viewer.device_name.clone(),
        frames: viewer.presented,
        seconds_after_first: seconds,
        size: frames.size().unwrap_or_default(),
        allocations: viewer.counter.counts(),
        stats: frames.stats().clone(),
        screenshot: frames.take_screenshot(),
        validation_messages: Vec::new(),
    };
    // Read after the teardown: the layer reports objects left alive when the device and
    // instance are destroyed.
    let messages = frames.messages();
    drop(frames);
    drop(viewer.window.take());
    report.validation_messages = messages.lock().map(|m| m.clone()).unwrap_or_default();
    Ok(report)
}

/// Whether the scene's light or camera moves during the shutter: the viewer's stochastic
/// frame does not take either (its lighting pass is set up with both still), its deferred
/// frame takes both.
fn moves(scene: &crate::scene::Scene) -> bool {
    scene.light.moves() || scene.camera.moves()
}
