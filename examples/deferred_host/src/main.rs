//! A deferred engine with motion-blurred shadows (the crate's library, `deferred.rs` and
//! `deferred/`, read from the top; `gpu.rs` its device, `glsl/` its shaders): it renders a few
//! frames of a box flying and turning over the ground beside a still post, under a spot light
//! and a directional light, with three frames in flight.
//!
//! ```sh
//! cargo run -p motion-shadows-deferred-host   # MOTION_SHADOWS_VALIDATION=1: validation on
//! ```
//!
//! Writes `out/deferred_host.png` and prints a summary.

use motion_shadows_deferred_host::{deferred, gpu::Gpu};

use deferred::{Engine, Settings, World};

const FRAMES: u32 = 4;

fn main() -> deferred::Result<()> {
    let validation = std::env::var("MOTION_SHADOWS_VALIDATION").is_ok_and(|v| v == "1");
    let gpu = Gpu::new(validation)?;
    let (world, (width, height)) = (World::demo(), (320, 240));
    let settings = Settings {
        width,
        height,
        shadow_size: (512, 512),
        // The still meshes never change in place.
        keep_static_layer: true,
        receivers_move: true,
    };
    let (last, device) = {
        let mut engine = Engine::new(&gpu, &world, settings)?;
        let frames = engine.render(&world, 0..FRAMES, &|f| f == FRAMES - 1)?;
        let last = frames.into_iter().next_back().ok_or("the last frame was not kept")?;
        (last, engine.context().info().name.clone())
    }; // The engine waits for its frames and frees everything (the library's objects too).
    println!("device:  {device}");
    println!("frames:  {FRAMES} at {width}x{height}, {} in flight", deferred::FRAMES_IN_FLIGHT);
    for (i, (counts, mask)) in last.counters.iter().zip(&last.masks).enumerate() {
        // The mean lit share over the pixels that show a surface.
        let shown: Vec<f32> = (mask.iter().zip(&last.radiance))
            .filter(|(_, r)| r[3] > 0.0)
            .map(|(m, _)| *m)
            .collect();
        let mean = shown.iter().sum::<f32>() / shown.len().max(1) as f32;
        println!(
            "light {i}: N_f = {}, N_r = {}, mean mask {mean:.4}",
            counts.node_count, counts.range_count
        );
    }
    // Linear radiance to sRGB.
    let encode = |v: f32| {
        let v = v.clamp(0.0, 1.0);
        let s = if v <= 0.003_130_8 { 12.92 * v } else { 1.055 * v.powf(1.0 / 2.4) - 0.055 };
        (s * 255.0).round() as u8
    };
    let bytes: Vec<u8> =
        last.radiance.iter().flat_map(|p| [encode(p[0]), encode(p[1]), encode(p[2])]).collect();
    std::fs::create_dir_all("out")?;
    image::save_buffer(
        "out/deferred_host.png",
        &bytes,
        width,
        height,
        image::ExtendedColorType::Rgb8,
    )?;
    println!("wrote out/deferred_host.png");
    // SAFETY: the engine, and with it everything made on the device, is gone.
    unsafe { gpu.destroy() };
    Ok(())
}
