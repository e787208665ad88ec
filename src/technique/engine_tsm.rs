//! Time-dependent shadow maps (Akenine-Moller, Munkberg and Hasselgren 2007) as an engine
//! builds them, for the deferred frame: the baseline the temporal map's
//! [`super::VisibilityMaskPass`] is compared against, built to be as fast as is honest.
//!
//! For N maps at the times t_i = (i + 0.5) / N: start a D32 depth map from the static draws'
//! map (drawn once and kept across frames, like the temporal map's kept static layer), draw
//! the moving draws at t_i into it depth-only (`shadow_depth.vert`, as
//! [`super::PlainShadowPass`] draws), and test the host's G-buffer (the same [`MaskInputs`]
//! as the temporal mask) against it: each pixel's point moved to `p + (t_i - time) * motion`,
//! tested with the temporal map's own receiver test (`ms_receiver_texel` in
//! `glsl/motion_shadows.glsl`: normal offset, receiver-plane depth, light bias) against the
//! map's depth read through a sampled image, and counted lit or not. The host's image ends as
//! the lit fraction of the N times, which converges to the shutter's lit fraction as N grows
//! (error at most about 1/N plus a texel's worth of motion).
//!
//! The maps are drawn in batches of [`EngineTsmMap::layers`] (the layers of the working map,
//! an array image), and one compute dispatch (`glsl/tsm_mask.comp`) tests every pixel against
//! the batch's maps: the pixel's G-buffer point, normal and the light are read once per
//! batch, the output image read and written once per batch (the first batch writes its count
//! of lit maps, later ones add theirs, the last scales the sum by 1/N). On lavapipe that per-pixel work, not the lookups, is most
//! of a dispatch, so layers trade memory (4 bytes per texel and layer) for time: at a
//! 1920x1080 G-buffer and 2048x2048 maps a map costs about 230-260 ms of GPU time with 1
//! layer, 75-95 with 4, 50-70 with 8 and 42-45 with 16 (in CPU time, both cores together,
//! about 400, 140, 90 and 70 ms), of which drawing the moving draws and starting the layer is
//! 2-5 ms (`examples/engine_tsm_costs.rs`, on 2 cores shared with other work: the figures
//! vary by a fifth from run to run).
//!
//! How each map starts from the static draws is [`TsmStart`]: an image copy of the static
//! map into the working map's layer ([`TsmStart::Copy`]), or a cleared layer and a second
//! lookup of the static map in the mask shader ([`TsmStart::SecondLookup`]). Both give the
//! same answers, bit for bit.

use super::draws::DrawList;
use super::gpu_types::{DRAW_STATIC, DepthFormat, PlainMapHeader};
use super::mask::{MaskInputs, NormalEncoding, NormalImage};
use super::push_constants::{DrawPush, MapDrawPush, PushBlock, TsmMaskPush};
use super::shaders;
use super::shadow_map::StaticLayerSource;
use super::view::LightView;
use crate::error::{Error, Result};
use crate::gpu::{
    Access, Attachments, Buffer, BufferUsage, Context, Image, ImageBindingLayout, ImageBindings,
    Pipeline, graphics_pipeline, image_barrier, memory_barrier, specialized_compute_pipeline,
};
use crate::gpu::{Doomed, Handle};
use ash::vk;
use glam::UVec4;
use std::sync::Mutex;
use std::sync::atomic::{AtomicU32, Ordering};

/// The most maps one [`EngineTsmPass::record`] draws (the papers compare up to 64; 1,024
/// leaves room for a reference, and keeps the count of lit maps exact in the R32 image).
pub const MAX_TSM_MAPS: u32 = 1024;
/// The most layers an [`EngineTsmMap`]'s working map may have (maps per dispatch).
pub const MAX_TSM_LAYERS: u32 = 64;

/// The maps' format: 32-bit float depth, as the ordinary shadow maps.
const MAP_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// How each of the N maps starts from the static draws' map.
///
/// Measured on lavapipe (2 cores; `examples/engine_tsm_costs.rs`, 1920x1080 G-buffer, 2048x2048
/// maps, 8 maps per dispatch): a copy of one map costs 1.3 ms and a clear 0.8 ms, but the
/// second lookup costs about 4 ms per map over the 1080p G-buffer (TSM-16: 797 ms with copies,
/// 867 ms with second lookups, the least of 20 runs each), so copying is the default. On a
/// GPU both are cheap and the balance may differ: measure there.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum TsmStart {
    /// Copy the static map into the working map's layer (a depth image copy per map), then
    /// draw the moving draws into it: one lookup per pixel and map.
    #[default]
    Copy,
    /// Clear the working map's layer (the render pass's load op), draw the moving draws into
    /// it, and look up both it and the static map per pixel (the nearer depth wins): no copy,
    /// two lookups.
    SecondLookup,
}

