//! Ordinary shadow maps at given times: the nearest depth (and triangle id) per texel, one
//! layer per time. The baseline for static scenes, the brute-force reference's per-slice map,
//! and time-dependent shadow maps (one depth-only layer per time stratum).
//!
//! Drawn as anyone who picks these methods would draw them: into a D32 depth attachment,
//! LESS test, so that the device's early and hierarchical depth rejection work; depth-only
//! maps without a fragment shader; maps with ids write them to an R32_UINT colour attachment
//! after an early depth test. No depth bias in the pipeline: every method gets the same
//! receiver test in the lighting pass (the normal offset or the receiver plane), which costs
//! the shadow pass nothing. The lookups read buffers by address, so the attachments are then
//! copied into buffers ([`PlainShadowPass::record_copy_out`], timed apart by the renderer).

use super::collection::draw_each;
use super::draws::DrawList;
use super::gpu_types::{DepthFormat, NO_TRIANGLE, PlainMapHeader};
use super::plain_shadow_steps::{Step, step_barrier};
use super::push_constants::{MapDrawPush, PushBlock};
use super::shaders;
use super::view::LightView;
use crate::error::{Error, Result};
use crate::gpu::{
    Access, Attachments, Buffer, BufferUsage, Context, Image, Pipeline, begin_rendering,
    graphics_pipeline,
};
use ash::vk;
use glam::UVec4;

/// The depth attachment's format: 32-bit float, as precise as the ranges' linear depths where
/// it matters (near the light).
pub const SHADOW_DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;
/// The triangle ids' attachment.
const ID_FORMAT: vk::Format = vk::Format::R32_UINT;

/// `layers` shadow maps of `width` x `height`: the attachments they are drawn into and the
/// buffers the lookups read.
pub struct PlainShadowMap {
    width: u32,
    height: u32,
    layers: u32,
    format: DepthFormat,
    depth_image: Image,
    /// [`DepthFormat::DepthAndId`]: the triangle ids' attachment.
    id_image: Option<Image>,
    /// The header (`PlainHeader` in shared.glsl): light, size and the planes' addresses.
    pub(crate) header: Buffer,
    /// The layers' depths (z/w floats), copied out of the depth attachment.
    pub(crate) depths: Buffer,
    /// [`DepthFormat::DepthAndId`]: the layers' triangle ids, copied out of their attachment.
    pub ids: Option<Buffer>,
    /// Whether the last recorded pass drew the layers for a moving light (the shading then
    /// reads each layer with the light at its time).
    recorded_moving: std::sync::atomic::AtomicBool,
}

impl PlainShadowMap {
    /// `layers` maps of `width` x `height` texels of `format` (one per frame in flight).
    pub fn new(
        ctx: &Context,
        width: u32,
        height: u32,
        layers: u32,
        format: DepthFormat,
    ) -> Result<Self> {
        let layers = layers.max(1);
        let texels = width as u64 * height as u64 * layers as u64;
        let limit = ctx.max_addressed_buffer_bytes();
        if width == 0 || height == 0 {
            return Err(Error::InvalidArgument(format!(
                "shadow map size {width}x{height}"
            )));
        }
        if texels * 4 > limit {
            return Err(Error::DeviceLimit {
                what: "the ordinary shadow maps",
                count: texels,
                element_bytes: 4,
                needed_bytes: texels * 4,
                limit_bytes: limit,
            });
        }
        let size = (width, height, layers);
        let attachment = |name: &str, format: vk::Format, usage: vk::ImageUsageFlags| {
            Image::new(
                ctx,
                name,
                size,
                format,
                usage | vk::ImageUsageFlags::TRANSFER_SRC,
            )
        };
        let planes = |name: &str| Buffer::new(ctx, name, texels * 4, BufferUsage::Storage);
        let with_ids = format == DepthFormat::DepthAndId;
        Ok(Self {
            width,
            height,
            layers,
            format,
            depth_image: attachment(
                "ordinary shadow maps' depth attachment",
                SHADOW_DEPTH_FORMAT,
                vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            )?,
            id_image: with_ids
                .then(|| {
                    attachment(
                        "ordinary shadow maps' id attachment",
                        ID_FORMAT,
                        vk::ImageUsageFlags::COLOR_ATTACHMENT,
                    )
                })
                .transpose()?,
            header: Buffer::new(
                ctx,
                "ordinary shadow map header",
                header_bytes(layers).len() as u64,
                BufferUsage::Storage,
            )?,
            depths: planes("ordinary shadow maps' depths")?,
            ids: with_ids
                .then(|| planes("ordinary shadow maps' ids"))
                .transpose()?,
            recorded_moving: std::sync::atomic::AtomicBool::new(false),
        })
    }
    /// Whether the last recorded pass drew the layers for a moving light ([`LightView::end`]).
    pub(crate) fn recorded_for_moving_light(&self) -> bool {
        self.recorded_moving
            .load(std::sync::atomic::Ordering::Relaxed)
    }
    /// Maps in the buffer.
    pub fn layers(&self) -> u32 {
        self.layers
    }
    /// What each texel holds.
    pub fn format(&self) -> DepthFormat {
        self.format
    }
    /// The device address of the header.
    pub fn header_address(&self) -> u64 {
        self.header.device_address()
    }
    /// Bytes of the maps' texels (the papers' figure for TSM: layers x 4 x pixels; 8 with
    /// ids). The buffers the lookups read hold a copy of as many again.
    pub fn bytes(&self) -> u64 {
        self.width as u64 * self.height as u64 * self.layers as u64 * self.format.bytes()
    }
    fn attachments(&self) -> impl Iterator<Item = &Image> {
        std::iter::once(&self.depth_image).chain(self.id_image.as_ref())
    }

