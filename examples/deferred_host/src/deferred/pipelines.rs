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

/// `Draw` in glsl/gbuffer.vert (128 bytes): the frame's constants and the vertex buffer by
/// address, object to world at t = 1 and t = 0 (three rows each), the albedo, and the
/// mesh's first global triangle id (its shadow draw's).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub(super) struct DrawConstants {
    pub(super) addresses: [u64; 2],
    pub(super) model: [Vec4; 3],
    pub(super) previous_model: [Vec4; 3],
    pub(super) albedo: Vec3,
    pub(super) first_id: u32,
}

/// `Frame` in glsl/frame.glsl (read by address): `info` = width, height, lights.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub(super) struct FrameConstants {
    pub(super) view_proj: Mat4,
    pub(super) inv_view_proj: Mat4,
    pub(super) eye: Vec4,
    pub(super) info: UVec4,
    pub(super) ambient: Vec4,
}

/// The engine's pipelines and what they need; the shading's descriptor set holds depth,
/// normal, albedo, mask 0 and mask 1 (sampled images).
#[derive(Default)]
pub(super) struct Pipelines {
    device: Option<ash::Device>,
    pub(super) command_pool: vk::CommandPool,
    pub(super) descriptor_pool: vk::DescriptorPool,
    pub(super) set_layout: vk::DescriptorSetLayout,
    pub(super) layouts: [vk::PipelineLayout; 2],
    pub(super) gbuffer: vk::Pipeline,
    pub(super) shade: vk::Pipeline,
}

