//! The command line as users script it: `--json` output, scene export and re-import.

use std::path::Path;
use std::process::Command;

fn motion_shadows(args: &[&str], out: &Path) -> std::process::Output {
    let output = Command::new(env!("CARGO_BIN_EXE_motion-shadows"))
        .args(args)
        .arg("--out")
        .arg(out)
        .env("MOTION_SHADOWS_VALIDATION", "1")
        .output()
        .expect("run the binary");
    assert!(
        output.status.success(),
        "{args:?} failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

fn temp_dir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("motion-shadows-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn render_json_reports_the_frame_and_writes_the_files() {
    let dir = temp_dir("json");
    let out = motion_shadows(
        &[
            "render", "--width", "64", "--height", "48", "--spp", "2", "--json",
        ],
        &dir,
    );
    let json: serde_json::Value =
        serde_json::from_slice(&out.stdout).expect("stdout is one JSON object");
    assert_eq!(json["scene"], "cubes-toward-light");
    assert_eq!(json["method"], "temporal");
    assert_eq!(json["width"], 64);
    let (nf, nr) = (
        json["fragments"].as_u64().unwrap(),
        json["ranges"].as_u64().unwrap(),
    );
    assert!(nf > 0 && nr > 0 && nr <= nf, "N_f {nf}, N_r {nr}");
    // Equation (2), by hand: 16 bytes per fragment, 24 per range, two 4-byte heads per pixel.
    assert_eq!(
        json["shadow_map_bytes_eq2"].as_u64().unwrap(),
        nf * 16 + nr * 24 + 2 * 64 * 48 * 4
    );
    let passes: Vec<&str> = json["passes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["pass"].as_str().unwrap())
        .collect();
    assert_eq!(
        passes,
        [
            "collection",
            "generation",
            "lighting raster",
            "lighting shade"
        ]
    );
    for file in json["files"].as_array().unwrap() {
        assert!(Path::new(file.as_str().unwrap()).is_file(), "{file}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// A built-in scene exported as a file renders to the same bytes as the built-in.
#[test]
fn exported_scene_file_renders_like_the_builtin() {
    let dir = temp_dir("export");
    let scene_file = dir.join("scene.json");
    let status = Command::new(env!("CARGO_BIN_EXE_motion-shadows"))
        .args(["scene", "export", "cubes-toward-light", "--out"])
        .arg(&scene_file)
        .status()
        .unwrap();
    assert!(status.success());
    let small = ["--width", "48", "--height", "36", "--spp", "2"];
    let a = dir.join("builtin");
    let b = dir.join("file");
    motion_shadows(&[&["render"][..], &small].concat(), &a);
    let file_arg = scene_file.to_str().unwrap();
    motion_shadows(
        &[&["render", "--scene-file", file_arg][..], &small].concat(),
        &b,
    );
    let exr = |d: &Path| std::fs::read(d.join("cubes-toward-light-temporal.exr")).unwrap();
    assert!(exr(&a) == exr(&b), "the exported scene renders differently");
    std::fs::remove_dir_all(&dir).ok();
}
