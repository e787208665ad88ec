//! The library as an engine outside this repository sees it: a crate that depends on
//! motion-shadows by path, with no `.cargo/config.toml` of ours around it.
//!
//! - `dependency_tree_is_lean`: `cargo tree` of such a crate holds none of the app's crates,
//!   and motion-shadows' own normal dependencies are a subset of the library's few.
//! - `dependent_builds_and_links`: such a crate builds (motion-shadows' build script links
//!   shaderc and compiles the GLSL) and its program, which uses library items, links and runs.
//!   This is what the `motion-shadows-shaderc-link` build-dependency is for: on Debian 12 the
//!   default shaderc link fails, and a `.cargo/config.toml` in this repository would not apply
//!   to a dependent. The crate's own build script compiles a shader of its own that includes
//!   `motion_shadows.glsl`, found through `DEP_MOTION_SHADOWS_GLSL_DIR` (the library's `links`
//!   metadata), with shaderc linked the way a host links it: the
//!   `motion-shadows-shaderc-link` build-dependency, named once in its build script.
//!
//! The temporary crates live under `CARGO_TARGET_TMPDIR` with their own target directories
//! (cargo holds the lock on the workspace's target directory during `cargo test`). Cargo is run
//! from the system temporary directory, because cargo reads `.cargo/config.toml` from its
//! working directory upwards: run from here it would apply this repository's configuration,
//! which an engine elsewhere does not get. The first run compiles ash, gpu-allocator, glam and
//! shaderc's crates once for that target directory; later runs rebuild only what changed.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Crates of the app (CLI, scenes, image output, progress bars, ...) that must never reach an
/// engine that depends on the library.
const APP_CRATES: &[&str] = &[
    "motion-shadows-app",
    "clap",
    "clap_builder",
    "clap_derive",
    "indicatif",
    "image",
    "png",
    "exr",
    "tobj",
    "anyhow",
    "serde_json",
    "serde",
    "serde_derive",
];

/// The only crates motion-shadows itself may depend on (normal dependencies).
const LIBRARY_DEPENDENCIES: &[&str] = &[
    "ash",
    "gpu-allocator",
    "glam",
    "bytemuck",
    "thiserror",
    "log",
];

/// The dependent's build script: finds the library's GLSL through the `links` metadata and
/// compiles the host's own compute shader, which includes `motion_shadows.glsl`.
const BUILD_RS: &str = r##"use std::path::PathBuf;
// Links shaderc where the distribution's libshaderc.so cannot be linked as it is (Debian 12).
use motion_shadows_shaderc_link as _;

const PROBE: &str = r#"#version 450
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_buffer_reference : require
#include "motion_shadows.glsl"
layout(local_size_x = 64) in;
layout(buffer_reference, std430, buffer_reference_align = 4) writeonly buffer Results {
    float v[];
};
layout(push_constant) uniform Push { uint64_t map; uint64_t results; } pc;
void main() {
    vec3 p = vec3(gl_GlobalInvocationID);
    Results(pc.results).v[gl_GlobalInvocationID.x] =
        ms_visibility(MsShadowMap(pc.map), p, vec3(0.0, 1.0, 0.0), 0.5, MS_NO_TRIANGLE);
}
"#;

fn main() {
    println!("cargo:rerun-if-env-changed=DEP_MOTION_SHADOWS_GLSL_DIR");
    let glsl_dir = PathBuf::from(
        std::env::var("DEP_MOTION_SHADOWS_GLSL_DIR")
            .expect("motion-shadows exports DEP_MOTION_SHADOWS_GLSL_DIR (links metadata)"),
    );
    assert!(glsl_dir.is_absolute(), "{} is not absolute", glsl_dir.display());
    assert_eq!(
        std::env::var("DEP_MOTION_SHADOWS_INCLUDE").ok().map(PathBuf::from),
        Some(glsl_dir.clone()),
        "DEP_MOTION_SHADOWS_INCLUDE names the same directory"
    );
    let header = glsl_dir.join("motion_shadows.glsl");
    assert!(header.is_file(), "no {}", header.display());

    let compiler = shaderc::Compiler::new().expect("shaderc compiler");
    let mut options = shaderc::CompileOptions::new().expect("shaderc options");
    options.set_target_env(shaderc::TargetEnv::Vulkan, shaderc::EnvVersion::Vulkan1_2 as u32);
    options.set_include_callback(move |name, _kind, _from, _depth| {
        let path = glsl_dir.join(name);
        std::fs::read_to_string(&path)
            .map(|content| shaderc::ResolvedInclude {
                resolved_name: path.display().to_string(),
                content,
            })
            .map_err(|e| format!("cannot include {}: {e}", path.display()))
    });
    let spirv = compiler
        .compile_into_spirv(PROBE, shaderc::ShaderKind::Compute, "probe.comp", "main", Some(&options))
        .unwrap_or_else(|e| panic!("the host's shader does not compile: {e}"));
    let out = PathBuf::from(std::env::var("OUT_DIR").unwrap()).join("probe.spv");
    std::fs::write(out, spirv.as_binary_u8()).expect("write probe.spv");
}
"##;

