//! The papers' lighting pass into a host image: copies a [`LightingTarget`]'s radiance into
//! the host's own storage image (any four-channel format: RGBA32F, RGBA16F, ...), so an
//! engine can use the stochastic lighting pass as one of its passes and keep compositing.

use super::image_pass::ImagePass;
use super::lighting::LightingTarget;
use super::push_constants::{PushBlock, RadiancePush};
use super::shaders;
use crate::error::Result;
use crate::gpu::{Context, ImageBindings};
use ash::vk;

/// Writes lighting targets into host images. Immutable after creation.
pub struct LightingImageOutput {
    pass: ImagePass,
}

impl LightingImageOutput {
    /// Creates the pass; needs shaderStorageImageWriteWithoutFormat enabled (as the
    /// visibility-mask pass does), so that one pipeline writes any format.
    pub fn new(ctx: &Context) -> Result<Self> {
        let pass = ImagePass::new(
            ctx,
            "writing the lighting pass into a host image",
            &[vk::DescriptorType::STORAGE_IMAGE],
            RadiancePush::BYTES,
            ("radiance_to_image.comp", shaders::RADIANCE_TO_IMAGE_COMP),
            &[&[]],
        )?;
        // Its one pipeline now: `record` has no error to return.
        pass.pipeline(0)?;
        Ok(Self { pass })
    }

    /// A descriptor set for one use in flight (per frame in flight).
    pub fn bindings(&self) -> Result<ImageBindings> {
        self.pass.layout.allocate()
    }

    /// Records the copy of `target`'s radiance (rgb; alpha: the share of samples seeing a
    /// moving triangle) into `image`, after [`super::LightingPass::record`] of the frame.
    ///
    /// # Safety
    /// - `cmd` was allocated from the device the pass was made on, is recording, outside any
    ///   render pass or dynamic rendering, on a queue with compute.
    /// - `bindings` was made by this pass and no command buffer using it is pending or has
    ///   it bound in `cmd` (its set is rewritten here).
    /// - `image` is a view of a 2D image of the device with storage usage, a four-channel
    ///   format, the target's size, in `GENERAL` layout; earlier accesses of it are ordered
    ///   before `COMPUTE_SHADER` storage writes by the host's barrier; it stays alive until
    ///   `cmd` completes.
    ///
    /// Synchronization: waits for the lighting pass (its closing barrier covers compute
    /// reads); leaves the image written by `COMPUTE_SHADER` with `SHADER_STORAGE_WRITE`.
    /// State changed: the bound compute pipeline, descriptor set 0 of the compute bind point,
    /// push constants.
    pub unsafe fn record(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        bindings: &mut ImageBindings,
        target: &LightingTarget,
        image: vk::ImageView,
    ) {
        // SAFETY: the caller's contract.
        unsafe { bindings.write(&[(image, vk::ImageLayout::GENERAL)]) };
        let constants = RadiancePush {
            radiance: target.radiance.device_address(),
            size: [target.width(), target.height()],
        };
        let size = (target.width(), target.height());
        let pipeline = self
            .pass
            .pipeline(0)
            .expect("made by LightingImageOutput::new");
        // SAFETY: the caller's contract; the set was just written.
        unsafe {
            self.pass
                .record(device, cmd, pipeline, bindings, &constants, size)
        };
    }
}
