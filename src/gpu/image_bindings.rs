//! Descriptor sets for a host's images. Buffers are reached by device address, images cannot
//! be: a pass that reads or writes a host's image binds a set of image descriptors, rewritten
//! for each use. One [`ImageBindings`] per use that may be pending at the same time.

use super::context::{Context, Shared};
use super::retire::{Doomed, Handle};
use crate::error::{Error, Result, VkContext};
use ash::vk;
use std::sync::Arc;

/// Objects the bindings borrow: freed when the last of them goes.
struct Inner {
    shared: Arc<Shared>,
    device: ash::Device,
    set_layout: vk::DescriptorSetLayout,
    /// Nearest-neighbour, clamped: for `texelFetch` of combined image samplers.
    sampler: vk::Sampler,
    types: Vec<vk::DescriptorType>,
}

impl Drop for Inner {
    /// Retires the sampler and layout: destroyed once no pending frame can use them.
    fn drop(&mut self) {
        self.shared.retire(Doomed::handles(vec![
            Handle::Sampler(self.sampler),
            Handle::DescriptorSetLayout(self.set_layout),
        ]));
    }
}

/// A compute-stage set layout of image descriptors, binding i of type `types[i]`.
pub struct ImageBindingLayout {
    inner: Arc<Inner>,
}

impl ImageBindingLayout {
    /// `types` may hold `COMBINED_IMAGE_SAMPLER` (read with `texelFetch`; the layout's own
    /// nearest sampler is used) and `STORAGE_IMAGE`.
    pub fn new(ctx: &Context, types: &[vk::DescriptorType]) -> Result<Self> {
        if let Some(ty) = types.iter().find(|&&ty| {
            ty != vk::DescriptorType::COMBINED_IMAGE_SAMPLER
                && ty != vk::DescriptorType::STORAGE_IMAGE
        }) {
            return Err(Error::InvalidArgument(format!(
                "image bindings of type {ty:?}: only COMBINED_IMAGE_SAMPLER and STORAGE_IMAGE"
            )));
        }
        let device = ctx.device();
        let bindings: Vec<_> = types
            .iter()
            .enumerate()
            .map(|(i, &ty)| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(i as u32)
                    .descriptor_type(ty)
                    .descriptor_count(1)
                    .stage_flags(vk::ShaderStageFlags::COMPUTE)
            })
            .collect();
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
        // SAFETY: `bindings` lists sampled or storage image types only (checked in new) and `info`
        // borrows it for the call; the device is the context's, alive while `inner` holds it.
        let set_layout = unsafe { device.create_descriptor_set_layout(&info, None) }
            .vk("vkCreateDescriptorSetLayout")?;
        let sampler_info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::NEAREST)
            .min_filter(vk::Filter::NEAREST)
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE);
        // SAFETY: a sampler of fixed, always-supported state (nearest, clamp to edge, no
        // anisotropy) on the live device.
        let sampler = match unsafe { device.create_sampler(&sampler_info, None) } {
            Ok(s) => s,
            Err(result) => {
                // SAFETY: the sampler could not be made, so the set layout just created is used by
                // nothing yet and is destroyed once.
                unsafe { device.destroy_descriptor_set_layout(set_layout, None) };
                return Err(Error::Vulkan {
                    call: "vkCreateSampler",
                    result,
                });
            }
        };
        Ok(Self {
            inner: Arc::new(Inner {
                shared: ctx.shared.clone(),
                device: device.clone(),
                set_layout,
                sampler,
                types: types.to_vec(),
            }),
        })
    }

    /// The set layout, for a pipeline layout.
    pub fn raw(&self) -> vk::DescriptorSetLayout {
        self.inner.set_layout
    }

    /// A pool and one set of this layout.
    pub fn allocate(&self) -> Result<ImageBindings> {
        let device = &self.inner.device;
        let sizes: Vec<_> = self
            .inner
            .types
            .iter()
            .map(|&ty| vk::DescriptorPoolSize {
                ty,
                descriptor_count: 1,
            })
            .collect();
        let info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(1)
            .pool_sizes(&sizes);
        let pool =
            // SAFETY: the pool sizes count one descriptor per binding of this layout and the pool
            // holds one set; `info` borrows them for the call.
            unsafe { device.create_descriptor_pool(&info, None) }.vk("vkCreateDescriptorPool")?;
        // Owns the pool from here on, so an error below frees it.
        let mut bindings = ImageBindings {
            inner: self.inner.clone(),
            pool,
            set: vk::DescriptorSet::null(),
        };
        let layouts = [self.inner.set_layout];
        let alloc = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(pool)
            .set_layouts(&layouts);
        bindings.set =
            // SAFETY: `pool` was just made for exactly one set of this layout (its sizes cover
            // every binding), so the allocation cannot overflow it; the set is freed with the pool.
            unsafe { device.allocate_descriptor_sets(&alloc) }.vk("vkAllocateDescriptorSets")?[0];
        Ok(bindings)
    }
}

/// One descriptor set of an [`ImageBindingLayout`], rewritten by the pass that records with
/// it: one per use that may be pending at the same time (per frame in flight, per light),
/// and used once per command buffer.
pub struct ImageBindings {
    inner: Arc<Inner>,
    pool: vk::DescriptorPool,
    set: vk::DescriptorSet,
}

impl ImageBindings {
    /// Points binding i at `images[i]` (a view and the layout it will be in).
    ///
    /// # Safety
    /// No command buffer that uses this set is pending, or has it bound while recording;
    /// the views are valid images of the device with the usages their binding types need.
    pub unsafe fn write(&mut self, images: &[(vk::ImageView, vk::ImageLayout)]) {
        assert_eq!(
            images.len(),
            self.inner.types.len(),
            "one image per binding"
        );
        let infos: Vec<[vk::DescriptorImageInfo; 1]> = images
            .iter()
            .zip(&self.inner.types)
            .map(|(&(view, layout), &ty)| {
                [vk::DescriptorImageInfo {
                    sampler: if ty == vk::DescriptorType::COMBINED_IMAGE_SAMPLER {
                        self.inner.sampler
                    } else {
                        vk::Sampler::null()
                    },
                    image_view: view,
                    image_layout: layout,
                }]
            })
            .collect();
        let writes: Vec<_> = infos
            .iter()
            .zip(&self.inner.types)
            .enumerate()
            .map(|(i, (info, &ty))| {
                vk::WriteDescriptorSet::default()
                    .dst_set(self.set)
                    .dst_binding(i as u32)
                    .descriptor_type(ty)
                    .image_info(info)
            })
            .collect();
        // SAFETY: the caller's contract: no pending or recording command buffer uses the set, and
        // the views are live images with the usages their types need. One write per binding with
        // the binding's own type (one image per binding was asserted), and `infos` outlives the
        // call.
        unsafe { self.inner.device.update_descriptor_sets(&writes, &[]) };
    }

    /// The set.
    pub fn raw(&self) -> vk::DescriptorSet {
        self.set
    }
}

impl Drop for ImageBindings {
    fn drop(&mut self) {
        // Retired: destroyed (with its set) once no pending frame can use the set.
        self.inner
            .shared
            .retire(Doomed::handles(vec![Handle::DescriptorPool(self.pool)]));
    }
}
