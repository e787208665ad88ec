//! The engine's pipelines and layouts, created once and shared by all frames.

use super::*;

// ---------------------------------------------------------------------------------------
// The engine's pipelines (created once, shared by all frames).
// ---------------------------------------------------------------------------------------

/// The engine's pipelines and layouts (created once, shared by all frames).
pub(super) struct Pipelines {
    pub(super) device: ash::Device,
    pub(super) frame_set_layout: vk::DescriptorSetLayout,
    pub(super) image_set_layout: vk::DescriptorSetLayout,
    pub(super) gbuffer_layout: vk::PipelineLayout,
    pub(super) gbuffer: vk::Pipeline,
    pub(super) shade_layout: vk::PipelineLayout,
    pub(super) shade: vk::Pipeline,
    pub(super) sampler: vk::Sampler,
    pub(super) descriptor_pool: vk::DescriptorPool,
    pub(super) command_pool: vk::CommandPool,
}

impl Pipelines {
    pub(super) fn new(device: &ash::Device, queue_family: u32) -> Result<Self> {
        let mut p = Pipelines {
            device: device.clone(),
            frame_set_layout: vk::DescriptorSetLayout::null(),
            image_set_layout: vk::DescriptorSetLayout::null(),
            gbuffer_layout: vk::PipelineLayout::null(),
            gbuffer: vk::Pipeline::null(),
            shade_layout: vk::PipelineLayout::null(),
            shade: vk::Pipeline::null(),
            sampler: vk::Sampler::null(),
            descriptor_pool: vk::DescriptorPool::null(),
            command_pool: vk::CommandPool::null(),
        };
        // On error, dropping `p` destroys what was created.
        p.create(device, queue_family)?;
        Ok(p)
    }

    pub(super) fn create(&mut self, device: &ash::Device, queue_family: u32) -> Result<()> {
        let pool = vk::CommandPoolCreateInfo::default()
            .queue_family_index(queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: the device's queue family, with a pool per engine; destroyed in Drop.
        self.command_pool =
            unsafe { device.create_command_pool(&pool, None) }.vk("vkCreateCommandPool")?;
        let binding = |binding, ty, stages| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(binding)
                .descriptor_type(ty)
                .descriptor_count(1)
                .stage_flags(stages)
        };
        let set_layout = |bindings: &[vk::DescriptorSetLayoutBinding]| {
            let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(bindings);
            // SAFETY: `info` and its bindings live through the call; destroyed in Drop.
            unsafe { device.create_descriptor_set_layout(&info, None) }
                .vk("vkCreateDescriptorSetLayout")
        };
        let pipeline_layout = |sets: &[vk::DescriptorSetLayout], push: vk::PushConstantRange| {
            let push = [push];
            let info = (vk::PipelineLayoutCreateInfo::default())
                .set_layouts(sets)
                .push_constant_ranges(&push);
            // SAFETY: the set layouts are made above; one push range within any device's 128
            // bytes; destroyed in Drop.
            unsafe { device.create_pipeline_layout(&info, None) }.vk("vkCreatePipelineLayout")
        };
        // Set 0: the frame's constants, read by every stage of both passes.
        let all = vk::ShaderStageFlags::VERTEX
            | vk::ShaderStageFlags::FRAGMENT
            | vk::ShaderStageFlags::COMPUTE;
        self.frame_set_layout = set_layout(&[binding(0, vk::DescriptorType::UNIFORM_BUFFER, all)])?;
        // Set 1 of the shading pass: depth, normals, albedo, two masks, the output, motion.
        let sampled = vk::DescriptorType::COMBINED_IMAGE_SAMPLER;
        let c = vk::ShaderStageFlags::COMPUTE;
        let storage = binding(5, vk::DescriptorType::STORAGE_IMAGE, c);
        let images = [0, 1, 2, 3, 4, 6].map(|b| binding(b, sampled, c));
        self.image_set_layout = set_layout(&[&images[..], &[storage]].concat())?;
        let n = FRAMES_IN_FLIGHT as u32;
        let size = |ty, descriptor_count| vk::DescriptorPoolSize {
            ty,
            descriptor_count,
        };
        let sizes = [
            size(vk::DescriptorType::UNIFORM_BUFFER, n),
            size(sampled, 6 * n),
            size(vk::DescriptorType::STORAGE_IMAGE, n),
        ];
        let pool = (vk::DescriptorPoolCreateInfo::default())
            .max_sets(2 * n)
            .pool_sizes(&sizes);
        // Exact texel reads (texelFetch ignores the filter, but a sampler is required).
        let sampler = vk::SamplerCreateInfo::default()
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE);
        // SAFETY: the pool's sizes count every binding of both set layouts for each of the
        // FRAMES_IN_FLIGHT slots; the sampler's state (nearest, clamp) is always supported;
        // both are destroyed in Drop.
        unsafe {
            self.descriptor_pool =
                (device.create_descriptor_pool(&pool, None)).vk("vkCreateDescriptorPool")?;
            self.sampler = device
                .create_sampler(&sampler, None)
                .vk("vkCreateSampler")?;
        }
        let push = |stage_flags, size: usize| vk::PushConstantRange {
            stage_flags,
            offset: 0,
            size: size as u32,
        };
        let draw = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
        self.gbuffer_layout = pipeline_layout(
            &[self.frame_set_layout],
            push(draw, std::mem::size_of::<DrawConstants>()),
        )?;
        self.shade_layout = pipeline_layout(
            &[self.frame_set_layout, self.image_set_layout],
            push(c, std::mem::size_of::<ShadeConstants>()),
        )?;
        self.gbuffer = gbuffer_pipeline(device, self.gbuffer_layout)?;
        self.shade =
            compute_pipeline(device, "shade.comp", sources::SHADE_COMP, self.shade_layout)?;
        Ok(())
    }
}

