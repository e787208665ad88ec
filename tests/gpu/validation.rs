//! The validation layer is really on in these tests: a deliberate misuse is reported.
//! (Every other test asserts that nothing was reported, which would pass trivially if the
//! layer were off.)

use crate::support::gpu::context;
use ash::vk;

#[test]
fn validation_layer_reports_a_deliberate_misuse() {
    let ctx = context();
    let device = ctx.device();
    // SAFETY: the pool is made for the context's own queue family, the command buffer is only
    // recorded (never submitted), and both are destroyed before the context; the one invalid
    // barrier is what the test wants the validation layer to report, and a driver never acts on an
    // unsubmitted command buffer.
    unsafe {
        let pool = device
            .create_command_pool(
                &vk::CommandPoolCreateInfo::default().queue_family_index(ctx.queue_family()),
                None,
            )
            .unwrap();
        let cmd = device
            .allocate_command_buffers(
                &vk::CommandBufferAllocateInfo::default()
                    .command_pool(pool)
                    .command_buffer_count(1),
            )
            .unwrap()[0];
        device
            .begin_command_buffer(cmd, &vk::CommandBufferBeginInfo::default())
            .unwrap();
        // An access the stage cannot make (shader writes in the transfer stage): invalid, but
        // harmless to the driver, which never acts on it (recorded, never submitted).
        let barrier = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::TRANSFER)
            .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
            .dst_access_mask(vk::AccessFlags2::SHADER_STORAGE_READ)];
        device.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().memory_barriers(&barrier),
        );
        device.end_command_buffer(cmd).unwrap();
        device.destroy_command_pool(pool, None);
    }
    let messages = ctx.validation_messages();
    assert!(
        messages.iter().any(|m| m.contains("srcAccessMask")),
        "the validation layer did not report the misuse: {messages:?}"
    );
}
