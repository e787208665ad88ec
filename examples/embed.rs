//! Embedding motion-shadows in a host engine's own Vulkan setup.
//!
//! The "host" (`tests/support/host.rs`, shared with the GPU tests) creates its own
//! `ash::Entry`, instance and Vulkan 1.3 device with exactly the features that
//! [`Context::from_raw`] lists, plus its own command pool, command buffer and fence. This
//! example wraps those handles with `Context::from_raw`, uploads the default scene, creates
//! the collection, generation and lighting passes, records all three into the host's command
//! buffer, and submits it on the host's queue with the host's fence: the library never
//! creates a device, submits or waits here. When the temporal shadow map's buffers were too
//! small (the counters say so after the submission), it grows them and records the frame
//! again. Finally it reads the radiance back, prints N_f, N_r and the mean radiance, writes
//! `out/embed.png`, and tears everything down: library objects first, then the host's
//! device, then its instance.
//!
//! Run it with
//!
//! ```sh
//! cargo run --release --example embed              # 1024x768, 8 spp, seed 1
//! cargo run --release --example embed -- 640 480 4 # width height spp
//! ```
//!
//! `MOTION_SHADOWS_VALIDATION=1` turns on the Khronos validation layer (with synchronization
//! validation) on the host's instance; the example then fails if the layer reports anything.

#[allow(dead_code)]
#[path = "../tests/support/host.rs"]
mod host;

use host::Host;
use motion_shadows::gpu::{Buffer, BufferUsage, Context};
use motion_shadows_app::output::{RadianceImage, auto_exposure, write_png};
use motion_shadows_app::render::upload;
use motion_shadows_app::scene::{BuiltinOptions, builtin};
use motion_shadows::technique::{
    CollectionPass, FrameInputs, FrameParams, FrameSettings, GenerationPass, LightingPass,
    LightingTarget, MAX_SAMPLES_PER_CHUNK, SceneGeometry, ShadowSource, TemporalShadowMap,
};
use std::error::Error;
use std::path::Path;

type Res<T> = Result<T, Box<dyn Error>>;

fn main() -> Res<()> {
    let args: Vec<u32> = std::env::args()
        .skip(1)
        .map(|a| a.parse())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("arguments are [width height spp]: {e}"))?;
    let arg = |i: usize, default: u32| args.get(i).copied().unwrap_or(default);
    let (width, height, spp) = (arg(0, 1024), arg(1, 768), arg(2, 8));
    if width == 0 || height == 0 || !(1..=64).contains(&spp) {
        return Err(format!("{width}x{height} at {spp} spp: sides must be > 0, spp 1..=64").into());
    }
    let validation = std::env::var("MOTION_SHADOWS_VALIDATION").is_ok_and(|v| v == "1");

    // The host engine's own Vulkan objects.
    let host = Host::new(validation)?;
    println!(
        "host device: {} (validation {})",
        host.device_name,
        if validation { "on" } else { "off" }
    );
    // Every library object lives and dies inside `frame`.
    let result = frame(&host, width, height, spp);
    let messages = host.validation_messages();
    // The host's device and instance go last (Host's Drop), after the library is gone.
    drop(host);
    result?;
    if !messages.is_empty() {
        return Err(format!(
            "the validation layer reported {} message(s):\n{}",
            messages.len(),
            messages.join("\n")
        )
        .into());
    }
    Ok(())
}

