//! Test-only compute shaders (`tests/glsl/`), compiled here with the library's own includes
//! (`glsl/`) and generated constants, so that they read the structs and functions the
//! library's shaders use, not copies.

use motion_shadows::technique::gpu_constants;
// Links shaderc where the distribution's libshaderc.so cannot be linked as it is; see
// build-support/shaderc-link.
use motion_shadows_shaderc_link as _;

/// SPIR-V of the compute shader `source` (named `name` in messages).
pub fn compile_compute(name: &str, source: &str) -> Vec<u8> {
    // The library's GLSL, beside this crate in the repository.
    let glsl = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../glsl");
    let compiler = shaderc::Compiler::new().expect("shaderc");
    let mut options = shaderc::CompileOptions::new().expect("shaderc options");
    options.set_target_env(
        shaderc::TargetEnv::Vulkan,
        shaderc::EnvVersion::Vulkan1_2 as u32,
    );
    options.set_include_callback(move |name, _kind, _from, _depth| {
        let content = if name == "gpu_constants.glsl" {
            gpu_constants::glsl_header()
        } else {
            std::fs::read_to_string(glsl.join(name)).map_err(|e| format!("{name}: {e}"))?
        };
        Ok(shaderc::ResolvedInclude {
            resolved_name: name.to_owned(),
            content,
        })
    });
    compiler
        .compile_into_spirv(
            source,
            shaderc::ShaderKind::Compute,
            name,
            "main",
            Some(&options),
        )
        .unwrap_or_else(|e| panic!("{e}"))
        .as_binary_u8()
        .to_vec()
}