    /// The attachments with their names (their allocations').
    pub(super) fn named_attachments(&self) -> impl Iterator<Item = (&Image, &'static str)> {
        std::iter::once((&self.depth_image, "ordinary shadow map depth attachment")).chain(
            self.id_image
                .as_ref()
                .map(|i| (i, "ordinary shadow map id attachment")),
        )
    }

    /// The planes' buffers (depths, and ids with [`DepthFormat::DepthAndId`]) with names.
    pub(super) fn named_planes(&self) -> impl Iterator<Item = (&Buffer, &'static str)> {
        std::iter::once((&self.depths, "ordinary shadow map depths"))
            .chain(self.ids.as_ref().map(|b| (b, "ordinary shadow map ids")))
    }
}

/// Whether a device whose optimal-tiling format features are `features` can draw the
/// ordinary maps: a D32_SFLOAT depth attachment and an R32_UINT colour attachment.
fn check_attachment_formats(features: impl Fn(vk::Format) -> vk::FormatFeatureFlags) -> Result<()> {
    for (format, usage, what) in [
        (
            SHADOW_DEPTH_FORMAT,
            vk::FormatFeatureFlags::DEPTH_STENCIL_ATTACHMENT,
            "D32_SFLOAT depth attachments (ordinary shadow maps)",
        ),
        (
            ID_FORMAT,
            vk::FormatFeatureFlags::COLOR_ATTACHMENT,
            "R32_UINT colour attachments (ordinary shadow maps' ids)",
        ),
    ] {
        if !features(format).contains(usage) {
            return Err(Error::MissingFeatures(format!(
                "the device cannot render to {what}"
            )));
        }
    }
    Ok(())
}

/// Renders ordinary shadow maps. Immutable after creation.
pub struct PlainShadowPass {
    /// Depth-only maps: vertex shader alone.
    depth_only: Pipeline,
    /// Maps with ids: the fragment shader writes the id after the early depth test.
    depth_and_id: Pipeline,
}

impl PlainShadowPass {
    /// Creates the pipelines; fails with [`Error::MissingFeatures`] on a device that cannot
    /// render to the D32 depth format or the R32_UINT colour format.
    pub fn new(ctx: &Context) -> Result<Self> {
        check_attachment_formats(|format| ctx.optimal_tiling_features(format))?;
        let vertex = (
            vk::ShaderStageFlags::VERTEX,
            "shadow_depth.vert",
            shaders::SHADOW_DEPTH_VERT,
        );
        let fragment = (
            vk::ShaderStageFlags::FRAGMENT,
            "shadow_depth.frag",
            shaders::SHADOW_DEPTH_FRAG,
        );
        let depth = Some(SHADOW_DEPTH_FORMAT);
        Ok(Self {
            depth_only: graphics_pipeline(
                ctx,
                MapDrawPush::BYTES,
                &[vertex],
                Attachments { depth, colors: &[] },
            )?,
            depth_and_id: graphics_pipeline(
                ctx,
                MapDrawPush::BYTES,
                &[vertex, fragment],
                Attachments {
                    depth,
                    colors: &[ID_FORMAT],
                },
            )?,
        })
    }