fn frame(host: &Host, width: u32, height: u32, spp: u32) -> Res<()> {
    let seed = 1;
    // SAFETY: the host created `device` from `physical` of `instance`, Vulkan 1.3, with a
    // graphics+compute queue of `queue_family` and exactly the features the contract lists;
    // the host outlives `ctx` and everything made from it (all dropped at the end of this
    // function, before `host` is).
    let ctx = unsafe {
        Context::from_raw(
            &host.instance,
            host.physical,
            host.device.clone(),
            host.queue_family,
            host.queue,
        )
    }?;

    // Scene -> GPU buffers, camera and light -> frame parameters (as `render::Renderer` does).
    let scene = builtin("cubes-toward-light", &BuiltinOptions::default())?;
    scene.validate()?;
    let image_size = (width, height);
    let shadow_size = image_size; // the papers use the image resolution
    let (vertices, triangles) = upload::flatten(&scene);
    let geometry = SceneGeometry::new(&ctx, &vertices, &triangles)?;
    let mut settings = FrameSettings::new(image_size, shadow_size, spp, seed);
    settings.ambient = scene.ambient;
    let params = FrameParams::new(
        &upload::camera_view(&scene, image_size),
        &upload::light_view(&scene, shadow_size),
        &settings,
    );
    let frame = Buffer::with_data(&ctx, "frame params", BufferUsage::Uniform, &[params])?;
    let inputs = FrameInputs {
        frame: &frame,
        geometry: &geometry,
    };

    // The passes and their targets. An engine creates these once and reuses them each frame.
    let mut collection = CollectionPass::new(&ctx)?;
    let mut generation = GenerationPass::new(&ctx)?;
    let mut lighting = LightingPass::new(&ctx)?;
    let target = LightingTarget::new(&ctx, width, height, spp, MAX_SAMPLES_PER_CHUNK)?;
    let pixels = shadow_size.0 * shadow_size.1;
    // A first guess at the capacities (the standalone renderer's); too small only costs a
    // re-run below.
    let mut map = TemporalShadowMap::new(
        &ctx,
        shadow_size.0,
        shadow_size.1,
        pixels.saturating_mul(2),
        pixels,
    )?;

    let device = &host.device;
    let mut attempts = 0;
    let counts = loop {
        attempts += 1;
        // The whole frame in the host's command buffer, on the host's queue and fence. The
        // passes put the barriers they need between themselves.
        host.record_and_wait(|cmd| {
            collection.record(device, cmd, inputs, &map, None);
            generation.record(device, cmd, &frame, &map, None);
            map.record_counter_readback(device, cmd);
            lighting.record(
                device,
                cmd,
                inputs,
                ShadowSource::Temporal(&map),
                &target,
                None,
            );
            target.record_readback(device, cmd);
        })?;
        let counts = map.read_counters()?;
        if !map.needs_more_room(&counts) {
            break counts;
        }
        // The lists overflowed, so this frame's shadows are incomplete. An engine would
        // show it anyway (or the previous frame), call grow_to_fit between frames (after the
        // frame's fence, since it frees the old buffers) and be exact from the next frame on;
        // here we simply record the same frame again.
        println!(
            "attempt {attempts}: needed {} fragments and {} ranges, had room for {} and {}; growing",
            counts.node_count,
            counts.range_count,
            map.node_capacity(),
            map.range_capacity()
        );
        map.grow_to_fit(&ctx, &counts)?;
    };

    let image = RadianceImage::new(width, height, target.read_rgb()?)?;
    let n = (width as f64) * (height as f64);
    let mut mean = [0.0f64; 3];
    for p in image.rgb.chunks_exact(3) {
        for (m, &v) in mean.iter_mut().zip(p) {
            *m += f64::from(v) / n;
        }
    }
    println!(
        "{width}x{height}, {spp} spp, {} triangles, {attempts} shadow pass attempt(s)",
        geometry.triangle_count()
    );
    println!("N_f (fragments): {}", counts.node_count);
    println!("N_r (ranges):    {}", counts.range_count);
    println!(
        "mean radiance:   {:.6} (linear RGB {:.6}, {:.6}, {:.6})",
        (mean[0] + mean[1] + mean[2]) / 3.0,
        mean[0],
        mean[1],
        mean[2]
    );
    let out = Path::new("out");
    std::fs::create_dir_all(out).map_err(|e| format!("creating {}: {e}", out.display()))?;
    let png = out.join("embed.png");
    write_png(&png, &image, auto_exposure(&image))?;
    println!("wrote {}", png.display());

    // Library objects before the context, the context before the host's device (which the
    // caller destroys). Everything here already waited on the host's fence.
    drop((
        map, target, lighting, generation, collection, frame, geometry,
    ));
    drop(ctx);
    Ok(())
}