impl Pipelines {
    pub(super) fn new(device: &ash::Device, queue_family: u32) -> Result<Self> {
        let mut p = Pipelines {
            device: Some(device.clone()),
            ..Default::default()
        };
        use {shaderc::ShaderKind as K, vk::ShaderStageFlags as Stage};
        let spirv = [
            compile(
                "gbuffer.vert",
                include_str!("../../glsl/gbuffer.vert"),
                K::Vertex,
            )?,
            compile(
                "gbuffer.frag",
                include_str!("../../glsl/gbuffer.frag"),
                K::Fragment,
            )?,
            compile(
                "shade.comp",
                include_str!("../../glsl/shade.comp"),
                K::Compute,
            )?,
        ];
        let binding = vk::DescriptorSetLayoutBinding::default().descriptor_count(1);
        let binding = binding.descriptor_type(vk::DescriptorType::SAMPLED_IMAGE);
        let bindings = [0, 1, 2, 3, 4].map(|b| binding.binding(b).stage_flags(Stage::COMPUTE));
        let (ty, n) = (vk::DescriptorType::SAMPLED_IMAGE, FRAMES_IN_FLIGHT as u32);
        let sizes = [vk::DescriptorPoolSize {
            ty,
            descriptor_count: 5 * n,
        }];
        let draw = Stage::VERTEX | Stage::FRAGMENT;
        let push = |stage_flags, size| {
            [vk::PushConstantRange {
                stage_flags,
                offset: 0,
                size,
            }]
        };
        let pushes = [
            push(draw, size_of::<DrawConstants>() as u32),
            push(Stage::COMPUTE, 40),
        ];
        let vertices = vk::PipelineVertexInputStateCreateInfo::default(); // pulled by address
        let triangles = vk::PrimitiveTopology::TRIANGLE_LIST;
        let assembly = vk::PipelineInputAssemblyStateCreateInfo::default().topology(triangles);
        let viewport = vk::PipelineViewportStateCreateInfo::default().viewport_count(1);
        let viewport = viewport.scissor_count(1);
        // No culling: the ground is seen from either side.
        let raster = vk::PipelineRasterizationStateCreateInfo::default().line_width(1.0);
        let samples = vk::SampleCountFlags::TYPE_1;
        let multisample = vk::PipelineMultisampleStateCreateInfo::default();
        let multisample = multisample.rasterization_samples(samples);
        let depth = vk::PipelineDepthStencilStateCreateInfo::default().depth_test_enable(true);
        let depth = depth
            .depth_write_enable(true)
            .depth_compare_op(vk::CompareOp::LESS);
        let rgba = vk::ColorComponentFlags::RGBA;
        let blend = [vk::PipelineColorBlendAttachmentState::default().color_write_mask(rgba); 4];
        let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend);
        let dynamic = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic);
        let formats =
            vk::PipelineRenderingCreateInfo::default().depth_attachment_format(FORMATS[0]);
        let mut formats = formats.color_attachment_formats(&FORMATS[1..]);
        let pool = vk::CommandPoolCreateInfo::default().queue_family_index(queue_family);
        let pool = pool.flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        let cache = vk::PipelineCache::null();
        // SAFETY: every create info is a local alive for its call; the modules hold shaderc's
        // SPIR-V of the engine's GLSL, whose push constants and set the layouts match (each
        // push range within any device's 128 bytes); the pool counts every slot's set. The
        // modules go once the pipelines are made; on an error, Drop destroys what was made.
        unsafe {
            let module = |code: &Vec<u32>| {
                let info = vk::ShaderModuleCreateInfo::default().code(code);
                device.create_shader_module(&info, None)
            };
            let modules = spirv.each_ref().map(module);
            let made = (|| -> Result<()> {
                let [vert, frag, comp] = modules.map(|m| m.map_err(Error::from));
                let stage = |stage, module| {
                    let info = vk::PipelineShaderStageCreateInfo::default().stage(stage);
                    info.module(module).name(c"main")
                };
                let stages = [stage(Stage::VERTEX, vert?), stage(Stage::FRAGMENT, frag?)];
                p.command_pool = device.create_command_pool(&pool, None)?;
                let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
                p.set_layout = device.create_descriptor_set_layout(&info, None)?;
                let info = vk::DescriptorPoolCreateInfo::default()
                    .max_sets(n)
                    .pool_sizes(&sizes);
                p.descriptor_pool = device.create_descriptor_pool(&info, None)?;
                let sets = [[].as_slice(), &[p.set_layout]];
                for ((layout, sets), push) in p.layouts.iter_mut().zip(sets).zip(&pushes) {
                    let info = vk::PipelineLayoutCreateInfo::default().set_layouts(sets);
                    *layout =
                        device.create_pipeline_layout(&info.push_constant_ranges(push), None)?;
                }
                let info = vk::GraphicsPipelineCreateInfo::default().stages(&stages);
                let info = info
                    .vertex_input_state(&vertices)
                    .input_assembly_state(&assembly);
                let info = info.viewport_state(&viewport).rasterization_state(&raster);
                let info = info
                    .multisample_state(&multisample)
                    .depth_stencil_state(&depth);
                let info = info.color_blend_state(&blend).dynamic_state(&dynamic);
                let info = [info.layout(p.layouts[0]).push_next(&mut formats)];
                p.gbuffer = device
                    .create_graphics_pipelines(cache, &info, None)
                    .map_err(|e| e.1)?[0];
                let info = vk::ComputePipelineCreateInfo::default().layout(p.layouts[1]);
                let info = [info.stage(stage(Stage::COMPUTE, comp?))];
                p.shade = device
                    .create_compute_pipelines(cache, &info, None)
                    .map_err(|e| e.1)?[0];
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
            for layout in self.layouts {
                device.destroy_pipeline_layout(layout, None);
            }
            device.destroy_descriptor_pool(self.descriptor_pool, None);
            device.destroy_descriptor_set_layout(self.set_layout, None);
            device.destroy_command_pool(self.command_pool, None);
        }
    }
}

/// One stage as Vulkan 1.2 SPIR-V; `#include` serves the library's header (`GLSL_INCLUDE`)
/// and the engine's own `frame.glsl`.
fn compile(name: &str, source: &str, kind: shaderc::ShaderKind) -> Result<Vec<u32>> {
    let mut options = shaderc::CompileOptions::new()?;
    options.set_target_env(
        shaderc::TargetEnv::Vulkan,
        shaderc::EnvVersion::Vulkan1_2 as u32,
    );
    options.set_include_callback(|requested, _, _, _| {
        let content = match requested {
            "motion_shadows.glsl" => GLSL_INCLUDE,
            "frame.glsl" => include_str!("../../glsl/frame.glsl"),
            _ => return Err(format!("no header {requested}")),
        };
        Ok(shaderc::ResolvedInclude {
            resolved_name: requested.into(),
            content: content.into(),
        })
    });
    let compiler = shaderc::Compiler::new()?;
    Ok(compiler
        .compile_into_spirv(source, kind, name, "main", Some(&options))?
        .as_binary()
        .into())
}