const MAIN_RS: &str = r#"use motion_shadows::gpu::{Context, ContextOptions};
use motion_shadows::technique::shaders;

fn main() {
    // Take the address of a library function so its code (ash, gpu-allocator) is compiled and
    // linked into this program; it is not called, so no Vulkan device is needed.
    let headless: fn(&ContextOptions) -> motion_shadows::Result<Context> = Context::headless;
    std::hint::black_box(headless);

    let spirv = shaders::SCENE_VERT.bytes();
    assert!(spirv.len() >= 20 && spirv.len() % 4 == 0, "SPIR-V of {} bytes", spirv.len());
    assert_eq!(spirv[..4], 0x0723_0203u32.to_le_bytes(), "SPIR-V magic number");
    println!("scene.vert: {} bytes of SPIR-V", spirv.len());

    // The host's own shader, compiled by its build script against the library's include.
    let probe: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/probe.spv"));
    assert!(probe.len() >= 20 && probe.len() % 4 == 0, "SPIR-V of {} bytes", probe.len());
    assert_eq!(probe[..4], 0x0723_0203u32.to_le_bytes(), "SPIR-V magic number");
    println!("host probe.comp: {} bytes of SPIR-V", probe.len());
}
"#;

fn cargo() -> Command {
    let program = std::env::var_os("CARGO").unwrap_or_else(|| env!("CARGO").into());
    let mut command = Command::new(program);
    command
        .current_dir(std::env::temp_dir())
        .env_remove("CARGO_TARGET_DIR")
        .env_remove("CARGO_BUILD_TARGET_DIR")
        .env("CARGO_TERM_COLOR", "never");
    command
}

/// Writes a crate that depends on this one by path (as an engine would) and returns its
/// manifest path.
fn dependent_crate(name: &str) -> PathBuf {
    let library = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::create_dir_all(dir.join("src")).unwrap();
    let manifest = format!(
        r#"[package]
name = "{name}"
version = "0.0.0"
edition = "2024"
publish = false

[dependencies]
motion-shadows = {{ path = {library:?}, default-features = false }}

# The host compiles its own shaders at build time, as an engine does.
[build-dependencies]
shaderc = "0.10.1"
motion-shadows-shaderc-link = {{ path = {shaderc_link:?} }}

[profile.dev]
debug = false

# Its own workspace, not a member of the one this directory lies in.
[workspace]
"#,
        library = library.display().to_string(),
        shaderc_link = library
            .join("build-support/shaderc-link")
            .display()
            .to_string(),
    );
    std::fs::write(dir.join("Cargo.toml"), manifest).unwrap();
    std::fs::write(dir.join("src/main.rs"), MAIN_RS).unwrap();
    std::fs::write(dir.join("build.rs"), BUILD_RS).unwrap();
    // The versions this repository is tested with, and no need for the registry index.
    if let Ok(lock) = std::fs::read(library.join("Cargo.lock")) {
        std::fs::write(dir.join("Cargo.lock"), lock).unwrap();
    }
    dir.join("Cargo.toml")
}

