//! Closed meshes: a light inside one lights nothing, and the mesh is named.

use super::*;

// ---------------------------------------------------------------------------------------
// Closed meshes: back-face culling is only right from outside.

#[test]
fn a_light_inside_a_closed_box_lights_nothing_and_the_box_is_named() {
    let dir = temp_dir("lamp");
    // The spot light sits in the middle of a closed box: no light gets out.
    let lamp = r#"{ "name": "lamp-housing", "albedo": [0.5, 0.5, 0.5], "closed": true,
        "mesh": { "box": { "size": [0.5, 0.5, 0.5] } }, "t0": { "translation": [0, 3, 0] } }"#;
    let plane = r#"{ "name": "ground", "albedo": [0.8, 0.8, 0.8],
        "mesh": { "plane": { "size": [10, 10], "subdivisions": 4 } } }"#;
    let scene = write_scene(
        &dir,
        "lamp.json",
        &scene_json("lamp", 0.1, "[0, 3, 0]", &[plane.into(), lamp.into()]),
    );
    let r = render_file(&scene, &dir, &[]);
    assert!(r.succeeded(), "{}", r.stderr());
    assert!(
        r.stderr()
            .contains("mesh #1 (\"lamp-housing\") is closed but contains the spot light"),
        "{}",
        r.stderr()
    );
    let (mean, max) = radiance_stats(&dir.join("lamp-temporal.exr"));
    // Lit, the floor under the light would be 0.8/pi * 50 / 9 = 1.4; enclosed, it is black
    // (a stray sample through the box's edges would still keep the mean near 0).
    assert!(
        mean < 1e-3,
        "light leaks out of the closed box: mean {mean}, max {max}"
    );

    // The camera inside a closed box: the box is drawn without culling too.
    let room = r#"{ "name": "room", "albedo": [0.5, 0.5, 0.5], "closed": true,
        "mesh": { "box": { "size": [1, 1, 1] } }, "t0": { "translation": [0, 4, 6] } }"#;
    let scene = write_scene(
        &dir,
        "room.json",
        &scene_json("room", 0.1, "[0, 3, 0]", &[plane.into(), room.into()]),
    );
    let r = render_file(&scene, &dir, &[]);
    assert!(r.succeeded(), "{}", r.stderr());
    assert!(
        r.stderr()
            .contains("mesh #1 (\"room\") is closed but contains the camera"),
        "{}",
        r.stderr()
    );
    // From inside the box the camera sees only its walls: no floor anywhere.
    let (mean, _) = radiance_stats(&dir.join("room-temporal.exr"));
    let (floor_mean, _) = {
        let scene = write_scene(
            &dir,
            "bare.json",
            &scene_json("bare", 0.1, "[0, 3, 0]", &[plane.into()]),
        );
        assert!(render_file(&scene, &dir, &[]).succeeded());
        radiance_stats(&dir.join("bare-temporal.exr"))
    };
    assert!(
        mean < 0.5 * floor_mean,
        "the camera sees through the closed box: mean {mean} vs floor alone {floor_mean}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
