//! The maps of one light: the static draws' depth map, kept across frames, and the working
//! map whose layers a batch of the N times is drawn into; and when the static map is drawn.

use super::checks::check_map_format;
use super::{MAP_FORMAT, MAX_TSM_LAYERS, TsmStart};
use crate::error::{Error, Result};
use crate::gpu::{Buffer, BufferUsage, Context, Doomed, Handle, Image};
use crate::technique::gpu_types::{GpuLightEnd, PlainMapHeader};
use crate::technique::shadow_map::StaticLayerSource;
use ash::vk;
use std::sync::Mutex;
use std::sync::atomic::{AtomicU32, Ordering};

/// Bytes of the header: the light and the map's size (a [`PlainMapHeader`], so that
/// `shadow_depth.vert` reads it as it reads an ordinary map's), then a moving light's pose at
/// t = 1 ([`GpuLightEnd`], zeros for a still light) where `shadow_depth.vert` and
/// `tsm_mask.comp` find it (shared.glsl's `PLAIN_LIGHT_END_OFFSET`): each map is drawn and
/// read with the light at its time.
pub(super) const HEADER_BYTES: u64 = LIGHT_END_OFFSET + std::mem::size_of::<GpuLightEnd>() as u64;
/// Where the light's pose at t = 1 starts in the header (`TSM_LIGHT_END_OFFSET` in
/// `glsl/tsm_mask.comp`, `PLAIN_LIGHT_END_OFFSET` in shared.glsl).
pub(super) const LIGHT_END_OFFSET: u64 = std::mem::size_of::<PlainMapHeader>() as u64;
const _: () = assert!(LIGHT_END_OFFSET == 224);

/// The maps of one light (per frame in flight and light): the static draws' depth map, kept
/// across frames, and the working depth maps (an array of [`Self::layers`]) the N times are
/// drawn into, a batch at a time.
pub struct EngineTsmMap {
    shared: std::sync::Arc<crate::gpu::Shared>,
    pub(super) width: u32,
    pub(super) height: u32,
    pub(super) layers: u32,
    pub(super) start: TsmStart,
    /// The static draws, drawn once (and again when the light or the static draws change).
    /// Rests in `static_resting_layout(start)` between uses.
    pub(super) static_map: Image,
    /// A batch of maps, one per layer: moving draws (and, with [`TsmStart::Copy`], the
    /// static ones).
    pub(super) working: Image,
    /// A 2D array view of every layer of `working`, for the mask shader (destroyed here).
    pub(super) working_array: vk::ImageView,
    /// [`PlainMapHeader`] and [`GpuLightEnd`]: the light (read by `shadow_depth.vert` and the
    /// mask shader).
    pub(super) header: Buffer,
    /// What the static map holds for keeping ([`crate::technique::LightView::keep_static_layer`]):
    /// `.0` drawn by a pass the host said it submitted, `.1` by the last recorded pass that drew
    /// it, until then ([`Self::static_map_submitted`]).
    static_source: Mutex<(Option<StaticLayerSource>, Option<StaticLayerSource>)>,
    /// Times [`super::EngineTsmPass::record`] has drawn the static map.
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

    /// How many times [`super::EngineTsmPass::record`] has drawn the static map (with
    /// [`crate::technique::LightView::keep_static_layer`], once per change of light or static
    /// draws).
    pub fn static_map_builds(&self) -> u32 {
        self.static_builds.load(Ordering::Relaxed)
    }

    /// Makes the next record redraw the static map, kept or not: call it when a static
    /// draw's buffer contents changed in place.
    pub fn forget_static_map(&self) {
        *self.static_source.lock().unwrap_or_else(|e| e.into_inner()) = (None, None);
    }

    /// Tells the map that the command buffer with its last recorded
    /// [`super::EngineTsmPass::record`] was submitted: a static map that pass drew may then be kept
    /// by later records (with [`crate::technique::LightView::keep_static_layer`]). As
    /// `TemporalShadowMap::static_layer_submitted`: a recorded pass that is not submitted needs
    /// nothing undone; without the call the static map is redrawn by every record.
    pub fn static_map_submitted(&self) {
        let mut state = self.static_source.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(recorded) = state.1.take() {
            state.0 = Some(recorded);
        }
    }

    /// Whether the static map must be drawn for `source` (and notes it as drawn, kept once
    /// submitted if `keep`).
    pub(super) fn take_static_redraw(&self, source: StaticLayerSource, keep: bool) -> bool {
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

/// The layout the static map rests in between frames: where its next use reads it.
pub(super) fn static_resting_layout(start: TsmStart) -> vk::ImageLayout {
    match start {
        TsmStart::Copy => vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
        TsmStart::SecondLookup => vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
    }
}
