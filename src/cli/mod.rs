//! The `motion-shadows` binary's commands.

pub mod args;
pub mod bench_cmd;
pub mod compare_cmd;
pub mod render_cmd;
pub mod summary;