/// Bytes of the header: the light and the map's size (a [`PlainMapHeader`], so that
/// `shadow_depth.vert` reads it as it reads an ordinary map's).
const HEADER_BYTES: u64 = std::mem::size_of::<PlainMapHeader>() as u64;

/// The maps of one light (per frame in flight and light): the static draws' depth map, kept
/// across frames, and the working depth maps (an array of [`Self::layers`]) the N times are
/// drawn into, a batch at a time.
pub struct EngineTsmMap {
    shared: std::sync::Arc<crate::gpu::Shared>,
    width: u32,
    height: u32,
    layers: u32,
    start: TsmStart,
    /// The static draws, drawn once (and again when the light or the static draws change).
    /// Rests in `static_resting_layout(start)` between uses.
    static_map: Image,
    /// A batch of maps, one per layer: moving draws (and, with [`TsmStart::Copy`], the
    /// static ones).
    working: Image,
    /// A 2D array view of every layer of `working`, for the mask shader (destroyed here).
    working_array: vk::ImageView,
    /// [`PlainMapHeader`]: the light (read by `shadow_depth.vert` and the mask shader).
    header: Buffer,
    /// What the static map holds for keeping ([`LightView::keep_static_layer`]): `.0` drawn
    /// by a pass the host said it submitted, `.1` by the last recorded pass that drew it,
    /// until then ([`Self::static_map_submitted`]).
    static_source: Mutex<(Option<StaticLayerSource>, Option<StaticLayerSource>)>,
    /// Times [`EngineTsmPass::record`] has drawn the static map.
    static_builds: AtomicU32,
}

impl EngineTsmMap {
    /// Maps of `width` x `height` texels (each side at most the device's
    /// maxImageDimension2D, 4,096 or more), drawn `layers` at a time (1 to
    /// [`MAX_TSM_LAYERS`]: the working map's layers, 4 bytes a texel each), started from the
    /// static map as `start` says. Errors on a zero size or a layer count out of range, and
    /// on a device that cannot draw, sample and copy D32_SFLOAT depth images.
    pub fn new(
        ctx: &Context,
        width: u32,
        height: u32,
        layers: u32,
        start: TsmStart,
    ) -> Result<Self> {
        check_map_format(|format| ctx.optimal_tiling_features(format))?;
        if width == 0 || height == 0 {
            return Err(Error::InvalidArgument(format!(
                "time-dependent shadow map size {width}x{height}"
            )));
        }
        if layers == 0 || layers > MAX_TSM_LAYERS {
            return Err(Error::InvalidArgument(format!(
                "{layers} time-dependent shadow map layers (1 to {MAX_TSM_LAYERS})"
            )));
        }
        let usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::SAMPLED;
        let static_map = Image::new(
            ctx,
            "time-dependent shadow maps' static map",
            (width, height, 1),
            MAP_FORMAT,
            usage | vk::ImageUsageFlags::TRANSFER_SRC,
        )?;
        let working = Image::new(
            ctx,
            "time-dependent shadow maps' working maps",
            (width, height, layers),
            MAP_FORMAT,
            usage | vk::ImageUsageFlags::TRANSFER_DST,
        )?;
        let view_info = vk::ImageViewCreateInfo::default()
            .image(working.raw())
            .view_type(vk::ImageViewType::TYPE_2D_ARRAY)
            .format(MAP_FORMAT)
            .subresource_range(working.layers_range(0, layers));
        // SAFETY: a view of the image just made, destroyed by Drop before it.
        let working_array =
            unsafe { ctx.device().create_image_view(&view_info, None) }.map_err(|result| {
                Error::Vulkan {
                    call: "vkCreateImageView",
                    result,
                }
            })?;
        let header = Buffer::new(
            ctx,
            "time-dependent shadow maps' header",
            HEADER_BYTES,
            BufferUsage::Storage,
        );
        let map = Self {
            shared: ctx.shared.clone(),
            width,
            height,
            layers,
            start,
            static_map,
            working,
            working_array,
            header: match header {
                Ok(header) => header,
                Err(e) => {
                    // SAFETY: the view was made above and is in no command buffer.
                    unsafe { ctx.device().destroy_image_view(working_array, None) };
                    return Err(e);
                }
            },
            static_source: Mutex::new((None, None)),
            static_builds: AtomicU32::new(0),
        };
        Ok(map)
    }