    /// Renders layer i of `map` with the scene at `times[i]`, seen from `light`, and copies
    /// the maps out for the lookups ([`Self::record_render`] then [`Self::record_copy_out`]).
    ///
    /// # Safety
    /// As [`super::CollectionPass::record`] (for `map` instead of a temporal map).
    ///
    /// Synchronization and state: as the two halves.
    pub unsafe fn record(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        draws: &DrawList,
        light: &LightView,
        map: &PlainShadowMap,
        times: &[f32],
    ) {
        // SAFETY: this function's contract is both halves' (CollectionPass::record's, for `map`),
        // and record_copy_out follows record_render in the same command buffer, as it requires.
        unsafe {
            self.record_render(device, cmd, draws, light, map, times);
            self.record_copy_out(device, cmd, map);
        }
    }

    /// Renders layer i of `map` with the scene at `times[i]` into the map's attachments
    /// (cleared first: depth 1, ids [`NO_TRIANGLE`]), and writes its header for `light`
    /// (a moving light's pose at each layer's time: [`LightView::moving_to`]).
    ///
    /// # Safety
    /// As [`super::CollectionPass::record`] (for `map` instead of a temporal map); must be
    /// followed by [`Self::record_copy_out`] before the lookups read `map`.
    ///
    /// Synchronization: waits for earlier shader reads of the header and transfer reads of
    /// the attachments (their contents are discarded); leaves the attachments written.
    /// State changed: the bound graphics pipeline, push constants, viewport, scissor.
    pub unsafe fn record_render(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        draws: &DrawList,
        light: &LightView,
        map: &PlainShadowMap,
        times: &[f32],
    ) {
        let header = PlainMapHeader {
            light: light.gpu(),
            size: UVec4::new(map.width, map.height, map.layers, map.format as u32),
            depths: map.depths.device_address(),
            ids: map.ids.as_ref().map_or(0, |b| b.device_address()),
        };
        // SAFETY: `cmd` is recording outside any render pass on a graphics and compute queue (the
        // contract), so every shader stage and transfer are supported.
        unsafe { step_barrier(device, cmd, map, &[Step::HeaderReads], &[Step::HeaderWrite]) };
        let mut bytes = header_bytes(map.layers);
        bytes[..HEADER].copy_from_slice(bytemuck::bytes_of(&header));
        bytes[HEADER..TIMES].copy_from_slice(bytemuck::bytes_of(&light.gpu_end()));
        map.recorded_moving
            .store(light.is_moving(), std::sync::atomic::Ordering::Relaxed);
        for (k, t) in times.iter().take(map.layers as usize).enumerate() {
            bytes[TIMES + 4 * k..TIMES + 4 * k + 4].copy_from_slice(&t.to_le_bytes());
        }
        // SAFETY: the map's header buffer, made with this size (header_bytes) and
        // transfer-destination usage; outside rendering, after its earlier readers (the barrier
        // above).
        unsafe { map.header.record_write(device, cmd, &bytes) };
        // SAFETY: the same command buffer, outside rendering; stages its queue supports. The
        // attachments are the map's own, alive as long as `map`, all their layers; their
        // contents are discarded (from UNDEFINED), which the render clears, after the last
        // copy out of them.
        unsafe {
            step_barrier(device, cmd, map, &[Step::HeaderWrite], &[Step::HeaderReads]);
            step_barrier(device, cmd, map, &[Step::CopyOut], &[Step::Draw]);
        }
        let pipeline = match map.format {
            DepthFormat::DepthOnly => &self.depth_only,
            DepthFormat::DepthAndId => &self.depth_and_id,
        };
        for (layer, &t) in times.iter().enumerate().take(map.layers as usize) {
            let layer = layer as u32;
            // SAFETY: outside rendering (the previous layer's rendering ended below), with the
            // map's attachment views of this layer, whose formats are the ones this pipeline was
            // made for (map.format picked it).
            unsafe {
                begin_rendering(
                    device,
                    cmd,
                    map.width,
                    map.height,
                    Some((map.depth_image.layer_view(layer), 1.0)),
                    map.id_image
                        .as_ref()
                        .map(|ids| (ids.layer_view(layer), NO_TRIANGLE)),
                )
            };
            // SAFETY: rendering has begun with this pipeline's attachment formats; the pipeline is
            // this pass's, alive as long as `self`.
            unsafe { pipeline.bind(device, cmd) };
            let constants = MapDrawPush {
                map: map.header_address(),
                time: t,
                ..MapDrawPush::default()
            };
            draw_each(device, cmd, pipeline, draws, constants);
            // SAFETY: this layer's rendering began above and its draws are recorded.
            unsafe { device.cmd_end_rendering(cmd) };
        }
    }

