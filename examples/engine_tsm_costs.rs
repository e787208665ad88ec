//! What time-dependent shadow maps cost in the deferred frame (`EngineTsmPass`), measured
//! with GPU timestamps and the process's CPU time: per map, at a 1920x1080 G-buffer and
//! 2048x2048 maps, with each of the two ways a map starts from the kept static map (an image
//! copy, or a clear and a second lookup), 1, 4, 8 or 16 maps per dispatch, split into drawing and
//! lookup (the same frames with an 8x8 mask); and the copy and the clear of one 2048x2048 map
//! alone.
//!
//! ```sh
//! cargo run --release --example engine_tsm_costs
//! ```
//!
//! The scene: a static ground (a 64x64 grid) and 96 static boxes, 32 boxes translating
//! during the shutter, lit by a slanted directional light; the G-buffer drawn at shutter
//! close. Each figure is the least of five runs.

use ash::vk;
use glam::Vec3;
use motion_shadows::Result;
use motion_shadows::gpu::{
    Access, Buffer, BufferUsage, Context, ContextOptions, Image, OneShot, TimestampQueries,
    image_barrier, memory_barrier,
};
use motion_shadows::technique::{
    CameraView, Draw, DrawList, EngineTsmMap, EngineTsmPass, GBuffer, GBufferCamera, GBufferPass,
    Indices, LightView, MaskInputs, PositionStream, TsmStart,
};

const WIDTH: u32 = 1920;
const HEIGHT: u32 = 1080;
const SHADOW: u32 = 2048;
const RUNS: usize = 5;
/// Maps per dispatch measured (the working map's layers).
const LAYERS: [u32; 4] = [1, 4, 8, 16];

/// The 12 triangles of the box of half-size `half` around `centre`.
fn cuboid(centre: Vec3, half: Vec3) -> Vec<Vec3> {
    let c = |x: f32, y: f32, z: f32| centre + half * Vec3::new(x, y, z);
    let quads = [
        [
            c(-1., -1., 1.),
            c(1., -1., 1.),
            c(1., 1., 1.),
            c(-1., 1., 1.),
        ],
        [
            c(1., -1., -1.),
            c(-1., -1., -1.),
            c(-1., 1., -1.),
            c(1., 1., -1.),
        ],
        [
            c(1., -1., 1.),
            c(1., -1., -1.),
            c(1., 1., -1.),
            c(1., 1., 1.),
        ],
        [
            c(-1., -1., -1.),
            c(-1., -1., 1.),
            c(-1., 1., 1.),
            c(-1., 1., -1.),
        ],
        [
            c(-1., 1., 1.),
            c(1., 1., 1.),
            c(1., 1., -1.),
            c(-1., 1., -1.),
        ],
        [
            c(-1., -1., -1.),
            c(1., -1., -1.),
            c(1., -1., 1.),
            c(-1., -1., 1.),
        ],
    ];
    quads
        .iter()
        .flat_map(|[a, b, c, d]| [*a, *b, *c, *a, *c, *d])
        .collect()
}

/// A 64x64 grid of quads over [-12, 12]^2 at height 0.
fn ground() -> Vec<Vec3> {
    let cells = 64;
    let step = 24.0 / cells as f32;
    let mut points = Vec::new();
    for j in 0..cells {
        for i in 0..cells {
            let p = |di: u32, dj: u32| {
                Vec3::new(
                    -12.0 + (i + di) as f32 * step,
                    0.0,
                    -12.0 + (j + dj) as f32 * step,
                )
            };
            points.extend([p(0, 0), p(0, 1), p(1, 1), p(0, 0), p(1, 1), p(1, 0)]);
        }
    }
    points
}

struct Mesh {
    t0: Buffer,
    t1: Option<Buffer>,
    triangles: u32,
}

impl Mesh {
    fn new(ctx: &Context, t0: &[Vec3], t1: Option<&[Vec3]>) -> Result<Mesh> {
        let buffer = |points: &[Vec3]| {
            let floats: Vec<[f32; 3]> = points.iter().map(|p| p.to_array()).collect();
            Buffer::with_data(ctx, "mesh", BufferUsage::HostToDevice, &floats)
        };
        Ok(Mesh {
            t0: buffer(t0)?,
            t1: t1.map(buffer).transpose()?,
            triangles: t0.len() as u32 / 3,
        })
    }

