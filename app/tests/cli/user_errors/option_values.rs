//! Values that would make nonsense, refused up front with messages naming them.

use super::*;

// ---------------------------------------------------------------------------------------
// Values accepted that made nonsense: refused up front with messages naming the value.

#[test]
fn nonsense_values_are_refused_with_clear_messages() {
    let out = temp_dir("values");
    for exposure in ["NaN", "inf", "-inf", "1e39", "65"] {
        let r = run(&["render", "--exposure", exposure, "--out", s(&out)]);
        r.refused(&["--exposure", "finite number of stops in [-64, 64]"]);
    }
    let r = run(&[
        "render",
        "--scene",
        "random-cubes",
        "--speed-min",
        "1e30",
        "--speed-max",
        "1e30",
        "--out",
        s(&out),
    ]);
    assert!(!r.stderr().contains("parallel"), "{}", r.stderr());
    r.refused(&["speed_max <= 1000"]);
    let r = run(&[
        "render",
        "--scene",
        "random-cubes",
        "--cube-size",
        "1e20",
        "--out",
        s(&out),
    ]);
    assert!(!r.stderr().contains("parallel"), "{}", r.stderr());
    r.refused(&["cube size must be in [0.1, 1000]"]);

    let inside_out = r#"{ "name": "inside-out", "albedo": [0.5, 0.5, 0.5], "closed": true,
        "mesh": { "box": { "size": [1, -1, 1] } } }"#;
    let scene = write_scene(
        &out,
        "neg.json",
        &scene_json("neg", 0.1, "[0, 5, 0]", &[floor(4.0), inside_out.into()]),
    );
    render_file(&scene, &out, &[]).refused(&["\"inside-out\"", "box size", "> 0"]);
    assert_eq!(
        std::fs::read_dir(&out).unwrap().count(),
        1,
        "only the scene file"
    );
    std::fs::remove_dir_all(&out).unwrap();
}
