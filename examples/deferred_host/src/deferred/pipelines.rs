//! The engine's pipelines, layouts and pools, made once for all frames, and its GLSL
//! (`glsl/`) compiled at run time by shaderc for Vulkan 1.2 SPIR-V, as the book says.

use super::*;
// Links shaderc where the distribution's libshaderc.so cannot be linked as it is.
use motion_shadows_shaderc_link as _;

/// The G-buffer: depth, then normal, albedo, world motion and triangle id.
pub(super) const FORMATS: [vk::Format; 5] = [
    vk::Format::D32_SFLOAT,
    vk::Format::R16G16B16A16_SFLOAT,
    vk::Format::R8G8B8A8_UNORM,
    vk::Format::R16G16B16A16_SFLOAT,
    vk::Format::R32_UINT,
];

/// `Draw` in glsl/gbuffer.vert: 128 bytes of push constants.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub(super) struct DrawConstants {
    /// The slot's `FrameConstants`, by device address.
    pub(super) frame: [u64; 2],
    /// Object to world at t = 1 and t = 0, three rows each.
    pub(super) model: [Vec4; 3],
    pub(super) previous_model: [Vec4; 3],
    pub(super) albedo: Vec3,
    /// The mesh's first global triangle id (its shadow draw's).
    pub(super) first_id: u32,
}

/// `Frame` in glsl/frame.glsl, read by device address; `lights` as its `Light`s.
#[repr(C)]
#[derive(Clone, Copy, Default, Pod, Zeroable)]
pub(super) struct FrameConstants {
    pub(super) view_proj: Mat4,
    pub(super) inv_view_proj: Mat4,
    pub(super) eye: Vec4,
    pub(super) info: UVec4,
    pub(super) ambient: Vec4,
    pub(super) lights: [[Vec4; 3]; MAX_LIGHTS],
}

/// The engine's pipelines and what they need; the shading's set holds depth, normal,
/// albedo, mask 0 and mask 1.
#[derive(Default)]
pub(super) struct Pipelines {
    device: Option<ash::Device>,
    pub(super) command_pool: vk::CommandPool,
    pub(super) descriptor_pool: vk::DescriptorPool,
    pub(super) set_layout: vk::DescriptorSetLayout,
    pub(super) gbuffer_layout: vk::PipelineLayout,
    pub(super) shade_layout: vk::PipelineLayout,
    pub(super) gbuffer: vk::Pipeline,
    pub(super) shade: vk::Pipeline,
}

