//! A deferred engine with motion-blurred shadows: the engine brings its own Vulkan device,
//! geometry, G-buffer (with world-space motion: this frame's position minus last frame's, and
//! each pixel's triangle id, which the mask needs for moving receivers),
//! frame loop (three frames in flight) and shading, and motion-shadows adds a temporal shadow
//! map per light and a visibility mask per light that follows each receiver along its motion
//! over the shutter. The engine is `deferred.rs` beside this
//! file and its parts in `deferred/` (the tests drive the same code, through this crate's
//! library); read it from the top.
//! `gpu.rs` is the engine's device, `glsl/` its shaders.
//!
//! ```sh
//! cargo run -p motion-shadows-deferred-host   # MOTION_SHADOWS_VALIDATION=1: validation layer on
//! ```
//!
//! Writes `out/deferred_host.png` and prints a summary.

// The engine's device and the engine, the crate's library: the tests
// (`tests/gpu/deferred_host.rs`, `app/tests/gpu/deferred_host.rs`) drive the same code.
use motion_shadows_deferred_host::{deferred, gpu::Gpu};

use deferred::{Engine, FrameOutput, Settings, ShadowLookup, World};
use std::path::Path;
use std::time::Instant;

const WIDTH: u32 = 320;
const HEIGHT: u32 = 240;
const FRAMES: u32 = 4;

fn main() -> Result<(), deferred::Error> {
    let start = Instant::now();
    let validation = std::env::var("MOTION_SHADOWS_VALIDATION").is_ok_and(|v| v == "1");
    let gpu = Gpu::new(validation)?;
    // SAFETY: the physical device is the instance's.
    let props = unsafe { gpu.instance.get_physical_device_properties(gpu.physical) };
    let world = World::demo();
    let settings = Settings {
        width: WIDTH,
        height: HEIGHT,
        shadow_size: (512, 512),
        lookup: ShadowLookup::MaskImages,
        // The static meshes never change in place and the lights stay put.
        keep_static_layer: true,
        receivers_move: true,
    };
    let (last, include_path, layer_builds) = {
        let mut engine = Engine::new(&gpu, &world, settings)?;
        // The casters move between frames; only the last frame is kept (written to disk).
        let last = engine
            .render(&world, 0..FRAMES, &|f| f == FRAMES - 1)?
            .pop()
            .ok_or("the last frame was not kept")?;
        // The same frame once more, shaded by the engine's own shader calling
        // `ms_lit_fraction` from the library's GLSL include instead of reading the masks.
        engine.set_lookup(ShadowLookup::LitFractionInShader);
        let include_path = engine
            .render(&world, FRAMES - 1..FRAMES, &|_| true)?
            .pop()
            .ok_or("the frame was not kept")?;
        // Each frame-in-flight slot's map per light: how often its static layer was drawn.
        let layer_builds: Vec<u32> = (0..deferred::FRAMES_IN_FLIGHT)
            .flat_map(|slot| (0..world.lights.len()).map(move |light| (slot, light)))
            .map(|(slot, light)| engine.shadow_map(slot, light).static_layer_builds())
            .collect();
        (last, include_path, layer_builds)
    }; // The engine waits for its frames and frees everything (the library's objects too).

    let png = Path::new("out").join("deferred_host.png");
    write_png(&png, &last)?;

    println!(
        "device:  {:?}",
        props.device_name_as_c_str().unwrap_or(c"?")
    );
    println!(
        "frames:  {FRAMES} at {WIDTH}x{HEIGHT}, {} in flight",
        deferred::FRAMES_IN_FLIGHT
    );
    for (i, (counts, mask)) in last.counters.iter().zip(&last.masks).enumerate() {
        // The mean lit fraction over the pixels that show a surface.
        let (sum, n) = mask
            .iter()
            .zip(&last.radiance)
            .filter(|(_, r)| r[3] > 0.0)
            .fold((0.0f64, 0usize), |(s, n), (m, _)| {
                (s + f64::from(*m), n + 1)
            });
        println!(
            "light {i}: N_f = {}, N_r = {}, mean mask {:.4}",
            counts.node_count,
            counts.range_count,
            sum / n.max(1) as f64
        );
    }
    let difference = last
        .radiance
        .iter()
        .zip(&include_path.radiance)
        .flat_map(|(a, b)| (0..3).map(move |c| (a[c] - b[c]).abs()))
        .fold(0.0f32, f32::max);
    println!("masks vs ms_lit_fraction in the engine's shader: max difference {difference:.2e}");
    println!(
        "static layers drawn per map ({} slots x {} lights) over {} frames: {layer_builds:?}",
        deferred::FRAMES_IN_FLIGHT,
        world.lights.len(),
        FRAMES + 1
    );
    println!(
        "wrote {} in {:.2} s",
        png.display(),
        start.elapsed().as_secs_f64()
    );

    // SAFETY: the engine, and with it everything made on the device, is gone.
    unsafe { gpu.destroy() };
    Ok(())
}

/// Linear radiance to an sRGB PNG: clamp to [0, 1], then the sRGB transfer curve.
fn write_png(path: &Path, frame: &FrameOutput) -> Result<(), deferred::Error> {
    let encode = |v: f32| {
        let v = v.clamp(0.0, 1.0);
        let s = if v <= 0.003_130_8 {
            12.92 * v
        } else {
            1.055 * v.powf(1.0 / 2.4) - 0.055
        };
        (s * 255.0).round() as u8
    };
    let bytes: Vec<u8> = frame
        .radiance
        .iter()
        .flat_map(|p| [encode(p[0]), encode(p[1]), encode(p[2])])
        .collect();
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    image::save_buffer(path, &bytes, WIDTH, HEIGHT, image::ExtendedColorType::Rgb8)?;
    Ok(())
}