    /// Texels across.
    pub fn width(&self) -> u32 {
        self.width
    }
    /// Texels down.
    pub fn height(&self) -> u32 {
        self.height
    }
    /// Maps drawn per dispatch: the working map's layers.
    pub fn layers(&self) -> u32 {
        self.layers
    }
    /// How each map starts from the static map.
    pub fn start(&self) -> TsmStart {
        self.start
    }
    /// Bytes of the depth maps: the static map and the working map's layers (4 per texel
    /// each).
    pub fn bytes(&self) -> u64 {
        (1 + self.layers as u64) * 4 * self.width as u64 * self.height as u64
    }
    /// The device address of the header (the light, then the size: `PlainHeader` in
    /// shared.glsl, without depth buffers).
    pub fn header_address(&self) -> u64 {
        self.header.device_address()
    }

    /// How many times [`EngineTsmPass::record`] has drawn the static map (with
    /// [`LightView::keep_static_layer`], once per change of light or static draws).
    pub fn static_map_builds(&self) -> u32 {
        self.static_builds.load(Ordering::Relaxed)
    }

    /// Makes the next record redraw the static map, kept or not: call it when a static
    /// draw's buffer contents changed in place.
    pub fn forget_static_map(&self) {
        *self.static_source.lock().unwrap_or_else(|e| e.into_inner()) = (None, None);
    }

    /// Tells the map that the command buffer with its last recorded [`EngineTsmPass::record`]
    /// was submitted: a static map that pass drew may then be kept by later records (with
    /// [`LightView::keep_static_layer`]). As `TemporalShadowMap::static_layer_submitted`: a
    /// recorded pass that is not submitted needs nothing undone; without the call the static
    /// map is redrawn by every record.
    pub fn static_map_submitted(&self) {
        let mut state = self.static_source.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(recorded) = state.1.take() {
            state.0 = Some(recorded);
        }
    }

    /// Whether the static map must be drawn for `source` (and notes it as drawn, kept once
    /// submitted if `keep`).
    fn take_static_redraw(&self, source: StaticLayerSource, keep: bool) -> bool {
        let mut state = self.static_source.lock().unwrap_or_else(|e| e.into_inner());
        if keep && state.0.as_ref() == Some(&source) {
            return false;
        }
        *state = (None, keep.then_some(source));
        self.static_builds.fetch_add(1, Ordering::Relaxed);
        true
    }
}

impl Drop for EngineTsmMap {
    fn drop(&mut self) {
        // Retired before the images (which drop after this), destroyed in that order.
        self.shared
            .retire(Doomed::handles(vec![Handle::ImageView(self.working_array)]));
    }
}

/// Whether a device whose optimal-tiling format features are `features` can draw, sample and
/// copy D32_SFLOAT depth maps.
fn check_map_format(features: impl Fn(vk::Format) -> vk::FormatFeatureFlags) -> Result<()> {
    let needed = vk::FormatFeatureFlags::DEPTH_STENCIL_ATTACHMENT
        | vk::FormatFeatureFlags::SAMPLED_IMAGE
        | vk::FormatFeatureFlags::TRANSFER_SRC
        | vk::FormatFeatureFlags::TRANSFER_DST;
    if !features(MAP_FORMAT).contains(needed) {
        return Err(Error::MissingFeatures(
            "the device cannot draw, sample and copy D32_SFLOAT depth images (time-dependent shadow maps)".into(),
        ));
    }
    Ok(())
}

// The mask's flags, shared with glsl/tsm_mask.comp through the generated constants.
use super::gpu_constants::{
    MASK_HAS_NORMALS as HAS_NORMALS, MASK_NORMALS_UNORM as NORMALS_UNORM,
    TSM_FIRST_BATCH as FIRST_BATCH, TSM_LAST_BATCH as LAST_BATCH,
};

/// Sampled reads of the mask shader (the working and static maps).
const COMPUTE_SAMPLED_READ: Access = Access::COMPUTE_SAMPLED_READ;
/// The mask shader's read-modify-write of the output image.
const COMPUTE_STORAGE_RW: Access = Access::COMPUTE_RW;

/// What one record binds: the descriptor set of the host's images and the two maps. One per
/// record that may be pending at the same time (per frame in flight and light), used once
/// per command buffer. Made by [`EngineTsmPass::bindings`].
pub struct EngineTsmBindings {
    images: ImageBindings,
}

