//! The `motion-shadows` binary's commands.

pub mod args;
pub mod render_cmd;
pub mod summary;
