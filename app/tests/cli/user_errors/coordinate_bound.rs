//! Large coordinates: rendered right up to the documented bound, refused beyond it.

use super::*;

// ---------------------------------------------------------------------------------------
// Large coordinates: rendered right up to the documented bound, refused beyond it.

#[test]
fn coordinates_just_inside_the_bound_render_lit_and_beyond_are_refused() {
    let dir = temp_dir("coordinates");
    // Camera near 0.1, bound 1e5 x near = 1e4.
    let inside = write_scene(
        &dir,
        "inside.json",
        &scene_json("inside", 0.1, "[0, 5, 0]", &[floor(0.99e4)]),
    );
    let r = render_file(&inside, &dir, &[]);
    assert!(r.succeeded(), "{}", r.stderr());
    let image = read_exr(&dir.join("inside-temporal.exr")).unwrap();
    // The camera looks at the origin, right below the light: the four centre pixels see the
    // floor there, lit at albedo/pi * I * cos / d^2 = 0.8/pi * 50 / 25.
    let expected = 0.8 / std::f32::consts::PI * 50.0 / 25.0;
    for (x, y) in [(23, 17), (24, 17), (23, 18), (24, 18)] {
        let [r, g, b] = image.pixel(x, y);
        for c in [r, g, b] {
            assert!(
                (c - expected).abs() < 0.03 * expected,
                "pixel ({x}, {y}) = {c}, expected {expected}"
            );
        }
    }
    let (mean, _) = radiance_stats(&dir.join("inside-temporal.exr"));
    assert!(mean > 0.05, "mostly black: mean {mean}");

    let beyond = write_scene(
        &dir,
        "beyond.json",
        &scene_json("beyond", 0.1, "[0, 5, 0]", &[floor(1.01e4)]),
    );
    render_file(&beyond, &dir, &[]).refused(&["mesh #0 (\"floor\")", "1e5 x near", "1e4"]);
    assert!(!dir.join("beyond-temporal.exr").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}
