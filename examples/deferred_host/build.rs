//! Passes the library's GLSL directory (its `links` metadata, `DEP_MOTION_SHADOWS_GLSL_DIR`)
//! to the engine's code, which includes one of the library's internal shader files for a
//! test probe: found the way a host's build finds the library's GLSL, not by a relative path.

fn main() {
    let dir = std::env::var("DEP_MOTION_SHADOWS_GLSL_DIR")
        .expect("motion-shadows exports its GLSL directory to direct dependents");
    let file = std::path::Path::new(&dir).join("temporal_samples.glsl");
    println!("cargo:rustc-env=TEMPORAL_SAMPLES_GLSL={}", file.display());
    println!("cargo:rerun-if-env-changed=DEP_MOTION_SHADOWS_GLSL_DIR");
}