    fn draw(&self, first_id: u32) -> Result<Draw> {
        let t0 = PositionStream::from_buffer(&self.t0, 0, 12)?;
        let t1 = match &self.t1 {
            Some(b) => PositionStream::from_buffer(b, 0, 12)?,
            None => t0,
        };
        Ok(Draw::new(
            t0,
            t1,
            3 * self.triangles,
            Indices::None,
            self.triangles,
            first_id,
        ))
    }
}

/// CPU time this process has used, in ms (user + system, all threads: on a CPU device such
/// as lavapipe, the device's work), or 0 where /proc is not there. Less disturbed than the
/// GPU timestamps (wall clock) by other processes on the machine.
fn cpu_ms() -> f64 {
    let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else {
        return 0.0;
    };
    // After the command name in parentheses: fields 3 on; utime and stime are 14 and 15.
    let fields: Vec<&str> = stat
        .rsplit_once(')')
        .map_or("", |(_, rest)| rest)
        .split_whitespace()
        .collect();
    let ticks = |i: usize| fields.get(i - 3).and_then(|f| f.parse::<f64>().ok());
    // Clock ticks of 10 ms (USER_HZ = 100 on Linux).
    ticks(14)
        .zip(ticks(15))
        .map_or(0.0, |(u, s)| (u + s) * 10.0)
}

/// A fixed pseudo-random number in [0, 1) for `i`.
fn hash(i: u32) -> f32 {
    let mut v = i.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    v = ((v >> ((v >> 28) + 4)) ^ v).wrapping_mul(277_803_737);
    ((v >> 22) ^ v) as f32 / 4_294_967_296.0
}

