//! One-shot command submission: record, submit, wait. Used by the standalone renderer and
//! tests; passes never submit.

use super::context::Context;
use crate::error::{Result, VkContext};
use ash::vk;

/// A primary command buffer from the context's pool and a fence to wait on it.
pub struct OneShot<'a> {
    ctx: &'a Context,
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
}

impl<'a> OneShot<'a> {
    /// A command buffer from the context's pool and an unsignalled fence.
    pub fn new(ctx: &'a Context) -> Result<Self> {
        let pool = ctx.one_shot_lock()?;
        let device = ctx.device();
        let info = vk::CommandBufferAllocateInfo::default()
            .command_pool(*pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: the pool is this device's, made for the context's queue family, and held locked
        // (external synchronization of the pool) until this function returns.
        let cmd =
            unsafe { device.allocate_command_buffers(&info) }.vk("vkAllocateCommandBuffers")?[0];
        // SAFETY: creating an unsignalled fence on the live device has no precondition.
        let fence = match unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) } {
            Ok(f) => f,
            Err(result) => {
                // SAFETY: `cmd` came from `pool`, which is still locked, and was never recorded or
                // submitted.
                unsafe { device.free_command_buffers(*pool, &[cmd]) };
                return Err(crate::Error::Vulkan {
                    call: "vkCreateFence",
                    result,
                });
            }
        };
        Ok(Self { ctx, cmd, fence })
    }

    /// Records with `record`, submits, and waits until the GPU is done. Objects dropped
    /// meanwhile (in `record`, say) are destroyed after the wait, not at once.
    pub fn run(&self, record: impl FnOnce(vk::CommandBuffer) -> Result<()>) -> Result<()> {
        // The pool and queue, for the whole recording, submission and wait. (So a OneShot
        // run inside another's `record` on the same context waits forever: run it after.)
        let _locked = self.ctx.one_shot_lock()?;
        let _under_way = UnderWay::begin(self.ctx);
        let device = self.ctx.device();
        // SAFETY: the pool is locked for the whole run, and the previous run (if any) waited for
        // its fence, so `cmd` and `fence` are not in use by the GPU; resetting is allowed since the
        // pool was made with RESET_COMMAND_BUFFER.
        unsafe {
            device
                .reset_command_buffer(self.cmd, vk::CommandBufferResetFlags::empty())
                .vk("vkResetCommandBuffer")?;
            device.reset_fences(&[self.fence]).vk("vkResetFences")?;
            let begin = vk::CommandBufferBeginInfo::default()
                .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            device
                .begin_command_buffer(self.cmd, &begin)
                .vk("vkBeginCommandBuffer")?;
        }
        let recorded = record(self.cmd);
        // SAFETY: `cmd` is in the recording state: begun above, and `record` receives only its
        // handle (it records into it, it cannot end or free it through this API).
        unsafe { device.end_command_buffer(self.cmd) }.vk("vkEndCommandBuffer")?;
        recorded?;
        let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(self.cmd)];
        let submit = [vk::SubmitInfo2::default().command_buffer_infos(&cmds)];
        // SAFETY: the queue is locked with the pool (no other OneShot submits to it; a host's own
        // use is from_raw's contract), `cmd` was ended, and `fence` was reset above; the wait keeps
        // every object the recording used alive until the GPU is done.
        unsafe {
            device
                .queue_submit2(self.ctx.queue(), &submit, self.fence)
                .vk("vkQueueSubmit2")?;
            device
                .wait_for_fences(&[self.fence], true, u64::MAX)
                .vk("vkWaitForFences")?;
        }
        Ok(())
    }
}

/// A OneShot's recording and run, for retirement (`retire.rs`): a headless context keeps
/// what is dropped meanwhile and destroys it at the end, once the run has waited or failed
/// (an error after the submission has waited for nothing: the fence wait is the last step,
/// and a failed wait leaves the device lost).
struct UnderWay<'a>(&'a Context);

impl<'a> UnderWay<'a> {
    fn begin(ctx: &'a Context) -> Self {
        ctx.shared.retirement().one_shot_begins();
        Self(ctx)
    }
}

impl Drop for UnderWay<'_> {
    fn drop(&mut self) {
        if self.0.shared.retirement().one_shot_ends() {
            // SAFETY: a headless context's queue runs only OneShots, and none is under way:
            // each waited for its work (or never submitted it).
            unsafe { self.0.shared.collect(None) };
        }
    }
}

impl Drop for OneShot<'_> {
    fn drop(&mut self) {
        // The pool exists: this OneShot's command buffer came from it.
        let Ok(pool) = self.ctx.one_shot_lock() else {
            return;
        };
        let device = self.ctx.device();
        // SAFETY: the run (if any) waited for `fence`, so neither the fence nor `cmd` is in use;
        // the pool is locked, and both are freed once, here.
        unsafe {
            device.destroy_fence(self.fence, None);
            device.free_command_buffers(*pool, &[self.cmd]);
        }
    }
}
