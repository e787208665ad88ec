//! One descriptor set with its layout and pool: each pass binds a handful of buffers.

use super::buffer::Buffer;
use super::context::{Context, Shared};
use crate::error::{Result, VkContext};
use ash::vk;
use std::sync::Arc;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DescriptorKind {
    Storage,
    Uniform,
}

impl DescriptorKind {
    fn vk(self) -> vk::DescriptorType {
        match self {
            Self::Storage => vk::DescriptorType::STORAGE_BUFFER,
            Self::Uniform => vk::DescriptorType::UNIFORM_BUFFER,
        }
    }
}

#[derive(Debug, Clone, Copy)]
pub struct DescriptorBinding {
    pub binding: u32,
    pub kind: DescriptorKind,
    pub stages: vk::ShaderStageFlags,
}

/// A set layout, a pool sized for exactly one set of it, and that set.
pub struct DescriptorSet {
    shared: Arc<Shared>,
    layout: vk::DescriptorSetLayout,
    pool: vk::DescriptorPool,
    set: vk::DescriptorSet,
    bindings: Vec<DescriptorBinding>,
    /// [`Buffer::uid`] of what each binding points at; 0 for nothing yet.
    bound: Vec<u64>,
}

impl DescriptorSet {
    pub fn new(ctx: &Context, bindings: &[DescriptorBinding]) -> Result<Self> {
        let device = ctx.device();
        let vk_bindings: Vec<_> = bindings
            .iter()
            .map(|b| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(b.binding)
                    .descriptor_type(b.kind.vk())
                    .descriptor_count(1)
                    .stage_flags(b.stages)
            })
            .collect();
        let layout_info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&vk_bindings);
        let layout = unsafe { device.create_descriptor_set_layout(&layout_info, None) }
            .vk("vkCreateDescriptorSetLayout")?;
        let mut this = Self {
            shared: ctx.shared.clone(),
            layout,
            pool: vk::DescriptorPool::null(),
            set: vk::DescriptorSet::null(),
            bindings: bindings.to_vec(),
            bound: vec![0; bindings.len()],
        };
        let sizes: Vec<_> = [DescriptorKind::Storage, DescriptorKind::Uniform]
            .into_iter()
            .filter_map(|kind| {
                let n = bindings.iter().filter(|b| b.kind == kind).count() as u32;
                (n > 0).then(|| vk::DescriptorPoolSize {
                    ty: kind.vk(),
                    descriptor_count: n,
                })
            })
            .collect();
        let pool_info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(1)
            .pool_sizes(&sizes);
        this.pool = unsafe { device.create_descriptor_pool(&pool_info, None) }
            .vk("vkCreateDescriptorPool")?;
        let layouts = [layout];
        let alloc = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(this.pool)
            .set_layouts(&layouts);
        this.set =
            unsafe { device.allocate_descriptor_sets(&alloc) }.vk("vkAllocateDescriptorSets")?[0];
        Ok(this)
    }

    pub fn layout(&self) -> vk::DescriptorSetLayout {
        self.layout
    }
    pub fn raw(&self) -> vk::DescriptorSet {
        self.set
    }

    /// Points binding i at `buffers[i]`, rewriting only bindings whose buffer changed (a
    /// rewrite would invalidate a command buffer being recorded with this set bound). Buffers
    /// are told apart by [`Buffer::uid`], not by handle: a driver may give a new buffer the
    /// handle value of a freed one. Must not change a binding while a command buffer using
    /// this set is pending.
    pub fn bind(&mut self, buffers: &[&Buffer]) {
        assert_eq!(buffers.len(), self.bindings.len(), "one buffer per binding");
        let infos: Vec<[vk::DescriptorBufferInfo; 1]> =
            buffers.iter().map(|b| [b.descriptor()]).collect();
        let writes: Vec<_> = self
            .bindings
            .iter()
            .zip(&infos)
            .zip(buffers.iter().zip(&self.bound))
            .filter(|(_, (buffer, bound))| buffer.uid() != **bound)
            .map(|((b, info), _)| {
                vk::WriteDescriptorSet::default()
                    .dst_set(self.set)
                    .dst_binding(b.binding)
                    .descriptor_type(b.kind.vk())
                    .buffer_info(info)
            })
            .collect();
        if !writes.is_empty() {
            unsafe { self.shared.device.update_descriptor_sets(&writes, &[]) };
        }
        self.bound = buffers.iter().map(|b| b.uid()).collect();
    }
}

impl Drop for DescriptorSet {
    fn drop(&mut self) {
        unsafe {
            self.shared.device.destroy_descriptor_pool(self.pool, None);
            self.shared
                .device
                .destroy_descriptor_set_layout(self.layout, None);
        }
    }
}