fn main() -> Result<()> {
    let ctx = Context::headless(&ContextOptions { validation: false })?;
    println!("device: {} ({})", ctx.info().name, ctx.info().driver);

    // The scene.
    let mut meshes = vec![Mesh::new(&ctx, &ground(), None)?];
    let mut boxes_static = Vec::new();
    for i in 0..96 {
        let centre = Vec3::new(
            hash(3 * i) * 20.0 - 10.0,
            0.5,
            hash(3 * i + 1) * 20.0 - 10.0,
        );
        boxes_static.extend(cuboid(centre, Vec3::new(0.4, 0.5 + hash(3 * i + 2), 0.4)));
    }
    meshes.push(Mesh::new(&ctx, &boxes_static, None)?);
    let (mut t0, mut t1) = (Vec::new(), Vec::new());
    for i in 0..32 {
        let k = 1000 + 4 * i;
        let centre = Vec3::new(hash(k) * 20.0 - 10.0, 1.5, hash(k + 1) * 20.0 - 10.0);
        let motion = Vec3::new(hash(k + 2) - 0.5, 0.0, hash(k + 3) - 0.5) * 3.0;
        let cube = cuboid(centre, Vec3::splat(0.3));
        t1.extend(cube.iter().map(|p| *p + motion));
        t0.extend(cube);
    }
    meshes.push(Mesh::new(&ctx, &t0, Some(&t1))?);
    let mut first_id = 0;
    let mut draws = Vec::new();
    for mesh in &meshes {
        draws.push(mesh.draw(first_id)?);
        first_id += mesh.triangles;
    }
    let mut light = LightView::directional(
        Vec3::new(0.4, -1.0, 0.3),
        1.0,
        Vec3::ZERO,
        12.0,
        30.0,
        1.0,
        60.0,
        (SHADOW, SHADOW),
    );
    light.keep_static_layer = true;
    let camera = CameraView::perspective(
        Vec3::new(0.0, 9.0, 14.0),
        Vec3::ZERO,
        Vec3::Y,
        55.0,
        WIDTH as f32 / HEIGHT as f32,
        0.1,
        100.0,
    );
    let view_proj = camera.proj * camera.view;

    // The G-buffer, drawn once.
    let mut list = DrawList::new(&ctx, 4)?;
    let gbuffer = GBuffer::new(&ctx, WIDTH, HEIGHT)?;
    let gbuffer_pass = GBufferPass::new(&ctx)?;
    let output = Image::new(
        &ctx,
        "mask",
        (WIDTH, HEIGHT, 1),
        vk::Format::R32_SFLOAT,
        vk::ImageUsageFlags::STORAGE,
    )?;
    let device = ctx.device();
    let one_shot = OneShot::new(&ctx)?;
    // SAFETY: the OneShot's command buffer of this context, recording outside rendering on its
    // graphics and compute queue; the list's update precedes the G-buffer pass that reads it, and
    // every buffer and image used outlives the run, which waits.
    one_shot.run(|cmd| unsafe {
        list.record_update(device, cmd, &draws)?;
        let camera = GBufferCamera {
            view_proj,
            eye: camera.position,
        };
        gbuffer_pass.record(device, cmd, &list, &camera, 1.0, &gbuffer);
        Ok(())
    })?;

    let pass = EngineTsmPass::new(&ctx)?;
    let mut bindings = pass.bindings()?;
    let mut timestamps = TimestampQueries::new(&ctx, 8)?;
    if let Some(why) = timestamps.unsupported_reason() {
        println!("no timing: {why}");
        return Ok(());
    }
    // One frame of `maps` maps over a `size` mask, the static map drawn first if `redraw`:
    // its GPU time and the CPU time of the submission in ms (each the least of RUNS).
    let mut frame =
        |map: &EngineTsmMap, maps: u32, size: (u32, u32), redraw: bool| -> Result<(f64, f64)> {
            let inputs = MaskInputs {
                size,
                ..gbuffer.mask_inputs(output.layer_view(0), view_proj.inverse(), 1.0, true)
            };
            let (mut best, mut best_cpu) = (f64::MAX, f64::MAX);
            for _ in 0..RUNS {
                if redraw {
                    map.forget_static_map();
                }
                // SAFETY: the previous run waited for its OneShot, so no command buffer with these
                // marks is pending.
                unsafe { timestamps.clear() };
                let cpu = cpu_ms();
                // SAFETY: the OneShot's recording command buffer of this context; the output image
                // goes to GENERAL for the mask's storage writes, the G-buffer was drawn in an
                // earlier run and left in its read layouts, and the map, bindings and timestamps
                // outlive the run, which waits.
                one_shot.run(|cmd| unsafe {
                    image_barrier(
                        device,
                        cmd,
                        output.raw(),
                        output.layers_range(0, 1),
                        (vk::ImageLayout::UNDEFINED, vk::ImageLayout::GENERAL),
                        Access::COMPUTE_RW,
                        Access::COMPUTE_RW,
                    );
                    timestamps.mark(cmd, "start");
                    pass.record(
                        device,
                        cmd,
                        &mut bindings,
                        &inputs,
                        &list,
                        &light,
                        map,
                        maps,
                    )?;
                    timestamps.mark(cmd, "tsm");
                    Ok(())
                })?;
                best_cpu = best_cpu.min(cpu_ms() - cpu);
                // Submitted: the next run may keep the static map (unless `redraw`).
                map.static_map_submitted();
                let spans = timestamps.spans_ms()?;
                best = best.min(spans.iter().map(|(_, ms)| ms).sum());
            }
            Ok((best, best_cpu))
        };

    println!(
        "{WIDTH}x{HEIGHT} G-buffer, {SHADOW}x{SHADOW} maps; GPU ms (timestamps) / CPU ms \
         (the process's CPU time), each the least of {RUNS} runs"
    );
    let per = |a: (f64, f64), b: (f64, f64), n: f64| ((b.0 - a.0) / n, (b.1 - a.1) / n);
    for start in [TsmStart::Copy, TsmStart::SecondLookup] {
        for layers in LAYERS {
            // Frames of `layers` maps (one batch) and of `extra` more (whole batches, at least
            // 8 maps), over the whole G-buffer and over 8x8 pixels (drawing alone, nearly).
            let extra = layers * 8u32.div_ceil(layers);
            let map = EngineTsmMap::new(&ctx, SHADOW, SHADOW, layers, start)?;
            let first = frame(&map, layers, (WIDTH, HEIGHT), true)?;
            let kept = frame(&map, layers, (WIDTH, HEIGHT), false)?;
            let more = frame(&map, layers + extra, (WIDTH, HEIGHT), false)?;
            let tiny = frame(&map, layers, (8, 8), false)?;
            let tiny_more = frame(&map, layers + extra, (8, 8), false)?;
            let per_map = per(kept, more, extra as f64);
            let per_map_tiny = per(tiny, tiny_more, extra as f64);
            let static_map = per(kept, first, 1.0);
            println!(
                "{start:?}, {layers} per dispatch: TSM-{layers} {:.1} / {:.0}; the static \
                 map's draw {:.1} / {:.0}; per map {:.1} / {:.0}: start + draw {:.1} / {:.0}, \
                 lookup {:.1} / {:.0}",
                kept.0,
                kept.1,
                static_map.0,
                static_map.1,
                per_map.0,
                per_map.1,
                per_map_tiny.0,
                per_map_tiny.1,
                per_map.0 - per_map_tiny.0,
                per_map.1 - per_map_tiny.1,
            );
        }
    }

    // The copy and the clear of one map alone: 32 of each in one submission, timed on the
    // host (lavapipe's timestamps around a lone transfer command do not bracket it), less
    // the same submission without them.
    let usage = vk::ImageUsageFlags::TRANSFER_SRC | vk::ImageUsageFlags::TRANSFER_DST;
    let size = (SHADOW, SHADOW, 1);
    let a = Image::new(&ctx, "a", size, vk::Format::D32_SFLOAT, usage)?;
    let b = Image::new(&ctx, "b", size, vk::Format::D32_SFLOAT, usage)?;
    let range = a.layers_range(0, 1);
    let one = vk::ClearDepthStencilValue {
        depth: 1.0,
        stencil: 0,
    };
    let layers = vk::ImageSubresourceLayers {
        aspect_mask: vk::ImageAspectFlags::DEPTH,
        mip_level: 0,
        base_array_layer: 0,
        layer_count: 1,
    };
    let region = vk::ImageCopy {
        src_subresource: layers,
        src_offset: vk::Offset3D::default(),
        dst_subresource: layers,
        dst_offset: vk::Offset3D::default(),
        extent: vk::Extent3D {
            width: SHADOW,
            height: SHADOW,
            depth: 1,
        },
    };
    const TRANSFERS: u32 = 32;
    // Wall and CPU ms of a submission with `count` copies (or clears) of b.
    let transfers = |copy: bool, count: u32| -> Result<(f64, f64)> {
        let (mut wall, mut cpu) = (f64::MAX, f64::MAX);
        for _ in 0..RUNS {
            let (start, start_cpu) = (std::time::Instant::now(), cpu_ms());
            // SAFETY: the OneShot's recording command buffer, outside rendering; `a` and `b` are
            // this context's depth images with transfer usage, each moved to the layout its clear
            // or copy names before it, and `region`/`range` cover exactly their one layer.
            one_shot.run(|cmd| unsafe {
                let to = |image: &Image, layout| {
                    image_barrier(
                        device,
                        cmd,
                        image.raw(),
                        range,
                        (vk::ImageLayout::UNDEFINED, layout),
                        Access::TRANSFER_WRITE.and(Access::TRANSFER_READ),
                        Access::TRANSFER_WRITE,
                    )
                };
                to(&a, vk::ImageLayout::TRANSFER_DST_OPTIMAL);
                let a_layout = vk::ImageLayout::TRANSFER_DST_OPTIMAL;
                device.cmd_clear_depth_stencil_image(cmd, a.raw(), a_layout, &one, &[range]);
                image_barrier(
                    device,
                    cmd,
                    a.raw(),
                    range,
                    (a_layout, vk::ImageLayout::TRANSFER_SRC_OPTIMAL),
                    Access::TRANSFER_WRITE,
                    Access::TRANSFER_READ,
                );
                to(&b, vk::ImageLayout::TRANSFER_DST_OPTIMAL);
                let b_layout = vk::ImageLayout::TRANSFER_DST_OPTIMAL;
                for _ in 0..count {
                    if copy {
                        let a_layout = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
                        device.cmd_copy_image(cmd, a.raw(), a_layout, b.raw(), b_layout, &[region]);
                    } else {
                        device.cmd_clear_depth_stencil_image(
                            cmd,
                            b.raw(),
                            b_layout,
                            &one,
                            &[range],
                        );
                    }
                    memory_barrier(device, cmd, Access::TRANSFER_WRITE, Access::TRANSFER_WRITE);
                }
                Ok(())
            })?;
            wall = wall.min(start.elapsed().as_secs_f64() * 1e3);
            cpu = cpu.min(cpu_ms() - start_cpu);
        }
        Ok((wall, cpu))
    };
    let none = transfers(true, 0)?;
    let copies = per(none, transfers(true, TRANSFERS)?, TRANSFERS as f64);
    let clears = per(none, transfers(false, TRANSFERS)?, TRANSFERS as f64);
    println!(
        "one {SHADOW}x{SHADOW} D32 map alone (wall ms / CPU ms): copy {:.2} / {:.1}, clear \
         {:.2} / {:.1}",
        copies.0, copies.1, clears.0, clears.1
    );
    Ok(())
}
