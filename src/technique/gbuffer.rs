//! The deferred frame's G-buffer: the draws of a [`DrawList`] at one shutter time, seen from a
//! camera, into a depth image and three float images (world normal, albedo, world motion over
//! the shutter, world position): what an engine's G-buffer holds, for the app's deferred frame and for hosts
//! that want a reference. The [`VisibilityMaskPass`](super::VisibilityMaskPass) reads it
//! through [`GBuffer::mask_inputs`].
//!
//! The motion image holds each point's displacement over the whole shutter, `p(1) - p(0)`,
//! interpolated from the vertices' own: exact, since a point with fixed barycentrics on a
//! triangle whose corners move linearly moves linearly.

use super::declared_barriers::{Barrier, record_own};
use super::draws::DrawList;
use super::mask::{
    MaskInputs, MotionImage, NormalEncoding, NormalImage, PositionImage, TriangleIdImage,
};
use super::push_constants::{GBufferPush, PushBlock};
use super::shaders;
use crate::error::{Error, Result};
use crate::gpu::{
    Access, Attachments, Buffer, BufferUsage, Context, Image, Pipeline, begin_rendering_colors,
    graphics_pipeline, image_barrier,
};
use ash::vk;
use glam::{Mat4, Vec3, Vec4};

/// The depth image's format (cleared to 1, LESS).
pub const GBUFFER_DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;
/// The normal, albedo and motion images' format: full float, so that the app's frame carries
/// no quantization of its own into comparisons with the truth.
pub const GBUFFER_COLOR_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
/// The triangle-id image's format (cleared to `u32::MAX`: none).
pub const GBUFFER_ID_FORMAT: vk::Format = vk::Format::R32_UINT;
/// Bytes a pixel of the readback: depth (4), normal, albedo and motion (16 each), id (4).
const READBACK_BYTES_PER_PIXEL: u64 = 4 + 3 * 16 + 4;

/// The layout the colour images are left in by [`GBufferPass::record`].
const COLOR_READ_LAYOUT: vk::ImageLayout = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
/// The layout the depth image is left in.
const DEPTH_READ_LAYOUT: vk::ImageLayout = vk::ImageLayout::DEPTH_STENCIL_READ_ONLY_OPTIMAL;

/// The camera a G-buffer is drawn from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GBufferCamera {
    /// World -> clip (Vulkan: y down, depth in [0, 1]).
    pub view_proj: Mat4,
    /// The camera's position (normals are turned toward it: surfaces are two-sided).
    pub eye: Vec3,
}

/// What the host reads back of a G-buffer: per pixel, row after row from the top.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GBufferContents {
    /// Pixels across.
    pub width: u32,
    /// Pixels down.
    pub height: u32,
    /// The depth image (1 where nothing was drawn).
    pub depth: Vec<f32>,
    /// Unit world normals, on the side facing the camera.
    pub normal: Vec<Vec3>,
    /// The draw's albedo (its `DrawRecord::albedo_flags` rgb).
    pub albedo: Vec<Vec3>,
    /// World displacement over the shutter, `p(1) - p(0)`.
    pub motion: Vec<Vec3>,
    /// The triangle each pixel shows (its global id; `u32::MAX` where nothing was drawn).
    pub ids: Vec<u32>,
}

/// A G-buffer's images, and a buffer to read them back.
pub struct GBuffer {
    width: u32,
    height: u32,
    depth: Image,
    /// Normal, albedo, motion.
    colors: [Image; 3],
    /// The triangle ids.
    ids: Image,
    /// World positions at the time drawn (not read back): the mask's receivers, without the
    /// error of rebuilding them from the depth.
    positions: Image,
    readback: Buffer,
}