/// Records time-dependent shadow maps and their mask. Immutable after creation: one serves
/// every frame in flight and every light.
pub struct EngineTsmPass {
    /// Depth-only drawing of the draws at one time (`shadow_depth.vert`, no fragment shader).
    depth_only: Pipeline,
    layout: ImageBindingLayout,
    /// Mask pipelines, indexed by `moving as usize + 2 * second_lookup as usize`.
    masks: Vec<Pipeline>,
}

impl EngineTsmPass {
    /// Creates the pipelines; fails with [`Error::MissingFeatures`] on a device that cannot
    /// draw, sample and copy D32_SFLOAT depth images.
    pub fn new(ctx: &Context) -> Result<Self> {
        check_map_format(|format| ctx.optimal_tiling_features(format))?;
        let depth_only = graphics_pipeline(
            ctx,
            MapDrawPush::BYTES,
            &[(
                vk::ShaderStageFlags::VERTEX,
                "shadow_depth.vert",
                shaders::SHADOW_DEPTH_VERT,
            )],
            Attachments {
                depth: Some(MAP_FORMAT),
                colors: &[],
            },
        )?;
        let sampled = vk::DescriptorType::COMBINED_IMAGE_SAMPLER;
        let layout = ImageBindingLayout::new(
            ctx,
            &[
                sampled,
                sampled,
                sampled,
                vk::DescriptorType::STORAGE_IMAGE,
                sampled,
                sampled,
                sampled,
            ],
        )?;
        let masks = [[0, 0], [1, 0], [0, 1], [1, 1]]
            .iter()
            .map(|constants| {
                specialized_compute_pipeline(
                    ctx,
                    &[&layout],
                    TsmMaskPush::BYTES,
                    "tsm_mask.comp",
                    shaders::TSM_MASK_COMP,
                    constants,
                )
            })
            .collect::<Result<_>>()?;
        Ok(Self {
            depth_only,
            layout,
            masks,
        })
    }

    /// The bindings for one record in flight.
    pub fn bindings(&self) -> Result<EngineTsmBindings> {
        Ok(EngineTsmBindings {
            images: self.layout.allocate()?,
        })
    }

