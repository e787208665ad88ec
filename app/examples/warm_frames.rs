//! Renders the default scene several times with one renderer and prints each frame's GPU time
//! per pass: the first frame includes shader compilation, later ones are warm.
//!
//! `cargo run --release --example warm_frames -- [frames] [width] [height] [spp] [samples per chunk]`

use motion_shadows::gpu::{Context, ContextOptions};
use motion_shadows_app::render::{RenderSettings, Renderer};
use motion_shadows_app::scene::{BuiltinOptions, builtin};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<u32> = std::env::args()
        .skip(1)
        .map(|a| a.parse())
        .collect::<Result<_, _>>()?;
    let arg = |i: usize, default: u32| args.get(i).copied().unwrap_or(default);
    let scene = builtin("cubes-toward-light", &BuiltinOptions::default())?;
    let ctx = Context::headless(&ContextOptions::from_env())?;
    let mut renderer = Renderer::new(&ctx)?;
    let settings = RenderSettings {
        width: arg(1, 1024),
        height: arg(2, 768),
        spp: arg(3, 8),
        max_samples_per_chunk: arg(4, 16),
        ..RenderSettings::default()
    };
    for frame in 0..arg(0, 3) {
        let result = renderer.render(&scene, &settings, &mut |_| {})?;
        let passes: Vec<String> = result
            .stats
            .passes
            .iter()
            .map(|p| format!("{} {:.1} ms", p.pass, p.gpu_ms))
            .collect();
        println!("frame {frame}: {}", passes.join(", "));
    }
    Ok(())
}
