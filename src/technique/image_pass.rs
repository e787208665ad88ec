//! What the two passes that touch a host's images share (the visibility mask, the lighting
//! output): a compute pipeline with one set of image bindings, created only where the device
//! can write storage images without a format, and one dispatch over an image. A pass may have
//! several variants of its shader (specialization constants); each is made when a record
//! first needs it.

use crate::error::{Error, Result};
use crate::gpu::{
    Context, ImageBindingLayout, ImageBindings, Pipeline, ShaderModule, Shared, compute_of_module,
};
use ash::vk;
use std::sync::{Arc, OnceLock};

/// Compute pipelines over a host's images (one per variant, made at first use), with their
/// binding layout. Made up front, the visibility mask's eleven variants cost a process about
/// 2 CPU seconds on lavapipe (LLVM compiles each), where a frame uses one to three of them.
pub(crate) struct ImagePass {
    pub layout: ImageBindingLayout,
    shared: Arc<Shared>,
    module: ShaderModule,
    push_bytes: u32,
    /// Per variant: its specialization constants, and its pipeline once made.
    variants: Vec<(Vec<u32>, OnceLock<Pipeline>)>,
}

impl ImagePass {
    /// `what` names the pass in the error when shaderStorageImageWriteWithoutFormat is not
    /// enabled (one pipeline then writes any output format). Variant i of the pipelines has
    /// the specialization constants `variants[i]`. Makes no pipeline yet.
    pub fn new(
        ctx: &Context,
        what: &str,
        bindings: &[vk::DescriptorType],
        push_bytes: u32,
        (name, spirv): (&str, crate::gpu::Spirv<'_>),
        variants: &[&[u32]],
    ) -> Result<Self> {
        if !ctx.info().storage_image_write_without_format {
            return Err(Error::MissingFeatures(format!(
                "{what} needs shaderStorageImageWriteWithoutFormat"
            )));
        }
        Ok(Self {
            layout: ImageBindingLayout::new(ctx, bindings)?,
            shared: ctx.shared.clone(),
            module: ShaderModule::new(ctx, name, spirv)?,
            push_bytes,
            variants: variants
                .iter()
                .map(|constants| (constants.to_vec(), OnceLock::new()))
                .collect(),
        })
    }

    /// Pipeline `variant`, made now if it was not made before (two threads that both make it
    /// keep the first one; the other is destroyed).
    pub fn pipeline(&self, variant: usize) -> Result<&Pipeline> {
        let (constants, made) = &self.variants[variant];
        if let Some(pipeline) = made.get() {
            return Ok(pipeline);
        }
        let pipeline = compute_of_module(
            &self.shared,
            &[&self.layout],
            self.push_bytes,
            &self.module,
            constants,
        )?;
        Ok(made.get_or_init(|| pipeline))
    }

    /// Records one dispatch of 8x8 groups of `pipeline` (one of [`Self::pipeline`]'s) over
    /// `size` with `bindings` (already written) bound as set 0 and `constants` pushed.
    ///
    /// # Safety
    /// `cmd` is recording, outside any render pass; `bindings` was made from this pass's
    /// layout and its views are valid until `cmd` completes.
    pub unsafe fn record<T: bytemuck::Pod>(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        pipeline: &Pipeline,
        bindings: &ImageBindings,
        constants: &T,
        size: (u32, u32),
    ) {
        // SAFETY: this function's contract (`cmd` recording outside a render pass, `bindings` of
        // this pass's layout with views live until `cmd` completes) is bind's.
        unsafe { self.bind(device, cmd, pipeline, bindings) };
        // SAFETY: the pipeline was just bound in `cmd`, and its layout's push range is the pass's
        // `push_bytes`, the size of T for every caller (the pass's push-constant struct).
        unsafe { pipeline.push(device, cmd, constants) };
        // SAFETY: a compute pipeline and its set are bound and its push constants set, outside a
        // render pass (the contract); 8x8 groups cover `size`, and the shader returns for
        // invocations past its edges.
        unsafe { device.cmd_dispatch(cmd, size.0.div_ceil(8), size.1.div_ceil(8), 1) };
    }

    /// Binds `pipeline` (one of [`Self::pipeline`]'s) and `bindings` (already written) as
    /// set 0.
    ///
    /// # Safety
    /// As [`Self::record`].
    pub unsafe fn bind(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        pipeline: &Pipeline,
        bindings: &ImageBindings,
    ) {
        // SAFETY: `cmd` is recording outside a render pass (the contract) and the pipeline is one
        // of this pass's, alive as long as `self`.
        unsafe { pipeline.bind(device, cmd) };
        // SAFETY: `bindings` was made from this pass's layout, which is set 0 of every variant's
        // pipeline layout, and its views stay valid until `cmd` completes (the contract).
        unsafe {
            device.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::COMPUTE,
                pipeline.layout(),
                0,
                &[bindings.raw()],
                &[],
            )
        };
    }

    /// Records one more dispatch of `pipeline`, already bound with its set by [`Self::bind`],
    /// with `constants` pushed and its group counts read from `args` at `offset`
    /// (`VkDispatchIndirectCommand`).
    ///
    /// # Safety
    /// As [`Self::record`]; [`Self::bind`] was recorded earlier in `cmd` with the same
    /// pipeline, and no other pipeline or set was bound since; `args` has indirect usage,
    /// holds the command at `offset`, made visible to `DRAW_INDIRECT` reads, and outlives
    /// `cmd`.
    pub unsafe fn record_indirect<T: bytemuck::Pod>(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        pipeline: &Pipeline,
        constants: &T,
        (args, offset): (vk::Buffer, u64),
    ) {
        // SAFETY: bind recorded this variant earlier in `cmd` and nothing else was bound since (the
        // contract), so the push goes to this pipeline's layout with its own push-constant size.
        unsafe { pipeline.push(device, cmd, constants) };
        // SAFETY: `args` has indirect usage and holds a VkDispatchIndirectCommand at `offset`,
        // visible to indirect reads, and outlives `cmd` (the contract); the pipeline and set are
        // bound.
        unsafe { device.cmd_dispatch_indirect(cmd, args, offset) };
    }
}