    /// Records `maps` (N) time-dependent shadow maps of `draws` lit by `light` into `map`,
    /// and the lit fraction of the N times into the host's `inputs.output`. First the static
    /// map, when it must be drawn: at every record, or with [`LightView::keep_static_layer`]
    /// only when the light's view or projection or the static draws' descriptions changed
    /// since its last submitted build ([`EngineTsmMap::static_map_submitted`]; or after
    /// [`EngineTsmMap::forget_static_map`]). Then, per batch
    /// of [`EngineTsmMap::layers`] maps: each layer started from the static map (a copy, or a
    /// clear), the moving draws drawn into it at its time, and one mask dispatch. Errors,
    /// recording nothing, when `maps` is 0 or above [`MAX_TSM_MAPS`], when `inputs.size` is
    /// 0 on a side, or when `inputs.motion` is given and `inputs.time` is not in [0, 1].
    ///
    /// # Safety
    /// - `cmd` was allocated from the device the pass and `map` were made on, is recording,
    ///   outside any render pass or dynamic rendering, on a queue with graphics and compute.
    /// - `bindings` was made by this pass and no command buffer using it is pending or has
    ///   it bound in `cmd` (its set is rewritten here).
    /// - No other command buffer recording `map` is pending unless it was submitted earlier
    ///   to the same queue (its header and working map are rewritten; one map per frame in
    ///   flight and light).
    /// - The views are valid, of the device, with the sizes and layouts [`MaskInputs`]
    ///   states, and stay alive until `cmd` completes; here the output must be an
    ///   `R32_SFLOAT` image with storage usage (the shader reads back its count between
    ///   batches of maps), in `GENERAL` layout.
    /// - The draws' buffers are as [`super::Draw`] requires; `draws` was updated
    ///   ([`DrawList::record_update`]) earlier in `cmd` or in a command buffer submitted
    ///   before it.
    /// - The host has made its writes to the depth, normal and motion images visible to
    ///   `COMPUTE_SHADER` sampled reads, and ordered earlier accesses of the output image
    ///   before `COMPUTE_SHADER` storage reads and writes, with its own barriers (image layout
    ///   transitions included).
    ///
    /// Synchronization: waits for earlier shader reads of the header, earlier uses of the
    /// maps by this pass (they are in no other hands). Leaves the output written by
    /// `COMPUTE_SHADER` (`SHADER_STORAGE_WRITE`, after reads of it there), in `GENERAL`
    /// layout; the host's barrier makes it visible to its lighting. The working map is left
    /// in `SHADER_READ_ONLY_OPTIMAL`, the static map in `SHADER_READ_ONLY_OPTIMAL`
    /// ([`TsmStart::SecondLookup`]) or `TRANSFER_SRC_OPTIMAL` ([`TsmStart::Copy`]).
    /// State changed: the bound graphics and compute pipelines, descriptor set 0 of the
    /// compute bind point, push constants, viewport, scissor.
    #[allow(clippy::too_many_arguments)]
    pub unsafe fn record(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        bindings: &mut EngineTsmBindings,
        inputs: &MaskInputs,
        draws: &DrawList,
        light: &LightView,
        map: &EngineTsmMap,
        maps: u32,
    ) -> Result<()> {
        check_record(inputs.size, inputs.time, inputs.motion.is_some(), maps)?;
        let second_lookup = map.start == TsmStart::SecondLookup;
        let static_layout = static_resting_layout(map.start);
        let static_reads = if second_lookup {
            COMPUTE_SAMPLED_READ
        } else {
            Access::TRANSFER_READ
        };

        // The header: the light as shadow_depth.vert and the mask shader read it.
        let header = PlainMapHeader {
            light: light.gpu(),
            size: UVec4::new(map.width, map.height, 1, DepthFormat::DepthOnly as u32),
            depths: 0,
            ids: 0,
        };
        // SAFETY: `cmd` is recording outside any render pass on a graphics and compute queue (this
        // function's contract, CollectionPass::record's), so every shader stage and transfer are
        // supported.
        unsafe { memory_barrier(device, cmd, Access::ANY_SHADER_READ, Access::TRANSFER_WRITE) };
        // SAFETY: plain data of the header's size; outside a render pass (the contract).
        unsafe { map.header.record_write(device, cmd, &[header]) };
        // SAFETY: the same command buffer, outside rendering; stages its queue supports.
        unsafe { memory_barrier(device, cmd, Access::TRANSFER_WRITE, Access::ANY_SHADER_READ) };

        // The static map, unless the one kept from an earlier frame still holds these draws.
        let source = StaticLayerSource::of(light, draws);
        if map.take_static_redraw(source, light.keep_static_layer) {
            // SAFETY: the static map is this map's image (one layer), in no other hands (the
            // contract); from UNDEFINED its old contents are discarded, which the cleared redraw
            // below replaces.
            unsafe {
                image_barrier(
                    device,
                    cmd,
                    map.static_map.raw(),
                    map.static_map.layers_range(0, 1),
                    (
                        vk::ImageLayout::UNDEFINED,
                        vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                    ),
                    static_reads,
                    Access::DEPTH_ATTACHMENT,
                )
            };
            let view = map.static_map.layer_view(0);
            // SAFETY: the caller's contract; the view is in the attachment layout.
            unsafe { begin_depth(device, cmd, view, map.width, map.height, true) };
            // SAFETY: rendering into the static map began just above; the depth-only pipeline is
            // this pass's, made for D32 depth with no colours, the static map's format.
            unsafe { self.depth_only.bind(device, cmd) };
            draw_where(device, cmd, &self.depth_only, draws, map, 0.0, true);
            // SAFETY: the rendering began above and the static draws are recorded into it.
            unsafe { device.cmd_end_rendering(cmd) };
            // SAFETY: rendering has ended; the same image and range, from the attachment layout it
            // was drawn in to the layout the rest of the frame reads it in.
            unsafe {
                image_barrier(
                    device,
                    cmd,
                    map.static_map.raw(),
                    map.static_map.layers_range(0, 1),
                    (vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL, static_layout),
                    Access::DEPTH_ATTACHMENT,
                    static_reads,
                )
            };
        }

        // The host's images and the maps, for every dispatch below.
        let depth = (inputs.depth, inputs.depth_layout);
        // Without a normal or motion image (or, copying, without a second lookup) the depth
        // view stands in (never read: the flag and the variant say so).
        let normals = inputs.normals.map_or(depth, |n| (n.view, n.layout));
        let motion = inputs.motion.map_or(depth, |m| (m.view, m.layout));
        let read_only = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        let static_map = if second_lookup {
            (map.static_map.layer_view(0), read_only)
        } else {
            depth
        };
        // SAFETY: the caller's contract (the set is not in use; the views are valid).
        unsafe {
            bindings.images.write(&[
                depth,
                normals,
                motion,
                (inputs.output, vk::ImageLayout::GENERAL),
                (map.working_array, read_only),
                static_map,
                inputs.positions.map_or(depth, |p| (p.view, p.layout)),
            ])
        };
        let normal_flags = match inputs.normals {
            Some(NormalImage {
                encoding: NormalEncoding::Unorm,
                ..
            }) => HAS_NORMALS | NORMALS_UNORM,
            Some(_) => HAS_NORMALS,
            None => 0,
        } | super::mask::mask_position_flag(inputs);
        let variant = usize::from(inputs.motion.is_some()) + 2 * usize::from(second_lookup);
        let mask = &self.masks[variant];
        let working = map.working.raw();
        let all_layers = map.working.layers_range(0, map.layers);
        let inv_maps = 1.0 / maps as f32;
        for first in (0..maps).step_by(map.layers as usize) {
            let batch = map.layers.min(maps - first);
            // The working layers: their reads by the previous dispatch (or frame) are done.
            if second_lookup {
                // SAFETY: the working map is this map's image, all its `layers`; its previous
                // readers (the last dispatch, or an earlier frame's) are named as the source, and
                // UNDEFINED discards contents the second lookup redraws whole.
                unsafe {
                    image_barrier(
                        device,
                        cmd,
                        working,
                        all_layers,
                        (
                            vk::ImageLayout::UNDEFINED,
                            vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                        ),
                        COMPUTE_SAMPLED_READ,
                        Access::DEPTH_ATTACHMENT,
                    )
                };
            } else {
                // SAFETY: the working map's layers go to TRANSFER_DST_OPTIMAL for the static copy,
                // after the previous dispatch's sampled reads; from UNDEFINED, since the copy
                // overwrites every layer used.
                unsafe {
                    image_barrier(
                        device,
                        cmd,
                        working,
                        all_layers,
                        (
                            vk::ImageLayout::UNDEFINED,
                            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                        ),
                        COMPUTE_SAMPLED_READ,
                        Access::TRANSFER_WRITE,
                    )
                };
                // SAFETY: both images are the map's, in the layouts named.
                unsafe { copy_static(device, cmd, map, batch) };
                // SAFETY: the copy into the working layers is recorded; the same image and layers
                // move from TRANSFER_DST_OPTIMAL to the attachment layout the moving draws load.
                unsafe {
                    image_barrier(
                        device,
                        cmd,
                        working,
                        all_layers,
                        (
                            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                            vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                        ),
                        Access::TRANSFER_WRITE,
                        Access::DEPTH_ATTACHMENT,
                    )
                };
            }
            // SAFETY: outside rendering (the barrier above ended any); the depth-only pipeline is
            // this pass's, alive as long as `self`.
            unsafe { self.depth_only.bind(device, cmd) };
            for layer in 0..batch {
                let t = ((first + layer) as f32 + 0.5) * inv_maps;
                let view = map.working.layer_view(layer);
                // SAFETY: the caller's contract; the layer is in the attachment layout.
                unsafe { begin_depth(device, cmd, view, map.width, map.height, second_lookup) };
                draw_where(device, cmd, &self.depth_only, draws, map, t, false);
                // SAFETY: this layer's rendering began above and its moving draws are recorded.
                unsafe { device.cmd_end_rendering(cmd) };
            }
            // SAFETY: all the batch's renderings have ended; the working layers leave the
            // attachment layout for the mask shader's sampled reads.
            unsafe {
                image_barrier(
                    device,
                    cmd,
                    working,
                    all_layers,
                    (vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL, read_only),
                    Access::DEPTH_ATTACHMENT,
                    COMPUTE_SAMPLED_READ,
                )
            };
            if first > 0 {
                // The previous batch's count, read and rewritten by this one.
                // SAFETY: outside rendering; compute is on this queue.
                unsafe { memory_barrier(device, cmd, COMPUTE_STORAGE_RW, COMPUTE_STORAGE_RW) };
            }
            let flags = normal_flags
                | if first == 0 { FIRST_BATCH } else { 0 }
                | if first + batch == maps { LAST_BATCH } else { 0 };
            let constants = TsmMaskPush {
                inv_view_proj: inputs.inv_view_proj,
                light: map.header_address(),
                size: [inputs.size.0, inputs.size.1],
                background_depth: inputs.background_depth,
                flags,
                map_size: [map.width, map.height],
                time: inputs.time,
                maps: maps as f32,
                inv_maps,
                first_map: first,
                batch,
                reserved: [0; 3],
            };
            // SAFETY: the mask pipeline is this pass's (its variant for this map's start), alive as
            // long as `self`; a compute bind outside rendering.
            unsafe { mask.bind(device, cmd) };
            // SAFETY: the set was written above; its views are valid (the caller's contract).
            unsafe {
                device.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::COMPUTE,
                    mask.layout(),
                    0,
                    &[bindings.images.raw()],
                    &[],
                );
            }
            // SAFETY: the mask pipeline's layout has TsmMaskPush's size as its push range.
            unsafe { mask.push(device, cmd, &constants) };
            let groups = (inputs.size.0.div_ceil(8), inputs.size.1.div_ceil(8));
            // SAFETY: the mask pipeline and its set are bound with its constants; 8x8 groups cover
            // the host's image, and the shader returns for invocations past its edges.
            unsafe { device.cmd_dispatch(cmd, groups.0, groups.1, 1) };
        }
        Ok(())
    }
}

