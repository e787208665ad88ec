//! Barriers (synchronization2). Buffer hazards take a global memory barrier, which names
//! exactly the stages and accesses that matter, nothing more; images changing layout (the
//! depth-tested shadow maps' attachments) take an image barrier.

use ash::vk;

/// One side of a barrier: pipeline stages and the memory accesses made there.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Access {
    /// Pipeline stages.
    pub stages: vk::PipelineStageFlags2,
    /// Memory accesses in those stages.
    pub access: vk::AccessFlags2,
}

impl Access {
    /// Copies, fills and updates writing.
    pub const TRANSFER_WRITE: Self = Self {
        stages: vk::PipelineStageFlags2::TRANSFER,
        access: vk::AccessFlags2::TRANSFER_WRITE,
    };
    /// Copies reading.
    pub const TRANSFER_READ: Self = Self {
        stages: vk::PipelineStageFlags2::TRANSFER,
        access: vk::AccessFlags2::TRANSFER_READ,
    };
    /// Fragment shaders reading and writing storage.
    pub const FRAGMENT_RW: Self = Self {
        stages: vk::PipelineStageFlags2::FRAGMENT_SHADER,
        access: vk::AccessFlags2::from_raw(
            vk::AccessFlags2::SHADER_STORAGE_READ.as_raw()
                | vk::AccessFlags2::SHADER_STORAGE_WRITE.as_raw(),
        ),
    };
    /// Geometry shaders reading and writing storage (counters).
    pub const GEOMETRY_RW: Self = Self {
        stages: vk::PipelineStageFlags2::GEOMETRY_SHADER,
        access: vk::AccessFlags2::from_raw(
            vk::AccessFlags2::SHADER_STORAGE_READ.as_raw()
                | vk::AccessFlags2::SHADER_STORAGE_WRITE.as_raw(),
        ),
    };
    /// Compute shaders reading and writing storage.
    pub const COMPUTE_RW: Self = Self {
        stages: vk::PipelineStageFlags2::COMPUTE_SHADER,
        access: vk::AccessFlags2::from_raw(
            vk::AccessFlags2::SHADER_STORAGE_READ.as_raw()
                | vk::AccessFlags2::SHADER_STORAGE_WRITE.as_raw(),
        ),
    };
    /// Every shader stage the passes read scene data or the shadow map from.
    pub const ANY_SHADER_READ: Self = Self {
        stages: vk::PipelineStageFlags2::from_raw(
            vk::PipelineStageFlags2::VERTEX_SHADER.as_raw()
                | vk::PipelineStageFlags2::GEOMETRY_SHADER.as_raw()
                | vk::PipelineStageFlags2::FRAGMENT_SHADER.as_raw()
                | vk::PipelineStageFlags2::COMPUTE_SHADER.as_raw(),
        ),
        access: vk::AccessFlags2::from_raw(
            vk::AccessFlags2::SHADER_STORAGE_READ.as_raw()
                | vk::AccessFlags2::UNIFORM_READ.as_raw(),
        ),
    };
    /// Depth tests reading and writing a depth attachment.
    pub const DEPTH_ATTACHMENT: Self = Self {
        stages: vk::PipelineStageFlags2::from_raw(
            vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS.as_raw()
                | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS.as_raw(),
        ),
        access: vk::AccessFlags2::from_raw(
            vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ.as_raw()
                | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE.as_raw(),
        ),
    };
    /// Colour attachments written (and cleared by their load op).
    pub const COLOR_ATTACHMENT_WRITE: Self = Self {
        stages: vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
        access: vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
    };
    /// Nothing: the first use of a resource, or a wait on execution alone.
    pub const NONE: Self = Self {
        stages: vk::PipelineStageFlags2::NONE,
        access: vk::AccessFlags2::NONE,
    };
    /// Indirect dispatch arguments read.
    pub const INDIRECT_READ: Self = Self {
        stages: vk::PipelineStageFlags2::DRAW_INDIRECT,
        access: vk::AccessFlags2::INDIRECT_COMMAND_READ,
    };
    /// Compute shaders sampling images (a host's G-buffer, a depth map).
    pub const COMPUTE_SAMPLED_READ: Self = Self {
        stages: vk::PipelineStageFlags2::COMPUTE_SHADER,
        access: vk::AccessFlags2::SHADER_SAMPLED_READ,
    };
    /// The host reading mapped memory.
    pub const HOST_READ: Self = Self {
        stages: vk::PipelineStageFlags2::HOST,
        access: vk::AccessFlags2::HOST_READ,
    };

    /// Both sides merged, for a barrier that orders several earlier or later uses at once.
    pub const fn and(self, other: Self) -> Self {
        Self {
            stages: vk::PipelineStageFlags2::from_raw(self.stages.as_raw() | other.stages.as_raw()),
            access: vk::AccessFlags2::from_raw(self.access.as_raw() | other.access.as_raw()),
        }
    }
}

/// Makes the memory accesses `before` visible to `after`.
///
/// Unsafe to call: `cmd` is a raw handle the function cannot check.
///
/// ```compile_fail,E0133
/// # use motion_shadows::{ash, ash::vk, gpu::{Access, memory_barrier}};
/// # fn f(device: &ash::Device, cmd: vk::CommandBuffer) {
/// memory_barrier(device, cmd, Access::TRANSFER_WRITE, Access::HOST_READ);
/// # }
/// ```
///
/// # Safety
/// `cmd` is a command buffer of `device` in the recording state, and the stages in `before`
/// and `after` are supported by its queue family (and, inside a render pass, allowed there).
pub unsafe fn memory_barrier(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    before: Access,
    after: Access,
) {
    let barrier = [vk::MemoryBarrier2::default()
        .src_stage_mask(before.stages)
        .src_access_mask(before.access)
        .dst_stage_mask(after.stages)
        .dst_access_mask(after.access)];
    let dependency = vk::DependencyInfo::default().memory_barriers(&barrier);
    // SAFETY: the caller's contract.
    unsafe { device.cmd_pipeline_barrier2(cmd, &dependency) };
}

/// Moves `range` of `image` from layout `old` to `new`, ordering the accesses `before` ahead of
/// `after`. `old` = UNDEFINED discards the contents (a pass that clears them anyway).
///
/// # Safety
/// As [`memory_barrier`], outside a render pass; `image` is an image of `device` that
/// outlives the execution of `cmd`, `range` lies within it, and `old` is its layout in
/// `range` when the barrier executes (or UNDEFINED).
pub unsafe fn image_barrier(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    image: vk::Image,
    range: vk::ImageSubresourceRange,
    (old, new): (vk::ImageLayout, vk::ImageLayout),
    before: Access,
    after: Access,
) {
    let barrier = [vk::ImageMemoryBarrier2::default()
        .src_stage_mask(before.stages)
        .src_access_mask(before.access)
        .dst_stage_mask(after.stages)
        .dst_access_mask(after.access)
        .old_layout(old)
        .new_layout(new)
        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .image(image)
        .subresource_range(range)];
    let dependency = vk::DependencyInfo::default().image_memory_barriers(&barrier);
    // SAFETY: the caller's contract.
    unsafe { device.cmd_pipeline_barrier2(cmd, &dependency) };
}
