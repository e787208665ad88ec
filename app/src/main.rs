use motion_shadows_app::cli::args::{Cli, Command, RenderArgs, SceneCommand};
use motion_shadows_app::scene::limits::MAX_ERROR_CHARS;
use motion_shadows_app::scene::{BUILTIN_NAMES, clip};
use std::process::ExitCode;

fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        None => motion_shadows_app::cli::render_cmd::run(&RenderArgs::default()),
        Some(Command::Render(args)) => motion_shadows_app::cli::render_cmd::run(&args),
        Some(Command::Animate(args)) => motion_shadows_app::cli::animate_cmd::run(&args),
        Some(Command::Compare(args)) => motion_shadows_app::cli::compare_cmd::run(&args),
        Some(Command::Bench(args)) => motion_shadows_app::cli::bench_cmd::run(&args),
        Some(Command::View(args)) => motion_shadows_app::cli::view_cmd::run(&args),
        Some(Command::Scene(SceneCommand::List)) => {
            for name in BUILTIN_NAMES {
                println!("{name}");
            }
            Ok(())
        }
        Some(Command::Scene(SceneCommand::Export { name, out, random })) => {
            motion_shadows_app::cli::export_cmd::run(&name, out.as_deref(), &random)
        }
    }
}

/// Prints the error and its causes, each clipped: a cause may quote user input (a field
/// name, a path) of any length, and an error message must stay readable.
fn main() -> ExitCode {
    match run(Cli::parse_recording_given()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("Error: {}", clip(&error.to_string(), MAX_ERROR_CHARS));
            let causes: Vec<_> = error.chain().skip(1).collect();
            if !causes.is_empty() {
                eprintln!("\nCaused by:");
                for (i, cause) in causes.iter().take(8).enumerate() {
                    eprintln!("    {i}: {}", clip(&cause.to_string(), MAX_ERROR_CHARS));
                }
            }
            if let Some(hint) = motion_shadows_app::cli::install_hint::for_chain(&error) {
                eprintln!("\nTo fix: {hint}");
            }
            ExitCode::FAILURE
        }
    }
}
