//! The window and its event loop (winit, X11): the GPU state is made once the window exists,
//! a frame is drawn on every redraw, a resize marks the swapchain stale, a minimized window
//! draws nothing, Escape or closing the window ends the run. A scripted run (`--frames`)
//! ends by itself after its frames (and its resize, when asked).

use super::allocations::{AllocationCounter, Phase};
use super::device::{ViewDevice, ViewInstance};
use super::frame_loop::{Drawn, FrameLoop};
use super::{ViewOptions, ViewReport};
use anyhow::{Context as _, anyhow, bail};
use std::time::{Duration, Instant};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, KeyEvent, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{Key, NamedKey};
use winit::raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::window::{Window, WindowId};

/// How long a scripted run waits past its frames for the window system to resize.
const RESIZE_WAIT: Duration = Duration::from_secs(20);

struct Viewer {
    options: ViewOptions,
    /// Dropped before the window: the surface is made on it.
    frames: Option<FrameLoop>,
    window: Option<Window>,
    counter: AllocationCounter,
    presented: u64,
    /// When the first frame was presented (the frame rate counts the frames after it).
    first_presented: Option<Instant>,
    resize_requested: Option<Instant>,
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
        let frames = FrameLoop::new(
            gpu,
            self.options.scene.clone(),
            self.options.light.clone(),
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

    /// Draws one frame; returns whether the run is over.
    fn redraw(&mut self) -> anyhow::Result<bool> {
        let (Some(window), Some(frames)) = (self.window.as_ref(), self.frames.as_mut()) else {
            return Ok(false);
        };
        let size = window.inner_size();
        if size.width == 0 || size.height == 0 {
            // Minimized: nothing to present to.
            return Ok(false);
        }
        let script = self.options.frames;
        let wanted = self.options.resize;
        let screenshot =
            self.options.screenshot.is_some() && script.is_some_and(|n| self.presented + 1 >= u64::from(n));
        match frames.draw((size.width, size.height), screenshot, &mut self.counter)? {
            Drawn::Skipped => {}
            Drawn::Presented => {
                self.presented += 1;
                if self.presented == 1 {
                    self.first_presented = Some(Instant::now());
                    self.counter.set_phase(Phase::Frames);
                    if let Some((w, h)) = wanted {
                        // The window system answers with a Resized event.
                        let _ = window.request_inner_size(PhysicalSize::new(w, h));
                        self.resize_requested = Some(Instant::now());
                    }
                }
            }
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
                event:
                    KeyEvent {
                        logical_key: Key::Named(NamedKey::Escape),
                        state: ElementState::Pressed,
                        ..
                    },
                ..
            } => event_loop.exit(),
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
        anyhow!("the X11 display {:?} could not be opened: {e}", std::env::var("DISPLAY"))
    })?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut viewer = Viewer {
        options,
        frames: None,
        window: None,
        counter: AllocationCounter::default(),
        presented: 0,
        first_presented: None,
        resize_requested: None,
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
    frames.finish_all()?;
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
