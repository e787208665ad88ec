use clap::Parser;
use motion_shadows_app::cli::args::{Cli, Command, RenderArgs, SceneCommand};
use motion_shadows_app::cli::render_cmd::builtin_options;
use motion_shadows_app::scene::{BUILTIN_NAMES, builtin_file, scene_to_json};

fn main() -> anyhow::Result<()> {
    let cli = Cli::parse();
    match cli.command {
        None => motion_shadows_app::cli::render_cmd::run(&RenderArgs::default()),
        Some(Command::Render(args)) => motion_shadows_app::cli::render_cmd::run(&args),
        Some(Command::Compare(args)) => motion_shadows_app::cli::compare_cmd::run(&args),
        Some(Command::Bench(args)) => motion_shadows_app::cli::bench_cmd::run(&args),
        Some(Command::Scene(SceneCommand::List)) => {
            for name in BUILTIN_NAMES {
                println!("{name}");
            }
            Ok(())
        }
        Some(Command::Scene(SceneCommand::Export { name, out, random })) => {
            let json = scene_to_json(&builtin_file(&name, &builtin_options(&random))?);
            match out {
                Some(path) => std::fs::write(&path, json)
                    .map_err(|e| anyhow::anyhow!("writing {}: {e}", path.display())),
                None => {
                    println!("{json}");
                    Ok(())
                }
            }
        }
    }
}
