//! The engine's pipelines, layouts and pools, made once and shared by all frames; its GLSL
//! (`glsl/`) compiled at run time by shaderc, for Vulkan 1.2 SPIR-V as the book says.

use super::*;
// Links shaderc where the distribution's libshaderc.so cannot be linked as it is.
use motion_shadows_shaderc_link as _;

/// The G-buffer's attachments (after the depth): normal, albedo, world motion, triangle id.
pub(super) const COLOR_FORMATS: [vk::Format; 4] = [
    vk::Format::R16G16B16A16_SFLOAT,
    vk::Format::R8G8B8A8_UNORM,
    vk::Format::R16G16B16A16_SFLOAT,
    vk::Format::R32_UINT,
];
pub(super) const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;
/// The masks: a lit fraction per pixel, a format every device writes as a storage image.
pub(super) const MASK_FORMAT: vk::Format = vk::Format::R32_SFLOAT;

/// `Draw` in glsl/gbuffer.vert: 128 bytes of push constants.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub(super) struct DrawConstants {
    /// The slot's `FrameConstants` by device address.
    pub(super) frame: u64,
    pub(super) pad: u64,
    /// Object to world at t = 1 and t = 0, three rows each.
    pub(super) model: [Vec4; 3],
    pub(super) previous_model: [Vec4; 3],
    pub(super) albedo: Vec3,
    /// The mesh's first global triangle id (its shadow draw's): plus the primitive's index,
    /// the id the G-buffer stores.
    pub(super) first_id: u32,
}

/// `Frame` in glsl/frame.glsl (std430, read by device address).
#[repr(C)]
#[derive(Clone, Copy, Default, Pod, Zeroable)]
pub(super) struct FrameConstants {
    pub(super) view_proj: Mat4,
    pub(super) inv_view_proj: Mat4,
    pub(super) eye: Vec4,
    /// Width, height, lights.
    pub(super) info: UVec4,
    /// x: the ambient factor.
    pub(super) shading: Vec4,
    pub(super) lights: [[Vec4; 3]; MAX_LIGHTS],
}

/// The engine's pipelines and what they need (each destroyed once, in Drop).
#[derive(Default)]
pub(super) struct Pipelines {
    device: Option<ash::Device>,
    pub(super) command_pool: vk::CommandPool,
    pub(super) descriptor_pool: vk::DescriptorPool,
    /// The shading's images: depth, normal, albedo, mask 0, mask 1.
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
        let vert =
            compile_glsl("gbuffer.vert", include_str!("../../glsl/gbuffer.vert"), K::Vertex)?;
        let frag =
            compile_glsl("gbuffer.frag", include_str!("../../glsl/gbuffer.frag"), K::Fragment)?;
        let comp = compile_glsl("shade.comp", include_str!("../../glsl/shade.comp"), K::Compute)?;
        let compute = vk::ShaderStageFlags::COMPUTE;
        let bindings = [0, 1, 2, 3, 4].map(|binding| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(binding)
                .descriptor_type(vk::DescriptorType::SAMPLED_IMAGE)
                .descriptor_count(1)
                .stage_flags(compute)
        });
        let n = FRAMES_IN_FLIGHT as u32;
        let sizes = [vk::DescriptorPoolSize {
            ty: vk::DescriptorType::SAMPLED_IMAGE,
            descriptor_count: 5 * n,
        }];
        let draw = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
        let push = |stage_flags, size: usize| {
            [vk::PushConstantRange { stage_flags, offset: 0, size: size as u32 }]
        };
        let (draw_push, shade_push) = (push(draw, size_of::<DrawConstants>()), push(compute, 24));
        let attributes = [0, 1].map(|location| vk::VertexInputAttributeDescription {
            location,
            binding: 0,
            format: vk::Format::R32G32B32_SFLOAT,
            offset: 12 * location,
        });
        let binding = [vk::VertexInputBindingDescription {
            binding: 0,
            stride: 24,
            input_rate: vk::VertexInputRate::VERTEX,
        }];
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
            .vertex_binding_descriptions(&binding)
            .vertex_attribute_descriptions(&attributes);
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
            .depth_write_enable(true)
            .depth_compare_op(vk::CompareOp::LESS);
        let blend = [vk::PipelineColorBlendAttachmentState::default()
            .color_write_mask(vk::ColorComponentFlags::RGBA); 4];
        let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend);
        let dynamic = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic);
        let mut rendering = vk::PipelineRenderingCreateInfo::default()
            .color_attachment_formats(&COLOR_FORMATS)
            .depth_attachment_format(DEPTH_FORMAT);
        let pool = vk::CommandPoolCreateInfo::default()
            .queue_family_index(queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: every create info is a local alive for its call, the modules hold shaderc's
        // SPIR-V of the engine's GLSL, whose push constants and set the layouts match (the
        // push ranges within any device's 128 bytes); the pool's sizes count every set of the
        // FRAMES_IN_FLIGHT slots. The modules go once the pipelines are made; on an error,
        // Drop destroys what was made.
        unsafe {
            let module = |code: &[u32]| {
                device.create_shader_module(&vk::ShaderModuleCreateInfo::default().code(code), None)
            };
            let modules = [module(&vert), module(&frag), module(&comp)];
            let made = (|| -> Result<()> {
                let stages =
                    [vk::ShaderStageFlags::VERTEX, vk::ShaderStageFlags::FRAGMENT, compute]
                        .into_iter()
                        .zip(&modules)
                        .map(|(stage, module)| {
                            Ok(vk::PipelineShaderStageCreateInfo::default()
                                .stage(stage)
                                .module((*module)?)
                                .name(c"main"))
                        })
                        .collect::<std::result::Result<Vec<_>, vk::Result>>()?;
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
                let info = [vk::GraphicsPipelineCreateInfo::default()
                    .stages(&stages[..2])
                    .vertex_input_state(&vertex_input)
                    .input_assembly_state(&assembly)
                    .viewport_state(&viewport)
                    .rasterization_state(&raster)
                    .multisample_state(&multisample)
                    .depth_stencil_state(&depth)
                    .color_blend_state(&blend)
                    .dynamic_state(&dynamic)
                    .layout(p.gbuffer_layout)
                    .push_next(&mut rendering)];
                let cache = vk::PipelineCache::null();
                p.gbuffer =
                    device.create_graphics_pipelines(cache, &info, None).map_err(|e| e.1)?[0];
                let info = [vk::ComputePipelineCreateInfo::default()
                    .stage(stages[2])
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
        // the command buffers and sets go with their pools; null handles (what a failed `new`
        // did not make) are ignored.
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
    options.set_include_callback(|requested, _, _, _| match requested {
        "frame.glsl" => Ok(shaderc::ResolvedInclude {
            resolved_name: requested.into(),
            content: include_str!("../../glsl/frame.glsl").into(),
        }),
        other => Err(format!("no header {other}")),
    });
    let compiler = shaderc::Compiler::new()?;
    Ok(compiler
        .compile_into_spirv(source, kind, name, "main", Some(&options))?
        .as_binary()
        .to_vec())
}