/// The refusals of [`EngineTsmPass::record`], before anything is recorded: for a mask of
/// `size` pixels, a G-buffer at `time` (read only if `moving`) and `maps` maps.
fn check_record(size: (u32, u32), time: f32, moving: bool, maps: u32) -> Result<()> {
    if maps == 0 || maps > MAX_TSM_MAPS {
        return Err(Error::InvalidArgument(format!(
            "{maps} time-dependent shadow maps (1 to {MAX_TSM_MAPS})"
        )));
    }
    if size.0 == 0 || size.1 == 0 {
        return Err(Error::InvalidArgument(format!(
            "mask size {}x{}",
            size.0, size.1
        )));
    }
    if moving && !(0.0..=1.0).contains(&time) {
        return Err(Error::InvalidArgument(format!(
            "G-buffer time {time} (the shutter is [0, 1])"
        )));
    }
    Ok(())
}

/// The layout the static map rests in between frames: where its next use reads it.
fn static_resting_layout(start: TsmStart) -> vk::ImageLayout {
    match start {
        TsmStart::Copy => vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
        TsmStart::SecondLookup => vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
    }
}

/// Begins dynamic rendering into the depth map `view` (in `DEPTH_ATTACHMENT_OPTIMAL`),
/// cleared to 1 if `clear`, else loaded as it is, stored at the end; viewport and scissor
/// over the map.
///
/// # Safety
/// `cmd` is recording, outside rendering.
unsafe fn begin_depth(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    view: vk::ImageView,
    width: u32,
    height: u32,
    clear: bool,
) {
    let area = vk::Rect2D {
        offset: vk::Offset2D { x: 0, y: 0 },
        extent: vk::Extent2D { width, height },
    };
    let attachment = vk::RenderingAttachmentInfo::default()
        .image_view(view)
        .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
        .load_op(if clear {
            vk::AttachmentLoadOp::CLEAR
        } else {
            vk::AttachmentLoadOp::LOAD
        })
        .store_op(vk::AttachmentStoreOp::STORE)
        .clear_value(vk::ClearValue {
            depth_stencil: vk::ClearDepthStencilValue {
                depth: 1.0,
                stencil: 0,
            },
        });
    let info = vk::RenderingInfo::default()
        .render_area(area)
        .layer_count(1)
        .depth_attachment(&attachment);
    let viewport = vk::Viewport {
        x: 0.0,
        y: 0.0,
        width: width as f32,
        height: height as f32,
        min_depth: 0.0,
        max_depth: 1.0,
    };
    // SAFETY: `info` (and the attachment it points at) lives through the call; `cmd` is outside
    // rendering (this function's contract) and `view` is a depth view in DEPTH_ATTACHMENT_OPTIMAL
    // of `width` x `height` (the callers' barriers put it there), matching the render area,
    // viewport and scissor set inside the rendering.
    unsafe {
        device.cmd_begin_rendering(cmd, &info);
        device.cmd_set_viewport(cmd, 0, &[viewport]);
        device.cmd_set_scissor(cmd, 0, &[area]);
    }
}

