//! The `motion-shadows` binary's commands.

pub mod animate_cmd;
pub mod args;
pub mod bench_cmd;
pub mod compare_cmd;
pub mod compare_deferred;
pub mod deferred_cmd;
pub mod export_cmd;
pub mod install_hint;
pub mod render_cmd;
pub mod shared;
pub mod summary;
pub mod technique_args;
pub mod unread_options;
pub mod value_parsers;
pub mod view_args;
pub mod view_cmd;

/// With `MOTION_SHADOWS_VALIDATION=1`, a run the validation layer complained about fails.
pub fn validation_clean(ctx: &motion_shadows::gpu::Context) -> anyhow::Result<()> {
    let messages = ctx.validation_messages();
    anyhow::ensure!(
        messages.is_empty(),
        "the Vulkan validation layer reported {} message(s)",
        messages.len()
    );
    Ok(())
}