/// Panics if a cargo configuration the dependent would read overrides shaderc's link: the
/// build would then prove nothing about an engine elsewhere.
fn assert_no_shaderc_override(cwd: &Path) {
    let mut configs: Vec<PathBuf> = cwd
        .ancestors()
        .flat_map(|dir| [dir.join(".cargo/config.toml"), dir.join(".cargo/config")])
        .collect();
    let cargo_home = std::env::var_os("CARGO_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|home| PathBuf::from(home).join(".cargo")));
    if let Some(home) = cargo_home {
        configs.extend([home.join("config.toml"), home.join("config")]);
    }
    for config in configs {
        if let Ok(text) = std::fs::read_to_string(&config) {
            assert!(
                !text.contains("shaderc"),
                "{} mentions shaderc; a dependent built with it proves nothing about an engine \
                 elsewhere. Remove that override (the motion-shadows-shaderc-link \
                 build-dependency replaces it).",
                config.display()
            );
        }
    }
}

fn run(command: &mut Command, what: &str) -> Output {
    let output = command
        .output()
        .unwrap_or_else(|e| panic!("{what}: cannot run {command:?}: {e}"));
    assert!(
        output.status.success(),
        "{what} failed ({}): {command:?}\n--- stdout\n{}\n--- stderr\n{}",
        output.status,
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr),
    );
    output
}

/// Crate names of a `cargo tree --prefix none` listing.
fn crate_names(tree: &[u8]) -> Vec<String> {
    String::from_utf8_lossy(tree)
        .lines()
        .filter_map(|line| line.split_whitespace().next())
        .map(str::to_owned)
        .collect()
}

#[test]
fn dependency_tree_is_lean() {
    let manifest = dependent_crate("external-dependent-tree");
    let tree = run(
        cargo()
            .args([
                "tree",
                "-e",
                "normal",
                "--prefix",
                "none",
                "--manifest-path",
            ])
            .arg(&manifest),
        "cargo tree of a crate depending on motion-shadows",
    );
    let names = crate_names(&tree.stdout);
    assert!(
        names.iter().any(|n| n == "motion-shadows"),
        "motion-shadows missing from the dependent's tree:\n{}",
        String::from_utf8_lossy(&tree.stdout)
    );
    let app: Vec<&str> = APP_CRATES
        .iter()
        .copied()
        .filter(|app| names.iter().any(|n| n == app))
        .collect();
    assert!(
        app.is_empty(),
        "an engine depending on motion-shadows would compile the app's crates {app:?}; they \
         belong in app/ (cargo tree -e normal -i <crate> shows the path). Tree:\n{}",
        String::from_utf8_lossy(&tree.stdout)
    );

    let direct = run(
        cargo()
            .args(["tree", "-e", "normal", "--prefix", "none", "--depth", "1"])
            .args(["-p", "motion-shadows", "--manifest-path"])
            .arg(&manifest),
        "cargo tree of motion-shadows' direct dependencies",
    );
    let names = crate_names(&direct.stdout);
    assert_eq!(names.first().map(String::as_str), Some("motion-shadows"));
    let extra: Vec<&String> = names[1..]
        .iter()
        .filter(|n| !LIBRARY_DEPENDENCIES.contains(&n.as_str()))
        .collect();
    assert!(
        extra.is_empty(),
        "motion-shadows has normal dependencies {extra:?} beyond {LIBRARY_DEPENDENCIES:?}; \
         every one reaches every engine that uses the library. Direct dependencies:\n{}",
        String::from_utf8_lossy(&direct.stdout)
    );
}

#[test]
fn dependent_builds_and_links() {
    let name = "external-dependent-build";
    let manifest = dependent_crate(name);
    assert_no_shaderc_override(&std::env::temp_dir());
    let target_dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("external-dependent-target");
    run(
        cargo()
            .args(["build", "--manifest-path"])
            .arg(&manifest)
            .arg("--target-dir")
            .arg(&target_dir),
        "building a crate that depends on motion-shadows (outside this repository's cargo \
         configuration)",
    );
    let program = target_dir
        .join("debug")
        .join(format!("{name}{}", std::env::consts::EXE_SUFFIX));
    let output = run(
        &mut Command::new(&program),
        "running the dependent's program",
    );
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        stdout.contains("scene.vert: ") && stdout.contains("host probe.comp: "),
        "unexpected output: {stdout}"
    );
}
