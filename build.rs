//! Compiles every GLSL shader in `glsl/` to SPIR-V in `OUT_DIR`, so a shader error fails the
//! build with the file and line. Files ending in `.glsl` are includes, not stages. The
//! constants shared with the Rust side are generated first, from the one table in
//! `src/technique/gpu_constants.rs`, as the include `gpu_constants.glsl`.
//!
//! For hosts that compile their own shaders at build time, it exports the absolute path of
//! `glsl/` (which holds the public include `motion_shadows.glsl`, self-contained) as the
//! `links` metadata `glsl_dir` and `include`: a direct dependent's build script reads
//! `DEP_MOTION_SHADOWS_GLSL_DIR` (or `DEP_MOTION_SHADOWS_INCLUDE`).

use std::path::{Path, PathBuf};
// Links shaderc where the distribution's libshaderc.so cannot be linked as it is (Debian 12);
// see build-support/shaderc-link. Naming the crate is what puts its link arguments on ours.
use motion_shadows_shaderc_link as _;

#[path = "src/technique/gpu_constants.rs"]
#[allow(dead_code)]
mod gpu_constants;

/// The generated include's name, as the shaders `#include` it.
const GENERATED_CONSTANTS: &str = "gpu_constants.glsl";
/// Includes that no stage includes yet (building blocks for passes still to come), compiled
/// alone so that the build checks them.
const CHECKED_ALONE: &[&str] = &["exact_shadow.glsl"];

/// The layout witness: the structs that the library's shaders declare but only read and write
/// as 64-bit words (`load_node`, `store_range`, `load_camera`), so that no compiled stage lays
/// them out. Each is written whole through a buffer reference here, so that its std430 layout
/// is in this module's SPIR-V for the device-free layout check
/// (`src/technique/shaders/layout_check.rs`). Compiled like the stages, never run.
const LAYOUT_WITNESS: &str = "layout_witness.comp";
const LAYOUT_WITNESS_SOURCE: &str = r#"#version 450
#include "shared.glsl"
layout(buffer_reference, std430, buffer_reference_align = 16) buffer WitnessNode { Node v; };
layout(buffer_reference, std430, buffer_reference_align = 16) buffer WitnessRange { MsRange v; };
layout(buffer_reference, std430, buffer_reference_align = 16) buffer WitnessCamera {
    CameraParams v;
};
layout(push_constant) uniform WitnessPush { uint64_t node; uint64_t range; uint64_t camera; };
layout(local_size_x = 1) in;
void main() {
    WitnessNode(node).v = Node(0.0, 0.0, 0u, 0u);
    WitnessRange(range).v = MsRange(0.0, 0.0, 0.0, 0.0, 0u, 0u);
    WitnessCamera(camera).v = CameraParams(mat4(0.0), vec4(0.0), vec4(0.0), vec4(0.0),
        vec4(0.0), vec4(0.0), uvec4(0u), vec4(0.0), 0ul, 0ul, 0ul, 0ul);
}
"#;

fn stage_of(path: &Path) -> Option<shaderc::ShaderKind> {
    match path.extension()?.to_str()? {
        "vert" => Some(shaderc::ShaderKind::Vertex),
        "geom" => Some(shaderc::ShaderKind::Geometry),
        "frag" => Some(shaderc::ShaderKind::Fragment),
        "comp" => Some(shaderc::ShaderKind::Compute),
        _ => None,
    }
}

fn main() {
    let glsl_dir = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").unwrap()).join("glsl");
    let out_dir = PathBuf::from(std::env::var("OUT_DIR").unwrap());
    println!("cargo:rerun-if-changed={}", glsl_dir.display());
    // `cargo:KEY=VALUE` of a `links` package: DEP_MOTION_SHADOWS_<KEY> in the build scripts
    // of the crates that depend on it directly.
    println!("cargo:glsl_dir={}", glsl_dir.display());
    println!("cargo:include={}", glsl_dir.display());
    println!("cargo:rerun-if-changed=src/technique/gpu_constants.rs");
    let constants = gpu_constants::glsl_header();
    std::fs::write(out_dir.join(GENERATED_CONSTANTS), &constants).expect("write constants");

    let compiler = shaderc::Compiler::new().expect("shaderc compiler");
    let mut entries: Vec<PathBuf> = std::fs::read_dir(&glsl_dir)
        .expect("read glsl/")
        .map(|e| e.expect("dir entry").path())
        .collect();
    entries.sort();

    let options = || {
        let include_dir = glsl_dir.clone();
        let mut options = shaderc::CompileOptions::new().expect("shaderc options");
        options.set_target_env(
            shaderc::TargetEnv::Vulkan,
            shaderc::EnvVersion::Vulkan1_2 as u32,
        );
        options.set_optimization_level(shaderc::OptimizationLevel::Performance);
        options.set_generate_debug_info();
        let constants = constants.clone();
        options.set_include_callback(move |name, _kind, _from, _depth| {
            if name == GENERATED_CONSTANTS {
                return Ok(shaderc::ResolvedInclude {
                    resolved_name: GENERATED_CONSTANTS.to_owned(),
                    content: constants.clone(),
                });
            }
            let p = include_dir.join(name);
            std::fs::read_to_string(&p)
                .map(|content| shaderc::ResolvedInclude {
                    resolved_name: p.display().to_string(),
                    content,
                })
                .map_err(|e| format!("cannot include {}: {e}", p.display()))
        });
        options
    };

    let mut failures = Vec::new();
    for path in &entries {
        println!("cargo:rerun-if-changed={}", path.display());
        let Some(kind) = stage_of(path) else { continue };
        let source = std::fs::read_to_string(path).expect("read shader");
        let file_name = path.file_name().unwrap().to_str().unwrap().to_owned();
        match compiler.compile_into_spirv(&source, kind, &file_name, "main", Some(&options())) {
            Ok(artifact) => {
                let out = out_dir.join(format!("{file_name}.spv"));
                std::fs::write(out, artifact.as_binary_u8()).expect("write spv");
            }
            Err(e) => failures.push(format!("glsl/{e}")),
        }
    }
    // Includes that no stage of the library includes yet are compiled alone, inside an empty
    // compute shader, so that an error in them fails the build too (nothing is written).
    for include in CHECKED_ALONE {
        let source = format!(
            "#version 450\n#include \"{include}\"\nlayout(local_size_x = 1) in;\nvoid main() {{}}\n"
        );
        let name = format!("{include} (checked alone)");
        let kind = shaderc::ShaderKind::Compute;
        if let Err(e) = compiler.compile_into_spirv(&source, kind, &name, "main", Some(&options()))
        {
            failures.push(format!("glsl/{e}"));
        }
    }
    let kind = shaderc::ShaderKind::Compute;
    let witness = LAYOUT_WITNESS_SOURCE;
    match compiler.compile_into_spirv(witness, kind, LAYOUT_WITNESS, "main", Some(&options())) {
        Ok(artifact) => {
            let out = out_dir.join(format!("{LAYOUT_WITNESS}.spv"));
            std::fs::write(out, artifact.as_binary_u8()).expect("write spv");
        }
        Err(e) => failures.push(format!("build.rs's {e}")),
    }
    if !failures.is_empty() {
        panic!("shader compilation failed:\n{}", failures.join("\n"));
    }
}