    /// Copies the attachments that [`Self::record_render`] drew into the buffers the lookups
    /// read.
    ///
    /// # Safety
    /// As [`Self::record_render`], which it follows.
    ///
    /// Synchronization: waits for the attachments' writes and earlier shader reads of the
    /// buffers; leaves the buffers written and visible to shader reads in every stage.
    pub unsafe fn record_copy_out(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        map: &PlainShadowMap,
    ) {
        // SAFETY: `cmd` is recording outside rendering (the contract, record_render having ended
        // its rendering), on a queue with every shader stage and transfer; the attachments are
        // the map's own, all their layers, in the attachment layouts record_render left them in,
        // moved to TRANSFER_SRC_OPTIMAL for the copies.
        unsafe {
            step_barrier(
                device,
                cmd,
                map,
                &[Step::PlanesRead, Step::Draw],
                &[Step::CopyOut],
            )
        };
        let planes = [Some(&map.depths), map.ids.as_ref()];
        for (image, buffer) in map.attachments().zip(planes.into_iter().flatten()) {
            // SAFETY: the image is in TRANSFER_SRC_OPTIMAL (above), and the map's buffer for this
            // plane holds width x height x layers texels of its format, copied from offset 0.
            unsafe { image.record_copy_to_buffer(device, cmd, buffer.raw(), 0) };
        }
        // SAFETY: outside rendering; transfer and every shader stage are on this queue.
        unsafe { step_barrier(device, cmd, map, &[Step::CopyOut], &[Step::PlanesRead]) };
    }
}

/// The layout an attachment is drawn in and the accesses drawing makes to it.
pub(super) fn attachment_state(image: &Image) -> (vk::ImageLayout, Access) {
    if image.aspect() == vk::ImageAspectFlags::DEPTH {
        (
            vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
            Access::DEPTH_ATTACHMENT,
        )
    } else {
        (
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            Access::COLOR_ATTACHMENT_WRITE,
        )
    }
}

/// Where a moving light's pose at t = 1 ([`super::GpuLightEnd`]) starts in an ordinary map's
/// header buffer (shared.glsl's `PLAIN_LIGHT_END_OFFSET`), and where the layers' times start
/// (`PLAIN_LAYER_TIMES_OFFSET`): every layer is drawn and read with the light at its time.
const HEADER: usize = std::mem::size_of::<PlainMapHeader>();
const TIMES: usize = HEADER + std::mem::size_of::<super::GpuLightEnd>();

/// The header buffer's bytes for `layers` layers (zeros).
fn header_bytes(layers: u32) -> Vec<u8> {
    vec![0; TIMES + 4 * layers as usize]
}

const _: () = assert!(HEADER == 224 && TIMES == 384);

#[cfg(test)]
mod tests {
    use super::*;

    /// Each format the ordinary maps draw into, when the device cannot render to it, gives
    /// an error naming it; with both, none.
    #[test]
    fn a_device_without_the_attachment_formats_is_refused_by_name() {
        let depth = vk::FormatFeatureFlags::DEPTH_STENCIL_ATTACHMENT;
        let colour = vk::FormatFeatureFlags::COLOR_ATTACHMENT;
        let device = |d: vk::FormatFeatureFlags, c: vk::FormatFeatureFlags| {
            move |format| match format {
                vk::Format::D32_SFLOAT => d,
                vk::Format::R32_UINT => c,
                _ => depth | colour,
            }
        };
        assert!(check_attachment_formats(device(depth, colour)).is_ok());
        for (d, c, named) in [
            (vk::FormatFeatureFlags::empty(), colour, "D32_SFLOAT"),
            (colour, colour, "D32_SFLOAT"),
            (depth, vk::FormatFeatureFlags::empty(), "R32_UINT"),
            (depth, depth, "R32_UINT"),
        ] {
            match check_attachment_formats(device(d, c)) {
                Err(Error::MissingFeatures(message)) => {
                    assert!(message.contains(named), "{message}")
                }
                other => panic!("{d:?} / {c:?}: {other:?}"),
            }
        }
    }
}
