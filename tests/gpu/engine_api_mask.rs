//! One `record_frame` with the mask on records the collection, the generation and the
//! visibility mask: a square sliding 2 units along +x under a light straight down shadows
//! each ground point for the share of the shutter its shadow covers it, which the mask must
//! give (the closed form) at the ground pixels of the library's own G-buffer.

use crate::support::gpu::{assert_no_validation_messages, context};
use glam::{Vec3, Vec4};
use motion_shadows::ash::vk;
use motion_shadows::research::gpu::{
    Access, Buffer, BufferUsage, Image, OneShot, image_barrier, memory_barrier,
};
use motion_shadows::research::passes::{CameraView, DrawList, GBuffer, GBufferCamera, GBufferPass};
use motion_shadows::{CpuGeometry, Light, LightShadow, Mesh, PositionStream, ShadowSettings};

const SIZE: (u32, u32) = (64, 48);
/// The square: side 1 at height 2, z in [0, 1], from x = X0 at t = 0 to X0 + TRAVEL.
const X0: f32 = -1.5;
const TRAVEL: f32 = 2.0;

/// The share of the shutter ground point `x` (z inside the square's) is lit.
fn closed_form(x: f32) -> f32 {
    let enters = ((x - X0 - 1.0) / TRAVEL).clamp(0.0, 1.0);
    let leaves = ((x - X0) / TRAVEL).clamp(0.0, 1.0);
    1.0 - (leaves - enters)
}

/// What one masked frame gave: `finish_frame`'s answer, the mask and the G-buffer's depth.
struct MaskedFrame {
    finished: motion_shadows::Result<()>,
    mask: Vec<f32>,
    depth: Vec<f32>,
    view_proj: glam::Mat4,
}

/// Records and runs one frame of the sliding square with the mask on; `loop_budget` (0: the
/// device's) is the mask's walk budget, with no follow-up rounds when it is not 0.
fn masked_frame(ctx: &motion_shadows::Context, loop_budget: u32) -> MaskedFrame {
    let device = ctx.device();
    let ground: Vec<Vec3> = [
        (-3.0, -1.0),
        (3.0, 2.0),
        (3.0, -1.0),
        (-3.0, -1.0),
        (-3.0, 2.0),
        (3.0, 2.0),
    ]
    .map(|(x, z)| Vec3::new(x, 0.0, z))
    .to_vec();
    let corners = [
        (0.0, 0.0),
        (1.0, 0.0),
        (1.0, 1.0),
        (0.0, 0.0),
        (1.0, 1.0),
        (0.0, 1.0),
    ];
    let square = |dx: f32| -> Vec<Vec3> {
        corners
            .map(|(x, z)| Vec3::new(X0 + dx + x, 2.0, z))
            .to_vec()
    };
    let (open, close) = (square(0.0), square(TRAVEL));
    let padded: Vec<Vec4> = (ground.iter().chain(&open).chain(&close))
        .map(|p| p.extend(1.0))
        .collect();
    let buffer =
        Buffer::with_data(ctx, "positions", BufferUsage::HostToDevice, &padded).expect("positions");
    let at = |vertex: u64| PositionStream::from_buffer(&buffer, 16 * vertex, 16).expect("stream");
    let meshes = [
        Mesh::still(at(0), 6).cpu(CpuGeometry::still(&ground)),
        Mesh::moving(at(6), at(12), 6)
            .first_triangle_id(2)
            .cpu(CpuGeometry::moving(&open, &close)),
    ];
    let light = Light::directional(Vec3::NEG_Y, Vec3::new(0.0, 0.0, 0.5), 4.0)
        .distance(10.0)
        .depth_range(0.1, 20.0);
    let settings = ShadowSettings {
        map_size: (256, 256),
        mask: true,
        frames_in_flight: 1,
        ..ShadowSettings::new(light)
    };
    let mut shadow = LightShadow::new(ctx, settings).expect("shadow with the mask");
    if loop_budget > 0 {
        shadow = shadow.with_mask_loop_budget(ctx, loop_budget, 0);
    }
    // The G-buffer (the host's, here the library's own pass) at shutter close.
    let camera = CameraView::perspective(
        Vec3::new(0.0, 7.0, 4.0),
        Vec3::new(0.0, 0.0, 0.5),
        Vec3::Y,
        50.0,
        SIZE.0 as f32 / SIZE.1 as f32,
        0.1,
        30.0,
    );
    let view_proj = camera.proj * camera.view;
    let draws: Vec<_> = (meshes.iter().enumerate())
        .map(|(i, m)| m.draw(i).expect("draw"))
        .collect();
    let mut list = DrawList::new(ctx, 2).expect("draw list");
    let gbuffer = GBuffer::new(ctx, SIZE.0, SIZE.1).expect("G-buffer");
    let gbuffer_pass = GBufferPass::new(ctx).expect("G-buffer pass");
    let output = Image::new(
        ctx,
        "mask",
        (SIZE.0, SIZE.1, 1),
        vk::Format::R32_SFLOAT,
        vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::TRANSFER_SRC,
    )
    .expect("mask image");
    let pixels = (SIZE.0 * SIZE.1) as usize;
    let readback = Buffer::new(
        ctx,
        "mask readback",
        4 * pixels as u64,
        BufferUsage::Readback,
    )
    .expect("readback");
    let inputs = gbuffer.mask_inputs(output.layer_view(0), view_proj.inverse(), 1.0, false);
    let range = output.layers_range(0, 1);
    OneShot::new(ctx)
        .expect("command buffer")
        .run(|cmd| {
            // SAFETY: the OneShot's command buffer, recording outside rendering on the
            // context's graphics and compute queue; the G-buffer is drawn (and left readable by
            // compute) before the mask reads it, the output moved to GENERAL before and to
            // TRANSFER_SRC after; every object outlives the run, which waits.
            unsafe {
                list.record_update(device, cmd, &draws)?;
                let eye = camera.position;
                gbuffer_pass.record(
                    device,
                    cmd,
                    &list,
                    &GBufferCamera { view_proj, eye },
                    1.0,
                    &gbuffer,
                );
                let to_general = (vk::ImageLayout::UNDEFINED, vk::ImageLayout::GENERAL);
                image_barrier(
                    device,
                    cmd,
                    output.raw(),
                    range,
                    to_general,
                    Access::TRANSFER_READ,
                    Access::COMPUTE_RW,
                );
                shadow.record_frame(ctx, cmd, 1, &meshes, Some(&inputs))?;
                let to_copy = (
                    vk::ImageLayout::GENERAL,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                );
                image_barrier(
                    device,
                    cmd,
                    output.raw(),
                    range,
                    to_copy,
                    Access::COMPUTE_RW,
                    Access::TRANSFER_READ,
                );
                output.record_copy_to_buffer(device, cmd, readback.raw(), 0);
                memory_barrier(device, cmd, Access::TRANSFER_WRITE, Access::HOST_READ);
                gbuffer.record_readback(device, cmd);
            }
            Ok(())
        })
        .expect("frame");
    // SAFETY: the OneShot waited for the frame.
    unsafe { ctx.collect(1) };
    let finished = shadow.finish_frame(ctx, 1);
    let mask: Vec<f32> = readback.read(pixels).expect("mask");
    let depth = gbuffer.read().expect("G-buffer").depth;
    MaskedFrame {
        finished,
        mask,
        depth,
        view_proj,
    }
}

