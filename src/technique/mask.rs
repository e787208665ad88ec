//! The visibility-mask pass, for deferred engines: from the host's depth image (and normal
//! image, if it has one) and its camera, the fraction of the shutter each pixel sees the
//! light, written into a host-owned single-channel image that the host's own lighting
//! multiplies in. The fraction is exact for receivers that stay put during the shutter
//! (`ms_lit_fraction` in `glsl/motion_shadows.glsl`), so the mask has no time noise.
//!
//! Host images cannot be reached by device address, so this pass, unlike the others, binds a
//! descriptor set: one [`MaskBindings`] per use in flight (per frame in flight and light).

use super::shaders;
use super::shadow_map::TemporalShadowMap;
use crate::error::{Error, Result, VkContext};
use crate::gpu::{Context, Pipeline, compute_pipeline_with_sets};
use ash::vk;
use glam::Mat4;
use std::sync::Arc;

/// How the host's normal image stores a world-space normal in its rgb channels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NormalEncoding {
    /// Signed components in [-1, 1] (float or snorm formats).
    Signed,
    /// `n * 0.5 + 0.5` in [0, 1] (unorm formats).
    Unorm,
}

/// The host's normal image.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NormalImage {
    /// A view of a sampled image (world-space normal in rgb), the size of the depth image.
    pub view: vk::ImageView,
    /// Its layout while the pass runs (e.g. `SHADER_READ_ONLY_OPTIMAL`).
    pub layout: vk::ImageLayout,
    /// How its values encode the normal.
    pub encoding: NormalEncoding,
}

/// What one mask dispatch reads and writes: the host's images and camera.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaskInputs {
    /// A view of the host's depth image (depth aspect, sampled usage), `size` texels.
    pub depth: vk::ImageView,
    /// Its layout while the pass runs (`DEPTH_STENCIL_READ_ONLY_OPTIMAL`,
    /// `DEPTH_READ_ONLY_OPTIMAL` or `SHADER_READ_ONLY_OPTIMAL`).
    pub depth_layout: vk::ImageLayout,
    /// The host's normal image, or `None` to rebuild normals from the depth neighbours.
    pub normals: Option<NormalImage>,
    /// A view of the output image: single channel (R8_UNORM, R16_UNORM, R16_SFLOAT or
    /// R32_SFLOAT), storage usage, `size` texels, in `GENERAL` layout.
    pub output: vk::ImageView,
    /// Pixels.
    pub size: (u32, u32),
    /// The inverse of the host's view-projection matrix (Vulkan clip space: x, y in [-1, 1]
    /// with y down, depth as stored in the depth image).
    pub inv_view_proj: Mat4,
    /// The depth image's clear value (1 for a standard depth buffer, 0 for reversed Z):
    /// pixels holding it have no surface and get 1 (lit).
    pub background_depth: f32,
}

/// The mask shader's push constants (96 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
struct MaskConstants {
    inv_view_proj: Mat4,
    map: u64,
    size: [u32; 2],
    background_depth: f32,
    flags: u32,
    reserved: [u32; 2],
}

const HAS_NORMALS: u32 = 1;
const NORMALS_UNORM: u32 = 2;

/// Objects of the pass that its bindings borrow: freed when the last of them goes.
struct Shared {
    device: ash::Device,
    set_layout: vk::DescriptorSetLayout,
    sampler: vk::Sampler,
}

impl Drop for Shared {
    fn drop(&mut self) {
        unsafe {
            self.device.destroy_sampler(self.sampler, None);
            self.device
                .destroy_descriptor_set_layout(self.set_layout, None);
        }
    }
}

/// The visibility-mask pass. Immutable after creation.
pub struct VisibilityMaskPass {
    shared: Arc<Shared>,
    pipeline: Pipeline,
}

/// The descriptor set one mask dispatch binds (the host's three image views). Rewritten by
/// every [`VisibilityMaskPass::record`], so: one per dispatch that may be pending at the same
/// time (per frame in flight and per light), and used once per command buffer.
pub struct MaskBindings {
    shared: Arc<Shared>,
    pool: vk::DescriptorPool,
    set: vk::DescriptorSet,
}

impl Drop for MaskBindings {
    fn drop(&mut self) {
        unsafe { self.shared.device.destroy_descriptor_pool(self.pool, None) };
    }
}

