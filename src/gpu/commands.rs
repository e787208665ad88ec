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
        let device = ctx.device();
        let info = vk::CommandBufferAllocateInfo::default()
            .command_pool(ctx.command_pool())
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        let cmd =
            unsafe { device.allocate_command_buffers(&info) }.vk("vkAllocateCommandBuffers")?[0];
        let fence = match unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) } {
            Ok(f) => f,
            Err(result) => {
                unsafe { device.free_command_buffers(ctx.command_pool(), &[cmd]) };
                return Err(crate::Error::Vulkan {
                    call: "vkCreateFence",
                    result,
                });
            }
        };
        Ok(Self { ctx, cmd, fence })
    }

    /// Records with `record`, submits, and waits until the GPU is done.
    pub fn run(&self, record: impl FnOnce(vk::CommandBuffer) -> Result<()>) -> Result<()> {
        let device = self.ctx.device();
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
        unsafe { device.end_command_buffer(self.cmd) }.vk("vkEndCommandBuffer")?;
        recorded?;
        let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(self.cmd)];
        let submit = [vk::SubmitInfo2::default().command_buffer_infos(&cmds)];
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

impl Drop for OneShot<'_> {
    fn drop(&mut self) {
        let device = self.ctx.device();
        unsafe {
            device.destroy_fence(self.fence, None);
            device.free_command_buffers(self.ctx.command_pool(), &[self.cmd]);
        }
    }
}