impl Drop for Pipelines {
    fn drop(&mut self) {
        // Null handles (a failed `new`) are ignored; the command buffers go with their pool,
        // the descriptor sets with theirs.
        let device = &self.device;
        // SAFETY: the engine drops its pipelines after waiting for every slot's frame (its own
        // Drop), so none is in use; null handles of a failed `new` are ignored by the destroy
        // calls.
        unsafe {
            device.destroy_pipeline(self.gbuffer, None);
            device.destroy_pipeline(self.shade, None);
            device.destroy_pipeline_layout(self.gbuffer_layout, None);
            device.destroy_pipeline_layout(self.shade_layout, None);
            device.destroy_descriptor_pool(self.descriptor_pool, None);
            device.destroy_descriptor_set_layout(self.frame_set_layout, None);
            device.destroy_descriptor_set_layout(self.image_set_layout, None);
            device.destroy_sampler(self.sampler, None);
            device.destroy_command_pool(self.command_pool, None);
        }
    }
}

/// The G-buffer pipeline: two vertex bindings (positions, normals) with dynamic strides, a
/// depth test, two color attachments, dynamic rendering (no render pass object).
pub(super) fn gbuffer_pipeline(
    device: &ash::Device,
    layout: vk::PipelineLayout,
) -> Result<vk::Pipeline> {
    let vert = shader_module(
        device,
        &compile_glsl(
            "gbuffer.vert",
            sources::GBUFFER_VERT,
            shaderc::ShaderKind::Vertex,
        )?,
    )?;
    let frag = match compile_glsl(
        "gbuffer.frag",
        sources::GBUFFER_FRAG,
        shaderc::ShaderKind::Fragment,
    )
    .and_then(|code| shader_module(device, &code))
    {
        Ok(m) => m,
        Err(e) => {
            // SAFETY: the fragment module failed, so the vertex module is used by nothing and
            // destroyed once.
            unsafe { device.destroy_shader_module(vert, None) };
            return Err(e);
        }
    };
    let stages = [
        vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::VERTEX)
            .module(vert)
            .name(c"main"),
        vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::FRAGMENT)
            .module(frag)
            .name(c"main"),
    ];
    let bindings = [0, 1, 2].map(|binding| vk::VertexInputBindingDescription {
        binding,
        stride: 24, // overridden per draw (VERTEX_INPUT_BINDING_STRIDE is dynamic)
        input_rate: vk::VertexInputRate::VERTEX,
    });
    let attributes = [0, 1, 2].map(|i| vk::VertexInputAttributeDescription {
        location: i,
        binding: i,
        format: vk::Format::R32G32B32_SFLOAT,
        offset: 0,
    });
    let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
        .vertex_binding_descriptions(&bindings)
        .vertex_attribute_descriptions(&attributes);
    let assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
        .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
    let viewport = vk::PipelineViewportStateCreateInfo::default()
        .viewport_count(1)
        .scissor_count(1);
    // No culling: the ground and the strip are seen from either side.
    let raster = vk::PipelineRasterizationStateCreateInfo::default()
        .polygon_mode(vk::PolygonMode::FILL)
        .cull_mode(vk::CullModeFlags::NONE)
        .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
        .line_width(1.0);
    let multisample = vk::PipelineMultisampleStateCreateInfo::default()
        .rasterization_samples(vk::SampleCountFlags::TYPE_1);
    let depth = vk::PipelineDepthStencilStateCreateInfo::default()
        .depth_test_enable(true)
        .depth_write_enable(true)
        .depth_compare_op(vk::CompareOp::LESS);
    let blend = [vk::PipelineColorBlendAttachmentState::default()
        .color_write_mask(vk::ColorComponentFlags::RGBA); 4];
    let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend);
    let dynamic = [
        vk::DynamicState::VIEWPORT,
        vk::DynamicState::SCISSOR,
        vk::DynamicState::VERTEX_INPUT_BINDING_STRIDE,
    ];
    let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic);
    let formats = [NORMAL_FORMAT, ALBEDO_FORMAT, MOTION_FORMAT, ID_FORMAT];
    let mut rendering = vk::PipelineRenderingCreateInfo::default()
        .color_attachment_formats(&formats)
        .depth_attachment_format(DEPTH_FORMAT);
    let info = [vk::GraphicsPipelineCreateInfo::default()
        .stages(&stages)
        .vertex_input_state(&vertex_input)
        .input_assembly_state(&assembly)
        .viewport_state(&viewport)
        .rasterization_state(&raster)
        .multisample_state(&multisample)
        .depth_stencil_state(&depth)
        .color_blend_state(&blend)
        .dynamic_state(&dynamic)
        .layout(layout)
        .push_next(&mut rendering)];
    // SAFETY: every state struct `info` points at is a local alive for the call, the modules hold
    // the engine's compiled GLSL, and `layout` was made for its push constants and sets.
    let pipeline =
        unsafe { device.create_graphics_pipelines(vk::PipelineCache::null(), &info, None) };
    // SAFETY: pipeline creation has returned; the modules are needed only while it runs.
    unsafe {
        device.destroy_shader_module(vert, None);
        device.destroy_shader_module(frag, None);
    }
    Ok(pipeline
        .map_err(|(_, e)| e)
        .vk("vkCreateGraphicsPipelines")?[0])
}
