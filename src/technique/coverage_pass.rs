//! Passes 2 and 3 of the coverage map (2017 paper, "Extension"; see coverage.rs): the caps
//! mark the texels one triangle covers for the whole frame, the reset removes marks where
//! another triangle is nearer at some time. A research pass (feature `research`).

use super::collection::{PrismPipelines, PrismShaders, draw_each};
use super::coverage::CoverageMap;
use super::coverage_steps::{Step, step_barrier};
use super::draws::DrawList;
use super::push_constants::{MapDrawPush, PushBlock};
use super::shaders;
use super::shadow_map::TemporalShadowMap;
use super::view::LightView;
use crate::error::Result;
use crate::gpu::{Context, Pipeline, attachmentless_pipeline, begin_attachmentless};
use ash::vk;

/// Passes 2 and 3 of the extension. Immutable after creation: one serves every frame in
/// flight and every light.
pub struct CoveragePass {
    caps: Pipeline,
    reset: PrismPipelines,
}

impl CoveragePass {
    /// Creates the caps pipeline (vertex and fragment shader) and the reset pipeline (the
    /// collection pass's prisms with another fragment shader).
    pub fn new(ctx: &Context) -> Result<Self> {
        let caps = attachmentless_pipeline(
            ctx,
            MapDrawPush::BYTES,
            &[
                (
                    vk::ShaderStageFlags::VERTEX,
                    "coverage_caps.vert",
                    shaders::COVERAGE_CAPS_VERT,
                ),
                (
                    vk::ShaderStageFlags::FRAGMENT,
                    "coverage.frag",
                    shaders::COVERAGE_FRAG,
                ),
            ],
        )?;
        let reset = PrismPipelines::new(
            ctx,
            PrismShaders {
                paper_fragment: ("coverage_reset.frag", shaders::COVERAGE_RESET_FRAG),
                exact_fragment: (
                    "coverage_reset_exact.frag",
                    shaders::COVERAGE_RESET_EXACT_FRAG,
                ),
                static_fragment: (
                    "coverage_reset_static.frag",
                    shaders::COVERAGE_RESET_STATIC_FRAG,
                ),
                ranges_fragment: None,
                conservative: false,
            },
        )?;
        Ok(Self { caps, reset })
    }

    /// Records passes 2 and 3 for `coverage`, after [`super::CollectionPass::record`] of
    /// `map` with the same coverage map (which wrote the header and filled the nearest map),
    /// and before [`super::GenerationPass::record`]; `light` is the collection's (its
    /// [`LightView::prisms`] picks the same prisms).
    ///
    /// # Safety
    /// As [`super::CollectionPass::record`], with `draws` the same list the collection pass
    /// drew.
    ///
    /// Synchronization: waits for the collection's fragment writes (its closing barrier) and
    /// earlier reads of the coverage map; leaves the coverage map written by the fragment
    /// stage and visible to compute and every shader read. State changed: the bound graphics
    /// pipeline, push constants, viewport, scissor.
    pub unsafe fn record(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        draws: &DrawList,
        light: &LightView,
        map: &TemporalShadowMap,
        coverage: &CoverageMap,
    ) {
        // SAFETY: `cmd` is recording outside any render pass on a graphics and compute queue
        // (CollectionPass::record's contract, which this one takes).
        unsafe { step_barrier(device, cmd, coverage, (Step::Earlier, Step::Fill)) };
        // SAFETY: the two buffers are the coverage map's own and alive as long as `coverage`;
        // WHOLE_SIZE fills stay within them, outside rendering, after the barrier above.
        unsafe {
            device.cmd_fill_buffer(cmd, coverage.coverage.raw(), 0, vk::WHOLE_SIZE, u32::MAX);
            device.cmd_fill_buffer(cmd, coverage.cover_depth.raw(), 0, vk::WHOLE_SIZE, 0);
        }
        // SAFETY: outside rendering; fragment and transfer stages are on the contract's graphics
        // queue.
        unsafe { step_barrier(device, cmd, coverage, (Step::Fill, Step::Marks)) };
        // SAFETY: outside rendering (the fill barrier is recorded), and the coverage map's size is
        // the extent the caps pipeline's dynamic viewport takes.
        unsafe { begin_attachmentless(device, cmd, coverage.width(), coverage.height()) };
        // SAFETY: rendering has just begun and the caps pipeline is this pass's, alive as long as
        // `self`.
        unsafe { self.caps.bind(device, cmd) };
        for time in [0.0, 1.0] {
            let constants = MapDrawPush {
                map: map.header_address(),
                time,
                ..MapDrawPush::default()
            };
            draw_each(device, cmd, &self.caps, draws, constants);
        }
        // SAFETY: the rendering began above and every cap draw has been recorded into it.
        unsafe { device.cmd_end_rendering(cmd) };
        // The reset pass reads what the caps wrote, in other fragment invocations.
        // SAFETY: rendering has ended; fragment stages are on this queue.
        unsafe { step_barrier(device, cmd, coverage, (Step::Marks, Step::Marks)) };
        // SAFETY: outside rendering again; the same extent as before, the coverage map's.
        unsafe { begin_attachmentless(device, cmd, coverage.width(), coverage.height()) };
        let constants = MapDrawPush {
            map: map.header_address(),
            ..MapDrawPush::default()
        };
        self.reset.draw(
            device,
            cmd,
            light.prisms,
            draws,
            constants,
            true,
            false,
            false,
            false,
            // The collection refuses a moving light with a coverage map.
            false,
        );
        // SAFETY: the reset pass's rendering was begun just above and its draws are recorded.
        unsafe { device.cmd_end_rendering(cmd) };
        // SAFETY: rendering has ended; fragment and compute stages are on the contract's graphics
        // and compute queue.
        unsafe { step_barrier(device, cmd, coverage, (Step::Marks, Step::Later)) };
    }
}