impl GBuffer {
    /// Images of `width` x `height` pixels.
    pub fn new(ctx: &Context, width: u32, height: u32) -> Result<Self> {
        if width == 0 || height == 0 {
            return Err(Error::InvalidArgument(format!(
                "G-buffer size {width}x{height}"
            )));
        }
        let usage = vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_SRC;
        let size = (width, height, 1);
        let depth = Image::new(
            ctx,
            "G-buffer depth",
            size,
            GBUFFER_DEPTH_FORMAT,
            usage | vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
        )?;
        let color = |name| {
            Image::new(
                ctx,
                name,
                size,
                GBUFFER_COLOR_FORMAT,
                usage | vk::ImageUsageFlags::COLOR_ATTACHMENT,
            )
        };
        let colors = [
            color("G-buffer normals")?,
            color("G-buffer albedo")?,
            color("G-buffer motion")?,
        ];
        let ids = Image::new(
            ctx,
            "G-buffer triangle ids",
            size,
            GBUFFER_ID_FORMAT,
            usage | vk::ImageUsageFlags::COLOR_ATTACHMENT,
        )?;
        let positions = color("G-buffer positions")?;
        let pixels = width as u64 * height as u64;
        let readback = Buffer::new(
            ctx,
            "G-buffer readback",
            pixels * READBACK_BYTES_PER_PIXEL,
            BufferUsage::Readback,
        )?;
        Ok(Self {
            width,
            height,
            depth,
            colors,
            ids,
            positions,
            readback,
        })
    }

    /// Pixels across and down.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// The mask pass's inputs for this G-buffer (after [`GBufferPass::record`]): its depth,
    /// normals and, with `moving_receivers`, motion; `output` as [`MaskInputs::output`];
    /// `inv_view_proj` the inverse of the camera's `view_proj`; `time` the shutter time drawn.
    pub fn mask_inputs(
        &self,
        output: vk::ImageView,
        inv_view_proj: Mat4,
        time: f32,
        moving_receivers: bool,
    ) -> MaskInputs {
        MaskInputs {
            depth: self.depth.layer_view(0),
            depth_layout: DEPTH_READ_LAYOUT,
            normals: Some(NormalImage {
                view: self.colors[0].layer_view(0),
                layout: COLOR_READ_LAYOUT,
                encoding: NormalEncoding::Signed,
            }),
            output,
            size: (self.width, self.height),
            inv_view_proj,
            background_depth: 1.0,
            motion: moving_receivers.then(|| MotionImage {
                view: self.colors[2].layer_view(0),
                layout: COLOR_READ_LAYOUT,
            }),
            time,
            ids: Some(TriangleIdImage {
                view: self.ids.layer_view(0),
                layout: COLOR_READ_LAYOUT,
            }),
            positions: Some(PositionImage {
                view: self.positions.layer_view(0),
                layout: COLOR_READ_LAYOUT,
            }),
            // The caller's choice (MaskInputs::with_plane_test_where_still).
            plane_test_where_still: false,
        }
    }

