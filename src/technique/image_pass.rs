//! What the two passes that touch a host's images share (the visibility mask, the lighting
//! output): a compute pipeline with one set of image bindings, created only where the device
//! can write storage images without a format, and one dispatch over an image.

use crate::error::{Error, Result};
use crate::gpu::{
    Context, ImageBindingLayout, ImageBindings, Pipeline, compute_pipeline_with_sets,
};
use ash::vk;

/// A compute pipeline over a host's images, with its binding layout.
pub(crate) struct ImagePass {
    pub layout: ImageBindingLayout,
    pub pipeline: Pipeline,
}

impl ImagePass {
    /// `what` names the pass in the error when shaderStorageImageWriteWithoutFormat is not
    /// enabled (one pipeline then writes any output format).
    pub fn new(
        ctx: &Context,
        what: &str,
        bindings: &[vk::DescriptorType],
        push_bytes: u32,
        name: &str,
        spirv: &[u8],
    ) -> Result<Self> {
        if !ctx.info().storage_image_write_without_format {
            return Err(Error::MissingFeatures(format!(
                "{what} needs shaderStorageImageWriteWithoutFormat"
            )));
        }
        let layout = ImageBindingLayout::new(ctx, bindings)?;
        let pipeline = compute_pipeline_with_sets(ctx, &[layout.raw()], push_bytes, name, spirv)?;
        Ok(Self { layout, pipeline })
    }

    /// Records one dispatch of 8x8 groups over `size` with `bindings` (already written) bound
    /// as set 0 and `constants` pushed.
    ///
    /// # Safety
    /// `cmd` is recording, outside any render pass; `bindings` was made from this pass's
    /// layout and its views are valid until `cmd` completes.
    pub unsafe fn record<T: Copy>(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        bindings: &ImageBindings,
        constants: &T,
        size: (u32, u32),
    ) {
        self.pipeline.bind(device, cmd);
        unsafe {
            device.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::COMPUTE,
                self.pipeline.layout,
                0,
                &[bindings.raw()],
                &[],
            )
        };
        self.pipeline.push(device, cmd, constants);
        unsafe { device.cmd_dispatch(cmd, size.0.div_ceil(8), size.1.div_ceil(8), 1) };
    }
}
