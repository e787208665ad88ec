//! Issue 35: `--lookup exact` reaches the deferred frame through the binary: `render` (and
//! `animate`, which takes its options) names the method `temporal-exact` (its files too) and
//! `render` says `lookup` in its JSON; `compare` adds the exact mask
//! beside the depth-line one, and it is the closer to the truth.

use super::{run, s, temp_dir};

const SMALL: [&str; 8] = [
    "--width",
    "48",
    "--height",
    "32",
    "--shadow-size",
    "64x64",
    "--scene",
    "walker-toward-light",
];

#[test]
fn the_exact_lookup_reaches_render_and_compare() {
    let dir = temp_dir("lookup");
    let render = run(&[
        &[
            "render", "--frame", "deferred", "--lookup", "exact", "--json",
        ][..],
        &["--out", s(&dir.join("render"))],
        &SMALL[..],
    ]
    .concat())
    .json();
    assert_eq!(render["lookup"], "exact");
    assert_eq!(render["method"], "temporal-exact");
    let files = render["files"].as_array().expect("files");
    assert!(
        files.iter().all(|f| f
            .as_str()
            .is_some_and(|f| f.contains("-deferred-temporal-exact"))),
        "{files:?}"
    );

    let animate = run(&[
        &[
            "animate", "--frames", "1", "--frame", "deferred", "--lookup", "exact", "--json",
        ][..],
        &["--out", s(&dir.join("animate"))],
        &SMALL[..],
    ]
    .concat())
    .json();
    assert_eq!(animate["method"], "temporal-exact");

    let compare = run(&[
        &[
            "compare", "--frame", "deferred", "--lookup", "exact", "--json",
        ][..],
        &["--out", s(&dir.join("compare"))],
        &SMALL[..],
    ]
    .concat())
    .json();
    assert_eq!(compare["lookup"], "exact");
    let methods = compare["methods"].as_array().expect("methods");
    let rmse = |name: &str| {
        methods
            .iter()
            .find(|m| m["method"] == name)
            .unwrap_or_else(|| panic!("{name} in {methods:?}"))["rmse"]
            .as_f64()
            .expect("rmse")
    };
    let (exact, depth) = (rmse("temporal-exact"), rmse("temporal"));
    println!("walker at 48x32, 64x64 map: exact {exact}, depth line {depth}");
    assert!(
        exact < 0.005 && exact < depth,
        "exact {exact}, depth line {depth}"
    );
    // The G-buffer's ids and the truth's hits name the same triangles (one id convention):
    // nearly every pixel sees the same one, and the error there is no larger.
    for m in methods {
        let (all, same) = (m["pixels"].as_u64(), m["pixels_same_surface"].as_u64());
        let (all, same) = (all.expect("pixels"), same.expect("pixels_same_surface"));
        assert!(same <= all && same * 10 >= all * 9, "{m}");
        let e = m["rmse_same_surface"].as_f64().expect("rmse_same_surface");
        assert!(e <= m["rmse"].as_f64().expect("rmse") * 1.5 + 1e-6, "{m}");
    }
    std::fs::remove_dir_all(&dir).ok();
}
