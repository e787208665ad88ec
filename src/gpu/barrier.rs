//! Global memory barriers (synchronization2). The passes only ever need buffer hazards, so a
//! global barrier names exactly the stages and accesses that matter, nothing more.

use ash::vk;

/// One side of a barrier: pipeline stages and the memory accesses made there.
#[derive(Debug, Clone, Copy)]
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
    /// Indirect dispatch arguments read.
    pub const INDIRECT_READ: Self = Self {
        stages: vk::PipelineStageFlags2::DRAW_INDIRECT,
        access: vk::AccessFlags2::INDIRECT_COMMAND_READ,
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
pub fn memory_barrier(device: &ash::Device, cmd: vk::CommandBuffer, before: Access, after: Access) {
    let barrier = [vk::MemoryBarrier2::default()
        .src_stage_mask(before.stages)
        .src_access_mask(before.access)
        .dst_stage_mask(after.stages)
        .dst_access_mask(after.access)];
    let dependency = vk::DependencyInfo::default().memory_barriers(&barrier);
    unsafe { device.cmd_pipeline_barrier2(cmd, &dependency) };
}