/// Copies the static map (in `TRANSFER_SRC_OPTIMAL`) into layers `0..layers` of the
/// working map (in `TRANSFER_DST_OPTIMAL`).
///
/// # Safety
/// `cmd` is recording, outside rendering; the maps are in those layouts.
unsafe fn copy_static(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    map: &EngineTsmMap,
    layers: u32,
) {
    let layer = |base_array_layer| vk::ImageSubresourceLayers {
        aspect_mask: vk::ImageAspectFlags::DEPTH,
        mip_level: 0,
        base_array_layer,
        layer_count: 1,
    };
    let regions: Vec<vk::ImageCopy> = (0..layers)
        .map(|i| vk::ImageCopy {
            src_subresource: layer(0),
            src_offset: vk::Offset3D::default(),
            dst_subresource: layer(i),
            dst_offset: vk::Offset3D::default(),
            extent: vk::Extent3D {
                width: map.width,
                height: map.height,
                depth: 1,
            },
        })
        .collect();
    // SAFETY: the caller's contract: outside rendering, the static map in TRANSFER_SRC_OPTIMAL and
    // the working map in TRANSFER_DST_OPTIMAL; one region per layer below `layers`, which the
    // caller keeps within the working map's layer count (a batch), each the whole map's size in
    // both images.
    unsafe {
        device.cmd_copy_image(
            cmd,
            map.static_map.raw(),
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            map.working.raw(),
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            &regions,
        )
    };
}

