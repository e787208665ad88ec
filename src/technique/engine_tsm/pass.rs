//! The pass: its pipelines (depth-only drawing, and the mask's four variants), the bindings
//! of one record in flight, and the record itself, a sequence of the steps in `steps.rs`.

use super::MAP_FORMAT;
use super::accesses::entry_barrier;
use super::bindings::EngineTsmBindings;
use super::checks::{check_map_format, check_record};
use super::map::EngineTsmMap;
use super::steps::{
    Batch, dispatch_mask, draw_moving_layers, draw_static_map, mask_flags, mask_variant,
    start_layers, write_bindings, write_header,
};
use crate::error::Result;
use crate::gpu::{
    Attachments, Context, ImageBindingLayout, Pipeline, graphics_pipeline,
    specialized_compute_pipeline,
};
use crate::technique::declared_barriers::record_own;
use crate::technique::draws::DrawList;
use crate::technique::mask::MaskInputs;
use crate::technique::push_constants::{MapDrawPush, PushBlock, TsmMaskPush};
use crate::technique::shaders;
use crate::technique::shadow_map::StaticLayerSource;
use crate::technique::view::LightView;
use ash::vk;

/// The pass's name in the access check's reports.
const PASS_NAME: &str = "time-dependent shadow maps";
/// Its entry barrier's label in the access check's log.
const ENTRY: &str = "time-dependent shadow maps entry";

/// Records time-dependent shadow maps and their mask. Immutable after creation: one serves
/// every frame in flight and every light.
pub struct EngineTsmPass {
    /// Depth-only drawing of the draws at one time (`shadow_depth.vert`, no fragment shader).
    depth_only: Pipeline,
    layout: ImageBindingLayout,
    /// Mask pipelines, indexed by `moving as usize + 2 * second_lookup as usize`.
    masks: Vec<Pipeline>,
    /// Whether [`Self::record`] records its own entry barrier (off:
    /// [`Self::with_host_barriers`]).
    pub(super) outer_barriers: bool,
}

impl EngineTsmPass {
    /// Creates the pipelines; fails with [`crate::Error::MissingFeatures`] on a device that cannot
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
            outer_barriers: true,
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
    /// clear), the moving draws drawn into it at its time, and one mask dispatch. A moving
    /// light ([`LightView::end`], turning or not) draws and reads each map with the light at
    /// the map's time, and every draw as moving (nothing stands still in its frame: the static
    /// map stays empty). Errors,
    /// recording nothing, when `maps` is 0 or above [`super::MAX_TSM_MAPS`], when `inputs.size` is
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
    /// - The draws' buffers are as [`crate::technique::Draw`] requires; `draws` was updated
    ///   ([`DrawList::record_update`]) earlier in `cmd` or in a command buffer submitted
    ///   before it.
    /// - The host has made its writes to the depth, normal and motion images visible to
    ///   `COMPUTE_SHADER` sampled reads, and ordered earlier accesses of the output image
    ///   before `COMPUTE_SHADER` storage reads and writes, with its own barriers (image layout
    ///   transitions included).
    ///
    /// Synchronization: waits for the previous record's reads of the map's header (the entry
    /// barrier, derived from [`Self::accesses`]; the host's with [`Self::with_host_barriers`])
    /// and for earlier uses of the maps' images by this pass (they are in no other hands). Leaves the output written by
    /// `COMPUTE_SHADER` (`SHADER_STORAGE_WRITE`, after reads of it there), in `GENERAL`
    /// layout; the host's barrier makes it visible to its lighting. The working map is left
    /// in `SHADER_READ_ONLY_OPTIMAL`, the static map in `SHADER_READ_ONLY_OPTIMAL`
    /// ([`super::TsmStart::SecondLookup`]) or `TRANSFER_SRC_OPTIMAL` ([`super::TsmStart::Copy`]).
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
        let check = map.header.access_check();
        if self.outer_barriers {
            // SAFETY: `cmd` is recording outside any render pass on a graphics and compute
            // queue (this function's contract), which has the stages the barrier names.
            unsafe { record_own(device, cmd, check, ENTRY, entry_barrier(map).as_ref()) };
        }
        self.accesses(inputs, draws, map)
            .declare_run(check, PASS_NAME);
        // SAFETY: `cmd` is recording outside any render pass on a graphics and compute queue, and
        // no other pending command buffer uses `map` (this function's contract); the previous
        // record's reads of the header were waited for (the entry barrier above, or the host's).
        unsafe { write_header(device, cmd, map, light) };

        // The static map, unless the one kept from an earlier frame still holds these draws
        // (under a moving light none: it is kept empty, and redrawn when the light stops).
        let light_moves = light.is_moving();
        let source = StaticLayerSource::of(light, draws);
        if map.take_static_redraw(source, light.keep_static_layer) {
            // SAFETY: as above; the draws' buffers are as `Draw` requires and the draw list
            // was updated before (the contract).
            unsafe { draw_static_map(device, cmd, &self.depth_only, draws, map, light_moves) };
        }

        // SAFETY: the caller's contract (the set is not in use; the views are valid).
        unsafe { write_bindings(bindings, inputs, map) };
        let mask = &self.masks[mask_variant(inputs, map.start)];
        let flags = mask_flags(inputs);
        for first in (0..maps).step_by(map.layers as usize) {
            let batch = Batch {
                first,
                count: map.layers.min(maps - first),
                maps,
            };
            // SAFETY: as above; `mask` is this pass's pipeline for the map's start, made with
            // the layout `bindings` was allocated from and written just above, and the host
            // ordered its images' writes before these reads (the contract).
            unsafe {
                start_layers(device, cmd, map, batch);
                draw_moving_layers(
                    device,
                    cmd,
                    &self.depth_only,
                    draws,
                    map,
                    batch,
                    light_moves,
                );
                dispatch_mask(device, cmd, mask, bindings, inputs, map, batch, flags);
            }
        }
        Ok(())
    }
}
