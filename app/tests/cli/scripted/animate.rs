//! `animate`: the frames, the GIF, the `--json` summary and what it refuses.

use super::*;

/// `animate`: one PNG per frame and a GIF with as many frames of the same size, the walker
/// moving between them, and the `--json` summary's counts and times.
#[test]
fn animate_writes_each_frame_and_a_gif_of_them() {
    use image::AnimationDecoder as _;
    let dir = temp_dir("animate");
    let out = motion_shadows(
        &[
            "animate", "--frames", "3", "--width", "64", "--height", "48", "--spp", "1", "--json",
        ],
        &dir,
    );
    let json: serde_json::Value =
        serde_json::from_slice(&out.stdout).expect("stdout is one JSON object");
    assert_eq!(json["scene"], "walker-toward-light");
    assert_eq!(json["frames"], 3);
    // Frame i's shutter opens i / 24 s after frame 0's (f32 printed in shortest form).
    let offsets: Vec<f32> = json["frame_offsets_s"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap() as f32)
        .collect();
    assert_eq!(offsets, [0.0, 1.0 / 24.0, 2.0 / 24.0]);
    let gpu_ms = json["frame_gpu_ms"].as_array().unwrap();
    assert_eq!(gpu_ms.len(), 3);
    assert!(gpu_ms.iter().all(|ms| ms.as_f64().unwrap() > 0.0));
    let names: Vec<String> = (0..3)
        .map(|i| format!("walker-toward-light-frame-000{i}.png"))
        .chain(["walker-toward-light.gif".to_owned()])
        .collect();
    let files: Vec<String> = names
        .iter()
        .map(|n| dir.join(n).display().to_string())
        .collect();
    assert_eq!(json["files"], serde_json::json!(files));
    assert_eq!(json["gif"], serde_json::json!(files[3]));

    let pngs: Vec<image::RgbImage> = files[..3]
        .iter()
        .map(|f| image::open(f).unwrap().to_rgb8())
        .collect();
    for png in &pngs {
        assert_eq!(png.dimensions(), (64, 48));
    }
    // The walker moves between consecutive frames (everything else is static).
    assert_ne!(pngs[0], pngs[1]);
    assert_ne!(pngs[1], pngs[2]);
    let gif = std::io::BufReader::new(std::fs::File::open(&files[3]).unwrap());
    let frames = image::codecs::gif::GifDecoder::new(gif)
        .unwrap()
        .into_frames()
        .collect_frames()
        .unwrap();
    assert_eq!(frames.len(), 3);
    for f in &frames {
        assert_eq!(f.buffer().dimensions(), (64, 48));
    }
    assert_ne!(frames[0].buffer(), frames[1].buffer());
    std::fs::remove_dir_all(&dir).ok();
}

/// `animate` refuses, before rendering or writing anything, a scene in which nothing is
/// animated, frame counts and rates out of range, and heat maps.
#[test]
fn animate_refuses_bad_requests_before_rendering() {
    let dir = temp_dir("animate-errors");
    let out = dir.join("out");
    for (args, needle) in [
        (&["--scene", "leg-toward-light"][..], "has no animation"),
        (&["--frames", "0"][..], "--frames"),
        (&["--frames", "601"][..], "--frames"),
        (&["--fps", "0"][..], "--fps"),
        (&["--fps", "NaN"][..], "--fps"),
        (&["--start", "inf"][..], "--start"),
        (&["--heatmaps"][..], "--heatmaps"),
        (&["--runs", "2"][..], "--runs"),
    ] {
        let output = Command::new(env!("CARGO_BIN_EXE_motion-shadows"))
            .arg("animate")
            .args(args)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success(), "{args:?}");
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
        assert!(!out.exists(), "{args:?} created the output directory");
    }
    // A frame's path is a directory: refused before rendering, the old GIF kept, and no
    // temporary file left.
    std::fs::create_dir_all(out.join("walker-toward-light-frame-0001.png")).unwrap();
    std::fs::write(out.join("walker-toward-light.gif"), "old").unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_motion-shadows"))
        .args([
            "animate", "--frames", "2", "--width", "16", "--height", "16",
        ])
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(stderr.contains("is a directory"), "{stderr}");
    assert!(
        !stderr.contains("lighting pass"),
        "rendered first: {stderr}"
    );
    let gif = std::fs::read_to_string(out.join("walker-toward-light.gif")).unwrap();
    assert_eq!(gif, "old");
    assert_eq!(std::fs::read_dir(&out).unwrap().count(), 2);
    std::fs::remove_dir_all(&dir).ok();
}

/// `animate --frame deferred` renders the engine's frame: frame 0 (the scene's own time) is
/// the PNG `render --frame deferred` writes for the same scene and settings, byte for byte,
/// and the summary names the frame and the deferred method. (Before, animate ignored
/// `--frame` and rendered the forward frame.)
#[test]
fn animate_renders_the_deferred_frame() {
    let out = temp_dir("animate-deferred");
    let common = [
        "--scene",
        "game-level",
        "--frame",
        "deferred",
        "--method",
        "tsm",
        "--tsm-maps",
        "4",
        "--width",
        "160",
        "--height",
        "90",
        "--shadow-size",
        "256x256",
        "--exposure",
        "0",
        "--json",
    ];
    let animate = motion_shadows(
        &[&["animate", "--frames", "2"], &common[..]].concat(),
        &out.join("animate"),
    );
    let summary: serde_json::Value = serde_json::from_slice(&animate.stdout).unwrap();
    assert_eq!(summary["frame"], "deferred");
    assert_eq!(summary["method"], "tsm-4");
    let render = motion_shadows(&[&["render"], &common[..]].concat(), &out.join("render"));
    let rendered: serde_json::Value = serde_json::from_slice(&render.stdout).unwrap();
    let png = |v: &serde_json::Value| {
        v["files"]
            .as_array()
            .unwrap()
            .iter()
            .map(|f| f.as_str().unwrap().to_owned())
            .find(|f| f.ends_with(".png") && !f.ends_with("-mask.png"))
            .unwrap()
    };
    let first = std::fs::read(png(&summary)).unwrap();
    assert_eq!(first, std::fs::read(png(&rendered)).unwrap());
    let second = std::fs::read(summary["files"][1].as_str().unwrap()).unwrap();
    assert_ne!(first, second, "game-level moves between frames");
    std::fs::remove_dir_all(&out).ok();
}