    /// Every image, its name (its allocation's) and the layout [`GBufferPass::record`]
    /// leaves it in.
    pub(super) fn named_images(&self) -> [(&Image, &'static str, vk::ImageLayout); 6] {
        let [normals, albedo, motion] = &self.colors;
        [
            (&self.depth, "G-buffer depth", DEPTH_READ_LAYOUT),
            (normals, "G-buffer normals", COLOR_READ_LAYOUT),
            (albedo, "G-buffer albedo", COLOR_READ_LAYOUT),
            (motion, "G-buffer motion", COLOR_READ_LAYOUT),
            (&self.ids, "G-buffer triangle ids", COLOR_READ_LAYOUT),
            (&self.positions, "G-buffer positions", COLOR_READ_LAYOUT),
        ]
    }

    fn images(&self) -> impl Iterator<Item = (&Image, vk::ImageLayout)> {
        std::iter::once((&self.depth, DEPTH_READ_LAYOUT))
            .chain(self.colors.iter().map(|image| (image, COLOR_READ_LAYOUT)))
    }

    /// Records copies of the images into the readback buffer, leaving them in their read
    /// layouts again.
    ///
    /// # Safety
    /// `cmd` is recording, outside rendering, after [`GBufferPass::record`] into this
    /// G-buffer (in `cmd` or a command buffer submitted before it).
    ///
    /// Synchronization: waits for the G-buffer's writes and for compute reads of it (a mask
    /// pass recorded before); leaves the buffer written and visible to the host.
    pub unsafe fn record_readback(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        let pixels = self.width as u64 * self.height as u64;
        let mut offset = 0;
        let ids = std::iter::once((&self.ids, COLOR_READ_LAYOUT));
        for (image, layout) in self.images().chain(ids) {
            let range = image.layers_range(0, 1);
            let before = Access::COMPUTE_SAMPLED_READ;
            let transfer = (layout, vk::ImageLayout::TRANSFER_SRC_OPTIMAL);
            // SAFETY: `cmd` is recording outside rendering (the contract) and the image is this
            // G-buffer's, in its read layout since GBufferPass::record left it there; the barrier
            // moves the whole layer to TRANSFER_SRC_OPTIMAL for the copy.
            unsafe {
                image_barrier(
                    device,
                    cmd,
                    image.raw(),
                    range,
                    transfer,
                    before,
                    Access::TRANSFER_READ,
                )
            };
            // SAFETY: the caller's contract; the buffer holds every image
            // (READBACK_BYTES_PER_PIXEL) and is the G-buffer's own.
            unsafe { image.record_copy_to_buffer(device, cmd, self.readback.raw(), offset) };
            let back = (vk::ImageLayout::TRANSFER_SRC_OPTIMAL, layout);
            // SAFETY: the same image and range as the barrier before the copy, now from
            // TRANSFER_SRC_OPTIMAL back to the read layout GBufferPass::record leaves it in,
            // after the copy's transfer reads.
            unsafe {
                image_barrier(
                    device,
                    cmd,
                    image.raw(),
                    range,
                    back,
                    Access::TRANSFER_READ,
                    before,
                )
            };
            let four_bytes = std::ptr::eq(image, &self.depth) || std::ptr::eq(image, &self.ids);
            offset += pixels * if four_bytes { 4 } else { 16 };
        }
        // SAFETY: `cmd` is recording outside rendering, on a queue with transfer; host reads are a
        // valid destination once the submission's fence signals.
        unsafe {
            crate::gpu::memory_barrier(device, cmd, Access::TRANSFER_WRITE, Access::HOST_READ)
        };
    }

    /// The contents copied by [`Self::record_readback`] (after its command buffer completed).
    pub fn read(&self) -> Result<GBufferContents> {
        let pixels = self.width as usize * self.height as usize;
        let words: Vec<u32> = self.readback.read(pixels * 14)?;
        let (floats, ids) = words.split_at(pixels * 13);
        let floats: Vec<f32> = floats.iter().map(|&w| f32::from_bits(w)).collect();
        let (depth, rest) = floats.split_at(pixels);
        let plane = |i: usize| -> Vec<Vec3> {
            rest[i * 4 * pixels..(i + 1) * 4 * pixels]
                .chunks_exact(4)
                .map(|v| Vec4::from_slice(v).truncate())
                .collect()
        };
        Ok(GBufferContents {
            width: self.width,
            height: self.height,
            depth: depth.to_vec(),
            normal: plane(0),
            albedo: plane(1),
            motion: plane(2),
            ids: ids.to_vec(),
        })
    }
}

/// Draws G-buffers. Immutable after creation.
pub struct GBufferPass {
    pipeline: Pipeline,
    /// Whether [`Self::record`] records its own entry and exit barriers (off:
    /// [`Self::with_host_barriers`]).
    pub(super) outer_barriers: bool,
}

impl GBufferPass {
    /// Creates the pipeline (vertex and fragment shader, depth and three colour attachments).
    pub fn new(ctx: &Context) -> Result<Self> {
        let pipeline = graphics_pipeline(
            ctx,
            GBufferPush::BYTES,
            &[
                (
                    vk::ShaderStageFlags::VERTEX,
                    "gbuffer.vert",
                    shaders::GBUFFER_VERT,
                ),
                (
                    vk::ShaderStageFlags::FRAGMENT,
                    "gbuffer.frag",
                    shaders::GBUFFER_FRAG,
                ),
            ],
            Attachments {
                depth: Some(GBUFFER_DEPTH_FORMAT),
                colors: &[
                    GBUFFER_COLOR_FORMAT,
                    GBUFFER_COLOR_FORMAT,
                    GBUFFER_COLOR_FORMAT,
                    GBUFFER_ID_FORMAT,
                    GBUFFER_COLOR_FORMAT,
                ],
            },
        )?;
        Ok(Self {
            pipeline,
            outer_barriers: true,
        })
    }

