//! The engine's GLSL, compiled at run time by shaderc.

use super::*;

// ---------------------------------------------------------------------------------------
// Shaders: GLSL compiled at run time by shaderc, the library's header served from the Rust
// constant `GLSL_INCLUDE` by the include callback, exactly as a host's shader system would.
// ---------------------------------------------------------------------------------------

/// The host's own shader sources (the crate's `glsl/`).
pub mod sources {
    pub const FRAME_GLSL: &str = include_str!("../../glsl/frame.glsl");
    pub const GBUFFER_VERT: &str = include_str!("../../glsl/gbuffer.vert");
    pub const GBUFFER_FRAG: &str = include_str!("../../glsl/gbuffer.frag");
    pub const SHADE_COMP: &str = include_str!("../../glsl/shade.comp");
}

/// Compiles one GLSL stage to SPIR-V. `#include "motion_shadows.glsl"` resolves to the
/// library's header, `#include "frame.glsl"` to the host's own.
pub fn compile_glsl(name: &str, source: &str, kind: shaderc::ShaderKind) -> Result<Vec<u32>> {
    let compiler = shaderc::Compiler::new()?;
    let mut options = shaderc::CompileOptions::new()?;
    options.set_target_env(
        shaderc::TargetEnv::Vulkan,
        shaderc::EnvVersion::Vulkan1_2 as u32,
    );
    options.set_optimization_level(shaderc::OptimizationLevel::Performance);
    options.set_include_callback(|requested, _kind, _from, _depth| {
        let content = match requested {
            "motion_shadows.glsl" => GLSL_INCLUDE,
            "frame.glsl" => sources::FRAME_GLSL,
            other => return Err(format!("no header {other}")),
        };
        Ok(shaderc::ResolvedInclude {
            resolved_name: requested.to_owned(),
            content: content.to_owned(),
        })
    });
    let artifact = compiler.compile_into_spirv(source, kind, name, "main", Some(&options))?;
    Ok(artifact.as_binary().to_vec())
}

/// A shader module of `code`, destroyed by the caller once the pipeline exists.
pub fn shader_module(device: &ash::Device, code: &[u32]) -> Result<vk::ShaderModule> {
    let info = vk::ShaderModuleCreateInfo::default().code(code);
    // SAFETY: `code` is SPIR-V that shaderc compiled from the engine's own GLSL for Vulkan 1.3,
    // read into aligned words.
    unsafe { device.create_shader_module(&info, None) }.vk("vkCreateShaderModule")
}

/// A compute pipeline of one GLSL source.
pub fn compute_pipeline(
    device: &ash::Device,
    name: &str,
    source: &str,
    layout: vk::PipelineLayout,
) -> Result<vk::Pipeline> {
    let module = shader_module(
        device,
        &compile_glsl(name, source, shaderc::ShaderKind::Compute)?,
    )?;
    let stage = vk::PipelineShaderStageCreateInfo::default()
        .stage(vk::ShaderStageFlags::COMPUTE)
        .module(module)
        .name(c"main");
    let info = [vk::ComputePipelineCreateInfo::default()
        .stage(stage)
        .layout(layout)];
    // SAFETY: the module holds shaderc's SPIR-V of the engine's GLSL, whose push constants and
    // bindings `layout` was made for; `info` lives through the call.
    let pipeline =
        unsafe { device.create_compute_pipelines(vk::PipelineCache::null(), &info, None) };
    // SAFETY: pipeline creation has returned, and a module may go once its pipelines are made.
    unsafe { device.destroy_shader_module(module, None) };
    Ok(pipeline
        .map_err(|(_, e)| e)
        .vk("vkCreateComputePipelines")?[0])
}