impl Pipelines {
    pub(super) fn new(device: &ash::Device, queue_family: u32) -> Result<Self> {
        let mut p = Pipelines { device: Some(device.clone()), ..Default::default() };
        use shaderc::ShaderKind as K;
        let spirv = [
            compile_glsl("gbuffer.vert", include_str!("../../glsl/gbuffer.vert"), K::Vertex)?,
            compile_glsl("gbuffer.frag", include_str!("../../glsl/gbuffer.frag"), K::Fragment)?,
            compile_glsl("shade.comp", include_str!("../../glsl/shade.comp"), K::Compute)?,
        ];
        use vk::ShaderStageFlags as Stage;
        let bindings = [0, 1, 2, 3, 4].map(|binding| {
            let binding =
                vk::DescriptorSetLayoutBinding::default().binding(binding).descriptor_count(1);
            binding.descriptor_type(vk::DescriptorType::SAMPLED_IMAGE).stage_flags(Stage::COMPUTE)
        });
        let n = FRAMES_IN_FLIGHT as u32;
        let sizes = [vk::DescriptorPoolSize {
            ty: vk::DescriptorType::SAMPLED_IMAGE,
            descriptor_count: 5 * n,
        }];
        let push = |stage_flags, size: usize| {
            [vk::PushConstantRange { stage_flags, offset: 0, size: size as u32 }]
        };
        let (draw_push, shade_push) = (
            push(Stage::VERTEX | Stage::FRAGMENT, size_of::<DrawConstants>()),
            push(Stage::COMPUTE, 24),
        );
        let attribute = |location| vk::VertexInputAttributeDescription {
            location,
            binding: 0,
            format: vk::Format::R32G32B32_SFLOAT,
            offset: 12 * location,
        };
        let (attributes, input_rate) = ([attribute(0), attribute(1)], vk::VertexInputRate::VERTEX);
        let binding = [vk::VertexInputBindingDescription {
            binding: 0,
            stride: size_of::<Vertex>() as u32,
            input_rate,
        }];
        let vertex_input =
            vk::PipelineVertexInputStateCreateInfo::default().vertex_binding_descriptions(&binding);
        let vertex_input = vertex_input.vertex_attribute_descriptions(&attributes);
        let assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
            .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
        let viewport =
            vk::PipelineViewportStateCreateInfo::default().viewport_count(1).scissor_count(1);
        // No culling: the ground is seen from either side.
        let raster = vk::PipelineRasterizationStateCreateInfo::default().line_width(1.0);
        let multisample = vk::PipelineMultisampleStateCreateInfo::default()
            .rasterization_samples(vk::SampleCountFlags::TYPE_1);
        let depth = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(true)
            .depth_write_enable(true);
        let depth = depth.depth_compare_op(vk::CompareOp::LESS);
        let blend = [vk::PipelineColorBlendAttachmentState::default()
            .color_write_mask(vk::ColorComponentFlags::RGBA); 4];
        let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend);
        let dynamic = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic);
        let formats =
            vk::PipelineRenderingCreateInfo::default().color_attachment_formats(&FORMATS[1..]);
        let mut formats = formats.depth_attachment_format(FORMATS[0]);
        let pool = vk::CommandPoolCreateInfo::default().queue_family_index(queue_family);
        let pool = pool.flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        let cache = vk::PipelineCache::null();
        // SAFETY: every create info is a local alive for its call; the modules hold shaderc's
        // SPIR-V of the engine's GLSL, whose push constants and set the layouts match (each
        // push range within any device's 128 bytes); the pool counts every slot's set. The
        // modules go once the pipelines are made; on an error, Drop destroys what was made.
        unsafe {
            let module = |code: &[u32]| {
                device.create_shader_module(&vk::ShaderModuleCreateInfo::default().code(code), None)
            };
            let modules = spirv.each_ref().map(|code| module(code));
            let made = (|| -> Result<()> {
                let stage = |stage, module: &std::result::Result<_, _>| {
                    Ok::<_, vk::Result>(
                        vk::PipelineShaderStageCreateInfo::default()
                            .stage(stage)
                            .module(*module.as_ref().map_err(|e| *e)?)
                            .name(c"main"),
                    )
                };
                let stages =
                    [stage(Stage::VERTEX, &modules[0])?, stage(Stage::FRAGMENT, &modules[1])?];
                p.command_pool = device.create_command_pool(&pool, None)?;
                let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
                p.set_layout = device.create_descriptor_set_layout(&info, None)?;
                let info = vk::DescriptorPoolCreateInfo::default().max_sets(n).pool_sizes(&sizes);
                p.descriptor_pool = device.create_descriptor_pool(&info, None)?;
                let info = vk::PipelineLayoutCreateInfo::default().push_constant_ranges(&draw_push);
                p.gbuffer_layout = device.create_pipeline_layout(&info, None)?;
                let sets = [p.set_layout];
                let info = vk::PipelineLayoutCreateInfo::default()
                    .set_layouts(&sets)
                    .push_constant_ranges(&shade_push);
                p.shade_layout = device.create_pipeline_layout(&info, None)?;
                let info = vk::GraphicsPipelineCreateInfo::default()
                    .stages(&stages)
                    .vertex_input_state(&vertex_input);
                let info = info
                    .input_assembly_state(&assembly)
                    .viewport_state(&viewport)
                    .rasterization_state(&raster);
                let info = info
                    .multisample_state(&multisample)
                    .depth_stencil_state(&depth)
                    .color_blend_state(&blend);
                let info = info.dynamic_state(&dynamic).layout(p.gbuffer_layout);
                let info = [info.push_next(&mut formats)];
                p.gbuffer =
                    device.create_graphics_pipelines(cache, &info, None).map_err(|e| e.1)?[0];
                let info = [vk::ComputePipelineCreateInfo::default()
                    .stage(stage(Stage::COMPUTE, &modules[2])?)
                    .layout(p.shade_layout)];
                p.shade = device.create_compute_pipelines(cache, &info, None).map_err(|e| e.1)?[0];
                Ok(())
            })();
            for module in modules.into_iter().flatten() {
                device.destroy_shader_module(module, None);
            }
            made?;
        }
        Ok(p)
    }
}

impl Drop for Pipelines {
    fn drop(&mut self) {
        let Some(device) = &self.device else { return };
        // SAFETY: the engine drops its pipelines after waiting for every frame (its Drop);
        // command buffers and sets go with their pools; null handles (not made) are ignored.
        unsafe {
            device.destroy_pipeline(self.gbuffer, None);
            device.destroy_pipeline(self.shade, None);
            device.destroy_pipeline_layout(self.gbuffer_layout, None);
            device.destroy_pipeline_layout(self.shade_layout, None);
            device.destroy_descriptor_pool(self.descriptor_pool, None);
            device.destroy_descriptor_set_layout(self.set_layout, None);
            device.destroy_command_pool(self.command_pool, None);
        }
    }
}

/// Compiles one stage for Vulkan 1.2 SPIR-V; `#include "frame.glsl"` is the engine's header.
fn compile_glsl(name: &str, source: &str, kind: shaderc::ShaderKind) -> Result<Vec<u32>> {
    let mut options = shaderc::CompileOptions::new()?;
    options.set_target_env(shaderc::TargetEnv::Vulkan, shaderc::EnvVersion::Vulkan1_2 as u32);
    options.set_include_callback(|requested, _, _, _| {
        let content = include_str!("../../glsl/frame.glsl").into();
        let found = shaderc::ResolvedInclude { resolved_name: requested.into(), content };
        if requested == "frame.glsl" { Ok(found) } else { Err(format!("no header {requested}")) }
    });
    let spirv =
        shaderc::Compiler::new()?.compile_into_spirv(source, kind, name, "main", Some(&options))?;
    Ok(spirv.as_binary().to_vec())
}
