//! A shadow map that receives no fragment at all is reported.

use super::*;

// ---------------------------------------------------------------------------------------
// Silent emptiness: a shadow map that receives no fragment at all is reported.

#[test]
fn a_shadow_map_that_receives_nothing_is_warned_about() {
    let dir = temp_dir("empty-map");
    // The spot light looks down from y = 10, but its depth range ends at 5: every triangle
    // lies beyond its far plane, which clips the papers' prisms (the exact ones are not
    // clipped by the near and far planes, so they would shadow it).
    let json = scene_json("beyond-far", 0.1, "[0, 10, 0]", &[floor(4.0)])
        .replace(r#""near": 0.05, "far": 50"#, r#""near": 0.05, "far": 5"#);
    let scene = write_scene(&dir, "beyond.json", &json);
    let out = dir.join("out");
    let run = render_file(&scene, &out, &["--json", "--prisms", "paper"]);
    assert!(run.succeeded(), "stderr: {}", run.stderr());
    let json: serde_json::Value = serde_json::from_slice(&run.output.stdout).unwrap();
    assert_eq!(json["fragments"], 0);
    let warnings = json["warnings"].as_array().expect("a warnings array");
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(
        warnings[0]
            .as_str()
            .unwrap()
            .contains("no triangle reaches the shadow map")
    );
    assert!(
        run.stderr().contains("warning: no triangle reaches"),
        "{}",
        run.stderr()
    );

    // The exact prisms are not clipped by the far plane: the same scene has fragments in
    // the lists (static layer off), or the floor in the static layer (on, the default: no
    // fragment, and no warning either, since the layer is read when the lists are empty).
    let run = render_file(&scene, &out, &["--json", "--static-layer", "off"]);
    assert!(run.succeeded(), "stderr: {}", run.stderr());
    let json: serde_json::Value = serde_json::from_slice(&run.output.stdout).unwrap();
    assert!(json["fragments"].as_u64().unwrap() > 0, "{json}");
    assert_eq!(json["warnings"].as_array().map(Vec::len), Some(0), "{json}");
    let run = render_file(&scene, &out, &["--json"]);
    assert!(run.succeeded(), "stderr: {}", run.stderr());
    let json: serde_json::Value = serde_json::from_slice(&run.output.stdout).unwrap();
    assert_eq!(json["fragments"], 0, "{json}");
    assert_eq!(json["warnings"].as_array().map(Vec::len), Some(0), "{json}");

    // Within the depth range: fragments, no warning.
    let json = scene_json("within-far", 0.1, "[0, 10, 0]", &[floor(4.0)]);
    let scene = write_scene(&dir, "within.json", &json);
    let run = render_file(&scene, &out, &["--json", "--static-layer", "off"]);
    assert!(run.succeeded(), "stderr: {}", run.stderr());
    let json: serde_json::Value = serde_json::from_slice(&run.output.stdout).unwrap();
    assert!(json["fragments"].as_u64().unwrap() > 0);
    assert_eq!(json["warnings"].as_array().map(Vec::len), Some(0));

    // Outside the light's cone, static: an empty static layer and empty lists are warned
    // about.
    let json = scene_json("outside-cone", 0.1, "[100, 10, 0]", &[floor(4.0)]);
    let scene = write_scene(&dir, "outside.json", &json);
    let run = render_file(&scene, &out, &["--json"]);
    assert!(run.succeeded(), "stderr: {}", run.stderr());
    let json: serde_json::Value = serde_json::from_slice(&run.output.stdout).unwrap();
    assert_eq!(json["fragments"], 0, "{json}");
    let warnings = json["warnings"].as_array().expect("a warnings array");
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    std::fs::remove_dir_all(&dir).ok();
}