#[test]
fn the_shadow_records_the_mask_in_the_same_call() {
    let ctx = context();
    let MaskedFrame {
        finished,
        mask,
        depth,
        view_proj,
    } = masked_frame(&ctx, 0);
    finished.expect("complete frame");
    let inverse = view_proj.inverse();
    let (mut checked, mut worst) = (0, 0.0f32);
    for (i, (&d, &got)) in depth.iter().zip(&mask).enumerate() {
        let (x, y) = ((i as u32 % SIZE.0) as f32, (i as u32 / SIZE.0) as f32);
        let ndc = (glam::Vec2::new(x, y) + 0.5) / glam::Vec2::new(SIZE.0 as f32, SIZE.1 as f32);
        let p = inverse * Vec4::new(2.0 * ndc.x - 1.0, 2.0 * ndc.y - 1.0, d, 1.0);
        let p = p.truncate() / p.w;
        // Ground points under the square's path, away from the edges of its shadow.
        let on_ground = d < 1.0 && p.y.abs() < 0.01;
        let inside_z = p.z > 0.1 && p.z < 0.9;
        let edges = [X0, X0 + 1.0, X0 + TRAVEL, X0 + TRAVEL + 1.0];
        let clear = edges.iter().all(|e| (p.x - e).abs() > 0.1);
        if on_ground && inside_z && clear {
            worst = worst.max((got - closed_form(p.x)).abs());
            checked += 1;
        }
    }
    eprintln!("{checked} ground pixels, worst {worst}");
    assert!(checked > 100, "{checked} ground pixels checked");
    assert!(worst <= 0.05, "the mask is off the closed form by {worst}");
    assert_no_validation_messages(&ctx);
}

/// A device that leaves long loops (lavapipe) may cut some pixels' lookups short: the mask
/// pass counts them, and `finish_frame` must report them rather than leave the host a mask it
/// cannot trust. A walk budget of 2 iterations with no follow-up round cuts the shadowed
/// pixels' lookups short on any device.
#[test]
fn finish_frame_reports_mask_pixels_cut_short_by_the_loop_limit() {
    let ctx = context();
    let frame = masked_frame(&ctx, 2);
    match frame.finished {
        Err(motion_shadows::Error::MaskCutShort { frame, pixels }) => {
            assert_eq!(frame, 1);
            assert!(pixels > 0, "{pixels} pixels reported");
        }
        other => panic!("finish_frame did not report the cut-short pixels: {other:?}"),
    }
    assert_no_validation_messages(&ctx);
}
