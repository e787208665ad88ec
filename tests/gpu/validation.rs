//! The validation layer is really on in these tests: a deliberate misuse is reported.
//! (Every other test asserts that nothing was reported, which would pass trivially if the
//! layer were off.)

use crate::support::gpu::context;
use ash::vk;
use motion_shadows::gpu::{Buffer, BufferUsage};

#[test]
fn validation_layer_reports_a_deliberate_misuse() {
    let ctx = context();
    let device = ctx.device();
    let buffer = Buffer::new(&ctx, "misused", 64, BufferUsage::Storage).unwrap();
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
        // dstOffset must be a multiple of 4: recorded, never submitted.
        device.cmd_fill_buffer(cmd, buffer.raw(), 2, 4, 0);
        device.end_command_buffer(cmd).unwrap();
        device.destroy_command_pool(pool, None);
    }
    let messages = ctx.validation_messages();
    assert!(
        messages.iter().any(|m| m.contains("vkCmdFillBuffer")),
        "the validation layer did not report the misuse: {messages:?}"
    );
}
