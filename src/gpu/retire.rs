//! Retirement: objects the GPU may still use are destroyed after the frame that may use them
//! has completed, never at once.
//!
//! Dropping a [`super::Buffer`], [`super::Image`], [`super::Pipeline`], descriptor pool or
//! query pool hands its handles here. A host's context ([`super::Context::from_raw`]) always
//! retires them, tagged with the frame the host last said it records
//! ([`super::Context::begin_frame`]), and destroys them when the host says that frame has
//! completed ([`super::Context::collect`]). A headless context submits only through
//! [`super::OneShot`], which waits: it destroys at once, except while a `OneShot` records or
//! runs, whose end destroys what was dropped meanwhile.
//!
//! So a safe function that replaces buffers (`TemporalShadowMap::reserve`, `grow_to_fit`),
//! or a `?` that drops a map a pending frame uses, never frees memory the GPU still reads.

use ash::vk;
use gpu_allocator::vulkan::{Allocation, Allocator};
use std::sync::Mutex;

/// One Vulkan handle to destroy.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Handle {
    Buffer(vk::Buffer),
    Image(vk::Image),
    ImageView(vk::ImageView),
    Pipeline(vk::Pipeline),
    PipelineLayout(vk::PipelineLayout),
    DescriptorPool(vk::DescriptorPool),
    DescriptorSetLayout(vk::DescriptorSetLayout),
    Sampler(vk::Sampler),
    QueryPool(vk::QueryPool),
}

/// What one dropped object leaves to destroy: its handles, in order, and its memory.
pub(crate) struct Doomed {
    pub handles: Vec<Handle>,
    pub allocation: Option<Allocation>,
    /// For the allocator's error message.
    pub name: String,
}

impl Doomed {
    /// Handles without memory.
    pub fn handles(handles: Vec<Handle>) -> Self {
        Self {
            handles,
            allocation: None,
            name: String::new(),
        }
    }

    /// Destroys the handles and frees the memory.
    ///
    /// # Safety
    /// No pending work uses the handles; they are `device`'s and the allocation
    /// `allocator`'s.
    unsafe fn destroy(self, device: &ash::Device, allocator: &Mutex<Allocator>) {
        for handle in self.handles {
            // SAFETY: the caller's contract.
            unsafe {
                match handle {
                    Handle::Buffer(h) => device.destroy_buffer(h, None),
                    Handle::Image(h) => device.destroy_image(h, None),
                    Handle::ImageView(h) => device.destroy_image_view(h, None),
                    Handle::Pipeline(h) => device.destroy_pipeline(h, None),
                    Handle::PipelineLayout(h) => device.destroy_pipeline_layout(h, None),
                    Handle::DescriptorPool(h) => device.destroy_descriptor_pool(h, None),
                    Handle::DescriptorSetLayout(h) => device.destroy_descriptor_set_layout(h, None),
                    Handle::Sampler(h) => device.destroy_sampler(h, None),
                    Handle::QueryPool(h) => device.destroy_query_pool(h, None),
                }
            }
        }
        if let Some(allocation) = self.allocation {
            match allocator.lock() {
                Ok(mut allocator) => {
                    if let Err(e) = allocator.free(allocation) {
                        log::error!("freeing {}: {e}", self.name);
                    }
                }
                Err(_) => log::error!("freeing {}: the allocator's mutex is poisoned", self.name),
            }
        }
    }
}

#[derive(Default)]
struct State {
    /// The frame the host last said it records ([`super::Context::begin_frame`]).
    frame: u64,
    /// A host's context ([`super::Context::from_raw`]): its queue has work the library
    /// does not see.
    host: bool,
    /// The host said which frame it records.
    frames: bool,
    /// OneShots recording or running on a headless context.
    one_shots: u32,
    /// Objects waiting for their frame, with that frame.
    waiting: Vec<(u64, Doomed)>,
    /// The latest frame the host said completed ([`super::Context::collect`]): its commands
    /// were submitted and ran, which is what keeping a static layer drawn then waits for.
    completed: Option<u64>,
}

/// The queue of objects waiting for their frame to complete.
pub(crate) struct Retirement {
    state: Mutex<State>,
}

impl Retirement {
    /// For a headless context (`host`: false) or a host's (true).
    pub fn new(host: bool) -> Self {
        Self {
            state: Mutex::new(State {
                host,
                ..State::default()
            }),
        }
    }

    fn state(&self) -> std::sync::MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Destroys `doomed` at once if no pending work can use it, else keeps it for
    /// [`Self::collect`].
    ///
    /// # Safety
    /// The handles are `device`'s, the allocation `allocator`'s; each is retired once.
    pub unsafe fn retire(
        &self,
        doomed: Doomed,
        device: &ash::Device,
        allocator: &Mutex<Allocator>,
    ) {
        let mut state = self.state();
        if state.host || state.frames || state.one_shots > 0 {
            let frame = state.frame;
            state.waiting.push((frame, doomed));
        } else {
            drop(state);
            // SAFETY: a headless context with no OneShot under way has no pending work.
            unsafe { doomed.destroy(device, allocator) };
        }
    }

    /// Notes that the host now records `frame`.
    pub fn begin_frame(&self, frame: u64) {
        let mut state = self.state();
        state.frames = true;
        state.frame = state.frame.max(frame);
    }

    /// Takes the objects retired during frames up to `completed` (all: `None`).
    fn take(&self, completed: Option<u64>) -> Vec<Doomed> {
        let mut state = self.state();
        let (done, waiting) = std::mem::take(&mut state.waiting)
            .into_iter()
            .partition(|(frame, _)| completed.is_none_or(|c| *frame <= c));
        state.waiting = waiting;
        done.into_iter().map(|(_, d)| d).collect()
    }

    /// Destroys the objects retired during frames up to `completed` (all: `None`); returns
    /// how many.
    ///
    /// # Safety
    /// Every submission of those frames has completed (`None`: no work is pending at all).
    pub unsafe fn collect(
        &self,
        completed: Option<u64>,
        device: &ash::Device,
        allocator: &Mutex<Allocator>,
    ) -> usize {
        // Only the host's word counts: `None` (nothing pending) says nothing of whether a
        // frame's commands were ever submitted.
        if let Some(frame) = completed {
            let mut state = self.state();
            state.completed = Some(state.completed.map_or(frame, |c| c.max(frame)));
        }
        let done = self.take(completed);
        let count = done.len();
        for doomed in done {
            // SAFETY: the caller's contract.
            unsafe { doomed.destroy(device, allocator) };
        }
        count
    }

    /// The latest frame the host said completed (None before the first
    /// [`super::Context::collect`]).
    pub fn completed(&self) -> Option<u64> {
        self.state().completed
    }

    /// Objects waiting for their frame.
    pub fn waiting(&self) -> usize {
        self.state().waiting.len()
    }

    /// A OneShot begins recording (headless contexts retire until it ends).
    pub fn one_shot_begins(&self) {
        self.state().one_shots += 1;
    }

    /// A OneShot ended; returns whether no work is pending now: it was the last under way
    /// on a headless context, whose queue only OneShots use and wait for.
    pub fn one_shot_ends(&self) -> bool {
        let mut state = self.state();
        state.one_shots -= 1;
        state.one_shots == 0 && !state.host
    }
}