    /// Records `draws` at shutter time `time` from `camera` into `target` (cleared first:
    /// depth 1, colours 0).
    ///
    /// # Safety
    /// `cmd` was allocated from the pass's device, is recording, outside rendering, on a
    /// graphics queue; the draw list's update was recorded before it (as for the collection
    /// pass), and its buffers stay alive until `cmd` completes.
    ///
    /// Synchronization: waits for earlier compute sampled reads and transfer reads of the
    /// images (their contents are discarded); leaves them written, in their read layouts
    /// (depth `DEPTH_STENCIL_READ_ONLY_OPTIMAL`, colours `SHADER_READ_ONLY_OPTIMAL`), visible
    /// to compute shaders' sampled reads. Both barriers are the transitions
    /// `Barrier::between` derives from [`Self::accesses`] and [`GBuffer::earlier_accesses`] /
    /// [`GBuffer::read_accesses`]; a pass made [`Self::with_host_barriers`] records neither
    /// (the host issues them, and the images are left in their attachment layouts). State changed: the bound graphics pipeline, push
    /// constants, viewport, scissor.
    pub unsafe fn record(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        draws: &DrawList,
        camera: &GBufferCamera,
        time: f32,
        target: &GBuffer,
    ) {
        let this = self.accesses(draws, target);
        let check = draws.buffer().access_check();
        if self.outer_barriers {
            let entry = Barrier::between(&target.earlier_accesses(), &this);
            // SAFETY: `cmd` is recording outside rendering on a graphics queue (the contract);
            // the images are the target's own, alive as long as `target`, in their read
            // layouts (where the pass and the readback leave them) or discarded from UNDEFINED
            // (the entry's transitions: the pass draws over them whole).
            unsafe { record_own(device, cmd, check, "G-buffer entry", entry.as_ref()) };
        }
        this.declare_run(check, "G-buffer");
        let [normal, albedo, motion] = target.colors.each_ref().map(|image| image.layer_view(0));
        let colors = [
            (normal, 0),
            (albedo, 0),
            (motion, 0),
            (target.ids.layer_view(0), u32::MAX),
            (target.positions.layer_view(0), 0),
        ];
        let depth = Some((target.depth.layer_view(0), 1.0));
        // SAFETY: the target's views are attachments of the pipeline's formats (GBufferPass::new
        // made it with them) and of `target`'s size; `cmd` is outside rendering (the contract).
        unsafe { begin_rendering_colors(device, cmd, target.width, target.height, depth, &colors) };
        // SAFETY: rendering has begun with the attachments this graphics pipeline was made for.
        unsafe { self.pipeline.bind(device, cmd) };
        for (index, record) in draws.records().iter().enumerate() {
            if record.triangle_count == 0 {
                continue;
            }
            let constants = GBufferPush {
                view_proj: camera.view_proj,
                eye: camera.eye.extend(1.0),
                draws: draws.address(),
                draw_index: index as u32,
                time,
            };
            // SAFETY: the pipeline bound above has this push-constant struct as its layout's range
            // (GBufferPush, the size GBufferPass::new gave it).
            unsafe { self.pipeline.push(device, cmd, &constants) };
            // SAFETY: the caller's contract; rendering began above with the pipeline's
            // attachment formats.
            unsafe { device.cmd_draw(cmd, 3 * record.triangle_count, 1, 0, 0) };
        }
        // SAFETY: rendering began above.
        unsafe { device.cmd_end_rendering(cmd) };
        if self.outer_barriers {
            let exit = Barrier::between(&this, &target.read_accesses());
            // SAFETY: rendering has ended, so the attachments may change layout: the same
            // images, from the attachment layouts the pass drew them in to their read layouts.
            unsafe { record_own(device, cmd, check, "G-buffer exit", exit.as_ref()) };
        }
    }
}
