//! Issue 35, item 4: `--lookup exact` on the forward (stochastic) frame: `render` names the
//! method `temporal-exact` (its files too) and says `lookup` in its JSON, `animate` too;
//! `compare --truth raytrace` adds `temporal-exact` beside the depth-line temporal, and it
//! is the closer to the ray tracer. Where the exact lookup does not apply (other methods,
//! the papers' prisms, the coverage map, a shadow filter, the static layer's and the sort's
//! options) it is refused by name before anything is rendered.

use super::{listing, run, s, temp_dir};

const SMALL: [&str; 10] = [
    "--width",
    "48",
    "--height",
    "32",
    "--spp",
    "2",
    "--shadow-size",
    "64x64",
    "--scene",
    "walker-toward-light",
];

#[test]
fn the_exact_lookup_reaches_the_forward_render_animate_and_compare() {
    let dir = temp_dir("forward-lookup");
    let render = run(&[
        &["render", "--lookup", "exact", "--json"][..],
        &["--out", s(&dir.join("render"))],
        &SMALL[..],
    ]
    .concat())
    .json();
    assert_eq!(render["lookup"], "exact");
    assert_eq!(render["method"], "temporal-exact");
    let files = render["files"].as_array().expect("files");
    assert!(
        files
            .iter()
            .all(|f| f.as_str().is_some_and(|f| f.contains("-temporal-exact."))),
        "{files:?}"
    );
    let depth = run(&[
        &["render", "--json"][..],
        &["--out", s(&dir.join("depth"))],
        &SMALL[..],
    ]
    .concat())
    .json();
    assert_eq!(depth["lookup"], "depth");
    assert_eq!(depth["method"], "temporal");

    let animate = run(&[
        &["animate", "--frames", "1", "--lookup", "exact", "--json"][..],
        &["--out", s(&dir.join("animate"))],
        &SMALL[..],
    ]
    .concat())
    .json();
    assert_eq!(animate["method"], "temporal-exact");
    assert_eq!(animate["lookup"], "exact");

    let compare = run(&[
        &[
            "compare", "--lookup", "exact", "--truth", "raytrace", "--slices", "4", "--json",
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
            .unwrap_or_else(|| panic!("{name} in {methods:?}"))["errors"]["rmse"]
            .as_f64()
            .expect("rmse")
    };
    let (exact, depth) = (rmse("temporal-exact"), rmse("temporal"));
    println!(
        "walker at 48x32, 2 spp, 64x64 map, against the ray tracer: exact {exact}, depth line {depth}"
    );
    assert!(
        exact < 0.002 && exact < depth,
        "exact {exact}, depth line {depth}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// Refused with every needle in the message, nothing written.
fn assert_refused(args: &[&str], needles: &[&str]) {
    let dir = temp_dir("forward-lookup-refused");
    let out = dir.join("out");
    let args = [args, &["--width", "32", "--height", "24", "--out", s(&out)]].concat();
    let message = run(&args).refused(needles);
    println!("{args:?}: {message}");
    assert!(
        listing(&out).is_empty(),
        "{args:?} wrote {:?}",
        listing(&out)
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_forward_frame_refuses_the_exact_lookup_where_it_does_not_apply() {
    for method in ["tsm", "plain", "reference", "raytrace", "coverage"] {
        for lookup in ["exact", "depth"] {
            assert_refused(
                &["render", "--method", method, "--lookup", lookup],
                &["--lookup", "does not apply to"],
            );
        }
    }
    for command in ["render", "compare"] {
        assert_refused(
            &[command, "--lookup", "exact", "--prisms", "paper"],
            &["--lookup exact", "--prisms exact"],
        );
        for filter in ["bilinear", "footprint"] {
            assert_refused(
                &[command, "--lookup", "exact", "--shadow-filter", filter],
                &["--lookup exact", "--shadow-filter"],
            );
        }
    }
    // (--static-layer applies: the exact map keeps its still triangles in static name lists.)
    for (flag, value) in [("--range-storage", "lists"), ("--pruning", "cover")] {
        for command in [&["render"][..], &["animate", "--frames", "1"][..]] {
            assert_refused(
                &[command, &["--lookup", "exact", flag, value][..]].concat(),
                &[flag, "--lookup exact"],
            );
        }
    }
}
