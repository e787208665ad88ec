//! Item 10: a range buffer past the device's limit was reported with its count saturated to
//! u32::MAX ("4294967295 elements"), not the count the scene needs.

use super::{run, s, scene_json, square, temp_dir};

/// Squares stacked over the floor, each covering the whole light view while it slides.
const LAYERS: u64 = 20;
const MAP_SIDE: u64 = 16384;

#[test]
fn a_range_buffer_past_the_device_limit_is_reported_with_the_real_count() {
    let dir = temp_dir("device-limit");
    let slide = r#", "t1": { "translation": [0.1, 0, 0] }"#;
    let mut objects = vec![square("floor", 20.0, 0.0, "")];
    for i in 0..LAYERS {
        objects.push(square(
            &format!("layer{i}"),
            20.0,
            1.0 + 0.2 * i as f32,
            slide,
        ));
    }
    let scene = dir.join("stack.json");
    std::fs::write(&scene, scene_json("stack", &objects)).unwrap();
    let size = format!("{MAP_SIDE}x{MAP_SIDE}");
    let r = run(&[
        "render",
        "--scene-file",
        s(&scene),
        "--width",
        "16",
        "--height",
        "16",
        "--spp",
        "1",
        "--shadow-size",
        &size,
        "--out",
        s(&dir.join("out")),
    ]);
    let message = r.refused(&["the range buffer needs"]);
    assert!(
        !message.contains("4294967295"),
        "a saturated count: {message}"
    );
    // "... needs B bytes (N elements of 24 bytes) ..."
    let figures = |after: &str| -> u64 {
        let rest = &message[message.find(after).unwrap() + after.len()..];
        rest.split(' ').next().unwrap().parse().unwrap()
    };
    let bytes = figures("the range buffer needs ");
    let count = figures("bytes (");
    // Every layer covers every texel of the map at least once during the shutter.
    assert!(count >= LAYERS * MAP_SIDE * MAP_SIDE, "{count}: {message}");
    assert_eq!(bytes, count * 24, "{message}");
    std::fs::remove_dir_all(&dir).ok();
}