impl VisibilityMaskPass {
    /// Creates the pass. Errors when the device does not support writing storage images
    /// without a format in the shader (`shaderStorageImageWriteWithoutFormat`), which lets one
    /// pipeline write any of the output formats; a host device must also have it enabled.
    pub fn new(ctx: &Context) -> Result<Self> {
        if !ctx.info().storage_image_write_without_format {
            return Err(Error::MissingFeatures(
                "the visibility-mask pass needs shaderStorageImageWriteWithoutFormat".into(),
            ));
        }
        let device = ctx.device();
        let binding = |binding, ty| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(binding)
                .descriptor_type(ty)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::COMPUTE)
        };
        let bindings = [
            binding(0, vk::DescriptorType::COMBINED_IMAGE_SAMPLER),
            binding(1, vk::DescriptorType::COMBINED_IMAGE_SAMPLER),
            binding(2, vk::DescriptorType::STORAGE_IMAGE),
        ];
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
        let set_layout = unsafe { device.create_descriptor_set_layout(&info, None) }
            .vk("vkCreateDescriptorSetLayout")?;
        // Exact texel reads (texelFetch ignores filtering, but a sampler is required).
        let sampler_info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::NEAREST)
            .min_filter(vk::Filter::NEAREST)
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE);
        let sampler = match unsafe { device.create_sampler(&sampler_info, None) } {
            Ok(s) => s,
            Err(result) => {
                unsafe { device.destroy_descriptor_set_layout(set_layout, None) };
                return Err(Error::Vulkan {
                    call: "vkCreateSampler",
                    result,
                });
            }
        };
        let shared = Arc::new(Shared {
            device: device.clone(),
            set_layout,
            sampler,
        });
        let pipeline = compute_pipeline_with_sets(
            ctx,
            &[set_layout],
            std::mem::size_of::<MaskConstants>() as u32,
            "visibility_mask.comp",
            shaders::VISIBILITY_MASK_COMP,
        )?;
        Ok(Self { shared, pipeline })
    }

    /// A descriptor set for one dispatch in flight.
    pub fn bindings(&self) -> Result<MaskBindings> {
        let device = &self.shared.device;
        let sizes = [
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                descriptor_count: 2,
            },
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::STORAGE_IMAGE,
                descriptor_count: 1,
            },
        ];
        let info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(1)
            .pool_sizes(&sizes);
        let pool =
            unsafe { device.create_descriptor_pool(&info, None) }.vk("vkCreateDescriptorPool")?;
        // Owns the pool from here on, so an error below frees it.
        let mut bindings = MaskBindings {
            shared: self.shared.clone(),
            pool,
            set: vk::DescriptorSet::null(),
        };
        let layouts = [self.shared.set_layout];
        let alloc = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(pool)
            .set_layouts(&layouts);
        bindings.set =
            unsafe { device.allocate_descriptor_sets(&alloc) }.vk("vkAllocateDescriptorSets")?[0];
        Ok(bindings)
    }

    /// Records the mask of `map` (after its generation pass) for the host's images.
    ///
    /// # Safety
    /// - `cmd` was allocated from the device the pass was made on, is recording, outside any
    ///   render pass or dynamic rendering, on a queue with compute.
    /// - `bindings` was made by this pass and no command buffer using it is pending or has
    ///   it bound in `cmd` (its set is rewritten here).
    /// - The views are valid, of the device, with the usages, sizes, formats and layouts
    ///   [`MaskInputs`] states, and stay alive until `cmd` completes.
    /// - The host has made its writes to the depth and normal images visible to
    ///   `COMPUTE_SHADER` sampled reads, and ordered earlier accesses of the output image
    ///   before `COMPUTE_SHADER` storage writes, with its own barriers (image layout
    ///   transitions included).
    /// - The map's collection and generation passes were recorded earlier in `cmd` or in a
    ///   command buffer submitted before it (their closing barrier makes the ranges visible).
    ///
    /// Synchronization: leaves the output written by `COMPUTE_SHADER` with
    /// `SHADER_STORAGE_WRITE`, in `GENERAL` layout; the host's barrier makes it visible to
    /// its lighting. State changed: the bound compute pipeline, descriptor set 0 of the
    /// compute bind point, push constants.
    pub unsafe fn record(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        bindings: &mut MaskBindings,
        inputs: &MaskInputs,
        map: &TemporalShadowMap,
    ) {
        let sampled = |view, layout| {
            [vk::DescriptorImageInfo {
                sampler: self.shared.sampler,
                image_view: view,
                image_layout: layout,
            }]
        };
        let depth = sampled(inputs.depth, inputs.depth_layout);
        // Without a normal image the depth view stands in (never read: the flag says so).
        let normals = match inputs.normals {
            Some(n) => sampled(n.view, n.layout),
            None => depth,
        };
        let output = [vk::DescriptorImageInfo {
            sampler: vk::Sampler::null(),
            image_view: inputs.output,
            image_layout: vk::ImageLayout::GENERAL,
        }];
        fn write(
            set: vk::DescriptorSet,
            binding: u32,
            ty: vk::DescriptorType,
            info: &[vk::DescriptorImageInfo; 1],
        ) -> vk::WriteDescriptorSet<'_> {
            vk::WriteDescriptorSet::default()
                .dst_set(set)
                .dst_binding(binding)
                .descriptor_type(ty)
                .image_info(info)
        }
        let sampled_ty = vk::DescriptorType::COMBINED_IMAGE_SAMPLER;
        let writes = [
            write(bindings.set, 0, sampled_ty, &depth),
            write(bindings.set, 1, sampled_ty, &normals),
            write(bindings.set, 2, vk::DescriptorType::STORAGE_IMAGE, &output),
        ];
        let flags = match inputs.normals {
            Some(NormalImage {
                encoding: NormalEncoding::Unorm,
                ..
            }) => HAS_NORMALS | NORMALS_UNORM,
            Some(_) => HAS_NORMALS,
            None => 0,
        };
        let constants = MaskConstants {
            inv_view_proj: inputs.inv_view_proj,
            map: map.header_address(),
            size: [inputs.size.0, inputs.size.1],
            background_depth: inputs.background_depth,
            flags,
            reserved: [0; 2],
        };
        unsafe {
            device.update_descriptor_sets(&writes, &[]);
            self.pipeline.bind(device, cmd);
            device.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::COMPUTE,
                self.pipeline.layout,
                0,
                &[bindings.set],
                &[],
            );
        }
        self.pipeline.push(device, cmd, &constants);
        unsafe {
            device.cmd_dispatch(cmd, inputs.size.0.div_ceil(8), inputs.size.1.div_ceil(8), 1)
        };
    }
}
