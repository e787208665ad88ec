//! A deferred engine with motion-blurred shadows (the crate's library: `deferred.rs` and
//! `deferred/`, read from the top; `gpu.rs` its device, `glsl/` its shaders) renders a box
//! flying and turning over the ground beside a still post, under a spot light and a
//! directional light, three frames in flight.
//!
//! ```sh
//! cargo run -p motion-shadows-deferred-host   # MOTION_SHADOWS_VALIDATION=1: validation on
//! ```
//!
//! Writes `out/deferred_host.png` and prints each light's counts.

use motion_shadows_deferred_host::{deferred, gpu::Gpu};

fn main() -> deferred::Result<()> {
    let gpu = Gpu::new(std::env::var("MOTION_SHADOWS_VALIDATION").is_ok_and(|v| v == "1"))?;
    let (world, width, height) = (deferred::World::demo(), 320, 240);
    // The still meshes never change in place: their static layers are kept.
    let (shadow_size, keep_static_layer, receivers_move) = ((512, 512), true, true);
    let settings = deferred::Settings {
        width,
        height,
        shadow_size,
        keep_static_layer,
        receivers_move,
    };
    let mut engine = deferred::Engine::new(&gpu, &world, settings)?;
    let frame = engine
        .render(&world, 0..4, &|f| f == 3)?
        .pop()
        .ok_or("no frame 3")?;
    for light in 0..world.lights.len() {
        let c = engine.shadow_map(frame.slot, light).read_counters()?;
        println!(
            "light {light}: N_f = {}, N_r = {}",
            c.node_count, c.range_count
        );
    }
    drop(engine); // waits for its frames and frees everything (the library's objects too)
    // Linear radiance to sRGB.
    let encode = |v: f32| match v.clamp(0.0, 1.0) {
        v if v <= 0.003_130_8 => (12.92 * v * 255.0).round() as u8,
        v => ((1.055 * v.powf(1.0 / 2.4) - 0.055) * 255.0).round() as u8,
    };
    let rgb: Vec<u8> = frame
        .radiance
        .iter()
        .flat_map(|p| p[..3].iter().map(|&v| encode(v)))
        .collect();
    std::fs::create_dir_all("out")?;
    let path = "out/deferred_host.png";
    image::save_buffer(path, &rgb, width, height, image::ExtendedColorType::Rgb8)?;
    let in_flight = deferred::FRAMES_IN_FLIGHT;
    println!("frames 0 to 3 at {width}x{height}, {in_flight} in flight: wrote {path}");
    // SAFETY: the engine, and with it everything made on the device, is gone.
    unsafe { gpu.destroy() };
    Ok(())
}
