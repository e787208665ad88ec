//! The engine TSM tests' rig: meshes in host-visible buffers, the light and the camera, and
//! a frame run through the G-buffer pass and the engine TSM pass, its mask and the G-buffer's
//! world points read back.

use super::{HALF, SHADOW, SIZE};
use ash::vk;
use glam::{Mat4, Vec3, Vec4};
use motion_shadows::Error;
use motion_shadows::gpu::{
    Access, Buffer, BufferUsage, Context, Image, OneShot, image_barrier, memory_barrier,
};
use motion_shadows::technique::{
    CameraView, Draw, DrawList, EngineTsmBindings, EngineTsmMap, EngineTsmPass, GBuffer,
    GBufferCamera, GBufferPass, Indices, LightView, PositionStream,
};

/// Two triangles of the rectangle [x0, x1] x [z0, z1] at height y.
pub(super) fn rect(x0: f32, x1: f32, z0: f32, z1: f32, y: f32) -> Vec<Vec3> {
    let a = Vec3::new(x0, y, z0);
    let b = Vec3::new(x0, y, z1);
    let c = Vec3::new(x1, y, z1);
    let d = Vec3::new(x1, y, z0);
    vec![a, b, c, a, c, d]
}

pub(super) fn shifted(points: &[Vec3], by: Vec3) -> Vec<Vec3> {
    points.iter().map(|p| *p + by).collect()
}

/// Triangles in host-visible buffers: one stream (static) or two (moving).
pub(super) struct Mesh {
    t0: Buffer,
    t1: Option<Buffer>,
    triangles: u32,
}

impl Mesh {
    pub(super) fn new(ctx: &Context, t0: &[Vec3], t1: Option<&[Vec3]>) -> Mesh {
        let floats = |points: &[Vec3]| points.iter().map(|p| p.to_array()).collect::<Vec<_>>();
        let buffer = |points: &[Vec3]| {
            Buffer::with_data(ctx, "test mesh", BufferUsage::HostToDevice, &floats(points))
                .expect("mesh buffer")
        };
        Mesh {
            t0: buffer(t0),
            t1: t1.map(buffer),
            triangles: t0.len() as u32 / 3,
        }
    }

    /// Rewrites the (static) positions in place.
    pub(super) fn rewrite(&mut self, t0: &[Vec3]) {
        let floats: Vec<[f32; 3]> = t0.iter().map(|p| p.to_array()).collect();
        self.t0.write(&floats).expect("rewrite mesh");
    }

    pub(super) fn draw(&self, first_id: u32) -> Draw {
        let stream = |b: &Buffer| PositionStream::from_buffer(b, 0, 12).expect("stream");
        let t0 = stream(&self.t0);
        let t1 = self.t1.as_ref().map_or(t0, stream);
        Draw::new(
            t0,
            t1,
            3 * self.triangles,
            Indices::None,
            self.triangles,
            first_id,
        )
    }
}

/// A directional light along `direction` over the box of half-width [`HALF`] around the
/// origin, the maps [`SHADOW`] texels on a side.
pub(super) fn light(direction: Vec3, keep_static: bool) -> LightView {
    let mut light = LightView::directional(
        direction,
        1.0,
        Vec3::ZERO,
        HALF,
        10.0,
        0.5,
        20.0,
        (SHADOW, SHADOW),
    );
    light.keep_static_layer = keep_static;
    light
}

/// The camera: above the ground at an angle, the light's box in view.
pub(super) fn camera() -> (Mat4, Vec3) {
    let c = CameraView::perspective(
        Vec3::new(0.4, 7.0, 4.0),
        Vec3::ZERO,
        Vec3::Y,
        50.0,
        SIZE.0 as f32 / SIZE.1 as f32,
        0.1,
        50.0,
    );
    (c.proj * c.view, c.position)
}

/// What a test frame draws: the G-buffer's receivers (drawn at `gbuffer_time`, their motion
/// read when `moving_receivers`) and the shadow maps' draws.
pub(super) struct Frame<'a> {
    pub(super) receivers: &'a [Draw],
    pub(super) casters: &'a [Draw],
    pub(super) light: &'a LightView,
    pub(super) maps: u32,
    pub(super) gbuffer_time: f32,
    pub(super) moving_receivers: bool,
    /// Draw the G-buffer (else the last frame's is read again).
    pub(super) draw_gbuffer: bool,
}

/// The passes, the G-buffer, the output image and its readback.
pub(super) struct Rig<'c> {
    ctx: &'c Context,
    gbuffer_pass: GBufferPass,
    pass: EngineTsmPass,
    bindings: EngineTsmBindings,
    gbuffer: GBuffer,
    output: Image,
    readback: Buffer,
    receivers: DrawList,
    casters: DrawList,
    /// The G-buffer's world points (None: background), from its last readback.
    points: Vec<Option<Vec3>>,
}