/// Records the static draws (`statics`) or the moving ones at time `t`, depth-only, inside
/// dynamic rendering with `pipeline` bound (`draw_each` of the collection pass, one kind of
/// draw only).
fn draw_where(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    pipeline: &Pipeline,
    draws: &DrawList,
    map: &EngineTsmMap,
    t: f32,
    statics: bool,
) {
    for (i, record) in draws.records().iter().enumerate() {
        let is_static = record.flags() & DRAW_STATIC != 0;
        if record.triangle_count == 0 || is_static != statics {
            continue;
        }
        let constants = MapDrawPush {
            draw: DrawPush {
                draws: draws.address(),
                draw_index: i as u32,
                draw_count: draws.draw_count(),
            },
            map: map.header_address(),
            time: t,
            flags: 0,
        };
        // SAFETY: draw_where runs inside rendering with `pipeline` bound (its callers in this
        // file), whose layout has MapDrawPush's size as its push range.
        unsafe { pipeline.push(device, cmd, &constants) };
        // SAFETY: inside that rendering with the pipeline bound and pushed; the vertex shader reads
        // only this draw's streams, which the draw list checked.
        unsafe { device.cmd_draw(cmd, 3 * record.triangle_count, 1, 0, 0) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// No maps, too many, an empty mask or a time outside the shutter are refused by name.
    #[test]
    fn bad_counts_sizes_and_times_are_refused() {
        assert!(check_record((8, 8), 1.0, true, 1).is_ok());
        assert!(check_record((8, 8), 0.0, true, MAX_TSM_MAPS).is_ok());
        // Without a motion image the time is not read.
        assert!(check_record((8, 8), 1.5, false, 4).is_ok());
        for (what, size, time, maps) in [
            ("0 time-dependent", (8, 8), 1.0, 0),
            ("1025 time-dependent", (8, 8), 1.0, MAX_TSM_MAPS + 1),
            ("mask size 0x8", (0, 8), 1.0, 4),
            ("mask size 8x0", (8, 0), 1.0, 4),
            ("G-buffer time 1.5", (8, 8), 1.5, 4),
            ("G-buffer time NaN", (8, 8), f32::NAN, 4),
        ] {
            match check_record(size, time, true, maps) {
                Err(Error::InvalidArgument(message)) => {
                    assert!(message.contains(what), "{message}")
                }
                other => panic!("{what}: {other:?}"),
            }
        }
    }

    /// A device that cannot draw, sample or copy D32 depth maps is refused by name.
    #[test]
    fn a_device_without_d32_depth_maps_is_refused() {
        let all = vk::FormatFeatureFlags::DEPTH_STENCIL_ATTACHMENT
            | vk::FormatFeatureFlags::SAMPLED_IMAGE
            | vk::FormatFeatureFlags::TRANSFER_SRC
            | vk::FormatFeatureFlags::TRANSFER_DST;
        assert!(check_map_format(|_| all).is_ok());
        for missing in [
            vk::FormatFeatureFlags::DEPTH_STENCIL_ATTACHMENT,
            vk::FormatFeatureFlags::SAMPLED_IMAGE,
            vk::FormatFeatureFlags::TRANSFER_SRC,
        ] {
            match check_map_format(|_| all & !missing) {
                Err(Error::MissingFeatures(message)) => {
                    assert!(message.contains("D32_SFLOAT"), "{message}")
                }
                other => panic!("{missing:?}: {other:?}"),
            }
        }
    }
}
