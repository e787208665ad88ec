//! Item 4: options a frame does not read were accepted and dropped (`render --frame deferred
//! --heatmaps` wrote no heat map; `--spp`, `--seed`, `--shadow-filter`... changed nothing).
//! Now every option in the tables of `cli::unread_options` is refused by name by each frame
//! and method that does not read it, before anything is loaded or rendered.

use super::{listing, run, s, temp_dir};
use motion_shadows_app::cli::args::MethodArg;
use motion_shadows_app::cli::unread_options::{COMPARE_OPTIONS, RENDER_OPTIONS, UnreadOption};

/// The option as a user would give it, with a value where it takes one (not its default, as
/// a user who means it would).
fn given(flag: &str) -> Vec<&str> {
    let value = match flag {
        "--spp" => Some("4"),
        "--seed" => Some("7"),
        "--slices" => Some("16"),
        "--shadow-estimator" => Some("analytic"),
        "--shadow-filter" => Some("bilinear"),
        "--prisms" => Some("paper"),
        "--range-storage" => Some("lists"),
        "--pruning" => Some("cover"),
        "--static-layer" => Some("off"),
        "--receiver" => Some("offset"),
        "--truth" => Some("raytrace"),
        "--camera-time" => Some("0.5"),
        "--tsm-maps" => Some("4"),
        "--lookup" => Some("exact"),
        "--heatmaps" | "--receiver-plane" | "--static-receivers" => None,
        other => panic!("{other}: add an example value for the new table row"),
    };
    std::iter::once(flag).chain(value).collect()
}

const METHODS: [(MethodArg, &str); 4] = [
    (MethodArg::Temporal, "temporal"),
    (MethodArg::Tsm, "tsm"),
    (MethodArg::Plain, "plain"),
    (MethodArg::Raytrace, "raytrace"),
];

/// Refused naming `option.flag`, with nothing written (a small image, so that a run that
/// wrongly goes ahead fails fast on the assertion instead of rendering for long).
fn assert_refused(command: &[&str], option: &UnreadOption) {
    let dir = temp_dir("unread");
    let out = dir.join("out");
    let args = [
        command,
        &given(option.flag)[..],
        &["--width", "32", "--height", "24", "--out", s(&out)],
    ]
    .concat();
    let message = run(&args).refused(&[option.flag, "does not apply to"]);
    assert!(message.contains(option.why), "{args:?}: {message}");
    assert!(
        listing(&out).is_empty(),
        "{args:?} wrote {:?}",
        listing(&out)
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn render_refuses_each_option_the_frame_and_method_do_not_read() {
    let mut refused = 0;
    for option in RENDER_OPTIONS {
        if !option.readers.forward {
            assert_refused(&["render"], option);
            refused += 1;
        }
        for (method, name) in METHODS {
            if !option.readers.deferred.contains(&method) {
                assert_refused(&["render", "--frame", "deferred", "--method", name], option);
                refused += 1;
            }
        }
    }
    assert!(refused >= 20, "only {refused} refusals walked");
}

#[test]
fn compare_refuses_each_option_the_frame_does_not_read() {
    let mut refused = 0;
    for option in COMPARE_OPTIONS {
        if !option.readers.forward {
            assert_refused(&["compare"], option);
            refused += 1;
        }
        if option.readers.deferred.is_empty() {
            assert_refused(&["compare", "--frame", "deferred"], option);
            refused += 1;
        }
    }
    assert!(refused >= 6, "only {refused} refusals walked");
}

/// `animate` takes `render`'s options, and refuses them as `render` does.
#[test]
fn animate_refuses_what_its_frame_does_not_read() {
    let spp = RENDER_OPTIONS.iter().find(|o| o.flag == "--spp").unwrap();
    assert_refused(
        &[
            "animate", "--frames", "1", "--frame", "deferred", "--method", "raytrace",
        ],
        spp,
    );
    let camera_time = RENDER_OPTIONS
        .iter()
        .find(|o| o.flag == "--camera-time")
        .unwrap();
    assert_refused(&["animate", "--frames", "1"], camera_time);
}
