//! What every buffer, image and pipeline holds on to: the device, the allocator and the
//! retirement of dropped objects, and (for a headless context) the instance, destroyed in
//! the right order once the last of them is gone.

use crate::gpu::debug::{MessageSink, Messenger};
use crate::gpu::retire::{Doomed, Retirement};
use gpu_allocator::vulkan::Allocator;
use std::mem::ManuallyDrop;
use std::sync::{Arc, Mutex};

/// Objects that must outlive every buffer and pipeline: freed last, in the right order
/// (retired objects, then the allocator, before the device; the device before the instance).
pub(crate) struct Shared {
    pub device: ash::Device,
    /// maxPushConstantsSize: pipeline layouts are checked against it.
    pub max_push_constants_size: u32,
    /// The context's own allocator, or the host's
    /// ([`crate::gpu::Context::from_raw_with_allocator`]).
    pub allocator: ManuallyDrop<Arc<Mutex<Allocator>>>,
    pub(super) retirement: Retirement,
    /// The debug check of declared accesses (off unless enabled).
    pub access_check: crate::gpu::AccessCheck,
    pub(super) owned: Option<Owned>,
}

impl Shared {
    /// Destroys `doomed` once no pending work can use it (see `retire.rs`).
    pub(crate) fn retire(&self, doomed: Doomed) {
        // SAFETY: objects made on this device, from this allocator, retired once (by their
        // Drop).
        unsafe {
            self.retirement
                .retire(doomed, &self.device, &self.allocator)
        };
    }

    /// Destroys what waits for frames up to `completed` (everything: `None`).
    ///
    /// # Safety
    /// Those frames' work has completed (`None`: no work is pending).
    pub(crate) unsafe fn collect(&self, completed: Option<u64>) -> usize {
        // SAFETY: the caller's contract.
        unsafe {
            self.retirement
                .collect(completed, &self.device, &self.allocator)
        }
    }

    pub(crate) fn retirement(&self) -> &Retirement {
        &self.retirement
    }
}

pub(super) struct Owned {
    pub(super) _entry: ash::Entry,
    pub(super) instance: ash::Instance,
    pub(super) messenger: Option<Messenger>,
    /// The sink of the messenger chained into VkInstanceCreateInfo, which the layer also uses
    /// during vkDestroyInstance: freed only after that.
    pub(super) creation_sink: *mut MessageSink,
}

// SAFETY: the creation sink is only touched by the layer's callback (behind its mutex) and
// freed once, in Shared::drop.
unsafe impl Send for Owned {}
// SAFETY: shared references to Owned expose no method that touches the sink or the instance; only
// Shared::drop (which has &mut) destroys them, so sharing it between threads races on nothing.
unsafe impl Sync for Owned {}

impl Drop for Shared {
    fn drop(&mut self) {
        // SAFETY: every resource holding an Arc<Shared> is gone, and no work is pending (the
        // contracts of `from_raw` and of a headless context's drop, which waits): what waits
        // for its frame can go. The allocator must be dropped before the device is destroyed
        // (it frees its memory blocks then); a host's allocator stays with the host.
        unsafe {
            self.collect(None);
            ManuallyDrop::drop(&mut self.allocator);
        }
        if let Some(owned) = self.owned.take() {
            // SAFETY: `owned` holds the instance and device this context created (never a host's:
            // `owned` is None for from_raw). The allocator was dropped and retired objects
            // destroyed just above, so nothing made on the device is left; the messenger goes
            // before its instance, and the creation sink is freed after vkDestroyInstance, the last
            // call that may report through it, exactly once since `owned` was taken.
            unsafe {
                self.device.destroy_device(None);
                drop(owned.messenger);
                owned.instance.destroy_instance(None);
                drop(Box::from_raw(owned.creation_sink));
            }
        }
    }
}