impl<'c> Rig<'c> {
    pub(super) fn new(ctx: &'c Context) -> Rig<'c> {
        let pass = EngineTsmPass::new(ctx).expect("engine TSM pass");
        Rig {
            ctx,
            gbuffer_pass: GBufferPass::new(ctx).expect("G-buffer pass"),
            bindings: pass.bindings().expect("bindings"),
            pass,
            gbuffer: GBuffer::new(ctx, SIZE.0, SIZE.1).expect("G-buffer"),
            output: Image::new(
                ctx,
                "TSM mask",
                (SIZE.0, SIZE.1, 1),
                vk::Format::R32_SFLOAT,
                vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::TRANSFER_SRC,
            )
            .expect("mask image"),
            readback: Buffer::new(
                ctx,
                "TSM mask readback",
                SIZE.0 as u64 * SIZE.1 as u64 * 4,
                BufferUsage::Readback,
            )
            .expect("readback"),
            receivers: DrawList::new(ctx, 4).expect("draw list"),
            casters: DrawList::new(ctx, 4).expect("draw list"),
            points: Vec::new(),
        }
    }

    /// Records and runs one frame into `map`; the mask, row after row.
    pub(super) fn run(&mut self, frame: &Frame, map: &EngineTsmMap) -> Result<Vec<f32>, Error> {
        let (view_proj, eye) = camera();
        let inputs = self.gbuffer.mask_inputs(
            self.output.layer_view(0),
            view_proj.inverse(),
            frame.gbuffer_time,
            frame.moving_receivers,
        );
        let device = self.ctx.device();
        let one_shot = OneShot::new(self.ctx)?;
        let output = self.output.raw();
        let range = self.output.layers_range(0, 1);
        // SAFETY: `cmd` is the OneShot's command buffer of this context, recording outside
        // rendering on its graphics and compute queue: each draw list's update precedes the pass
        // that reads it, the output image is moved to GENERAL before the pass writes it and to
        // TRANSFER_SRC_OPTIMAL before its copy, and every object used outlives the run, which
        // waits.
        one_shot.run(|cmd| unsafe {
            if frame.draw_gbuffer {
                self.receivers.record_update(device, cmd, frame.receivers)?;
                let camera = GBufferCamera { view_proj, eye };
                self.gbuffer_pass.record(
                    device,
                    cmd,
                    &self.receivers,
                    &camera,
                    frame.gbuffer_time,
                    &self.gbuffer,
                );
            }
            self.casters.record_update(device, cmd, frame.casters)?;
            image_barrier(
                device,
                cmd,
                output,
                range,
                (vk::ImageLayout::UNDEFINED, vk::ImageLayout::GENERAL),
                Access::TRANSFER_READ,
                Access::COMPUTE_RW,
            );
            self.pass.record(
                device,
                cmd,
                &mut self.bindings,
                &inputs,
                &self.casters,
                frame.light,
                map,
                frame.maps,
            )?;
            image_barrier(
                device,
                cmd,
                output,
                range,
                (
                    vk::ImageLayout::GENERAL,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                ),
                Access::COMPUTE_RW,
                Access::TRANSFER_READ,
            );
            self.output
                .record_copy_to_buffer(device, cmd, self.readback.raw(), 0);
            memory_barrier(device, cmd, Access::TRANSFER_WRITE, Access::HOST_READ);
            if frame.draw_gbuffer {
                self.gbuffer.record_readback(device, cmd);
            }
            Ok(())
        })?;
        // Submitted and waited for: a static map it drew may be kept.
        map.static_map_submitted();
        if frame.draw_gbuffer {
            let contents = self.gbuffer.read()?;
            let inverse = view_proj.inverse();
            self.points = (0..SIZE.0 * SIZE.1)
                .map(|i| {
                    let depth = contents.depth[i as usize];
                    (depth != 1.0).then(|| {
                        let (x, y) = (i % SIZE.0, i / SIZE.0);
                        let ndc = (glam::Vec2::new(x as f32, y as f32) + 0.5)
                            / glam::Vec2::new(SIZE.0 as f32, SIZE.1 as f32)
                            * 2.0
                            - 1.0;
                        let p = inverse * Vec4::new(ndc.x, ndc.y, depth, 1.0);
                        p.truncate() / p.w
                    })
                })
                .collect();
        }
        self.readback.read::<f32>((SIZE.0 * SIZE.1) as usize)
    }
}

/// The pixel whose G-buffer point is nearest to the ground point (x, 0, 0.3).
pub(super) fn nearest_pixel(rig: &Rig, x: f32) -> usize {
    let target = Vec3::new(x, 0.0, 0.3);
    (rig.points.iter().enumerate())
        .filter_map(|(i, p)| p.map(|p| (i, (p - target).length())))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .expect("ground pixels")
        .0
}

/// Per pixel whose point `closed_form` answers (None: skipped), the mask's error.
pub(super) fn errors(
    rig: &Rig,
    mask: &[f32],
    closed_form: impl Fn(Vec3) -> Option<f32>,
) -> Vec<(usize, f32, f32)> {
    rig.points
        .iter()
        .enumerate()
        .filter_map(|(i, p)| {
            let expected = closed_form((*p)?)?;
            Some((i, mask[i], expected))
        })
        .collect()
}
