//! Item 3: `compare --frame deferred --preset fig10` rendered cubes-toward-light.

use super::{run, s, temp_dir};

/// The preset's scene (args.rs: Fig. 10 is walker-toward-light); an explicit `--scene` still
/// overrides it.
#[test]
fn compare_deferred_takes_the_preset_scene() {
    let dir = temp_dir("preset");
    let small = ["--width", "32", "--height", "24", "--shadow-size", "64x64"];
    let compare = |extra: &[&str]| {
        run(&[
            &["compare", "--frame", "deferred", "--json", "--out", s(&dir)][..],
            &small[..],
            extra,
        ]
        .concat())
        .json()
    };
    assert_eq!(
        compare(&["--preset", "fig10"])["scene"],
        "walker-toward-light"
    );
    assert_eq!(
        compare(&["--preset", "fig10", "--scene", "leg-toward-light"])["scene"],
        "leg-toward-light"
    );
    std::fs::remove_dir_all(&dir).ok();
}
