//! Item 5: `render --frame deferred --method raytrace --static-receivers` said
//! `"moving_receivers": false` and rendered the moving truth, byte for byte.
//!
//! The scene: a floor sliding 2 units along +x over the shutter (where the G-buffer shows it
//! at shutter close) under a still 1 x 1 square at height 2, light straight down. A floor
//! point standing still is under the square all shutter or never: lit share 0 or 1 exactly,
//! and 0 somewhere. A floor point moving with the floor crossed the square's shadow (1 unit
//! wide) during at most half of its 2-unit path: lit share at least 1/2 everywhere, and
//! below 1 somewhere.

use super::{run, s, scene_json, square, temp_dir};

fn mask(path: &str) -> Vec<u8> {
    image::open(path)
        .expect("the mask PNG")
        .to_luma8()
        .into_raw()
}

#[test]
fn the_truth_with_static_receivers_holds_each_point_still() {
    let dir = temp_dir("receivers");
    let scene = dir.join("slide.json");
    let slide = r#", "t0": { "translation": [-2, 0, 0] }, "t1": { "translation": [0, 0, 0] }"#;
    std::fs::write(
        &scene,
        scene_json(
            "slide",
            &[
                square("floor", 12.0, 0.0, slide),
                square("blocker", 1.0, 2.0, ""),
            ],
        ),
    )
    .unwrap();
    let render = |extra: &[&str], out: &str| {
        let json = run(&[
            &[
                "render",
                "--frame",
                "deferred",
                "--method",
                "raytrace",
                "--scene-file",
                s(&scene),
                "--width",
                "64",
                "--height",
                "48",
                "--json",
                "--out",
                out,
            ][..],
            extra,
        ]
        .concat())
        .json();
        let file = json["files"]
            .as_array()
            .unwrap()
            .iter()
            .map(|f| f.as_str().unwrap().to_owned())
            .find(|f| f.ends_with("-mask.png"))
            .expect("the mask");
        (json["moving_receivers"].clone(), mask(&file))
    };
    let (moving_flag, moving) = render(&[], s(&dir.join("moving")));
    let (still_flag, still) = render(&["--static-receivers"], s(&dir.join("still")));
    assert_eq!(moving_flag, true);
    assert_eq!(still_flag, false);
    // 1/2 is 127.5 in the 8-bit mask.
    assert!(moving.iter().all(|&v| v >= 127), "a moving point below 1/2");
    assert!(
        moving.iter().any(|&v| v < 250),
        "no moving point crossed the shadow"
    );
    assert!(
        still.iter().all(|&v| v == 0 || v == 255),
        "a still point partly lit: {:?}",
        still.iter().find(|&&v| v != 0 && v != 255)
    );
    let shadowed = still.iter().filter(|&&v| v == 0).count();
    assert!(shadowed > 20, "{shadowed} still points in shadow");
    std::fs::remove_dir_all(&dir).ok();
}
