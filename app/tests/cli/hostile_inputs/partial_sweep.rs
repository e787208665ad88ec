//! Issue 36 item 8: the sweep of a killed run's temporary files removed any file in `--out`
//! named like one (`.thesis.tex.partial-999999`, `.notes.partial-4000000-1`): a user's own
//! files. It removes only the files a dead run of this program listed in its record now.

use super::{listing, run, run_env, s, temp_dir};

#[test]
fn user_files_named_like_partials_survive_and_a_dead_runs_partials_do_not() {
    let out = temp_dir("sweep-user-files");
    let users = [
        ".thesis.tex.partial-999999",
        ".notes.partial-4000000-1",
        ".cubes-toward-light-raytrace.png.partial-4000000-1",
        ".cubes-toward-light-raytrace.png.motion-shadows.partial-4000000-1",
        ".motion-shadows-run-4000000-1-0",
    ];
    for name in users {
        std::fs::write(out.join(name), format!("{name}: a user's words")).unwrap();
    }
    // A real dead run: killed with its files complete, before its commit.
    let render = [
        "render",
        "--method",
        "raytrace",
        "--width",
        "48",
        "--height",
        "36",
        "--spp",
        "2",
        "--out",
        s(&out),
    ];
    let killed = run_env(&render, &[("MOTION_SHADOWS_TEST_ABORT", "before-commit")]);
    assert!(!killed.succeeded(), "the run was not aborted");
    let left_by_the_run: Vec<String> = listing(&out)
        .into_iter()
        .filter(|n| !users.contains(&n.as_str()))
        .collect();
    assert!(
        left_by_the_run.iter().any(|n| n.contains(".partial-")),
        "{left_by_the_run:?}"
    );

    let json = out.join("scene.json");
    let next = run(&["scene", "export", "cubes-toward-light", "--out", s(&json)]);
    assert!(next.succeeded(), "{}", next.stderr());
    for name in &left_by_the_run {
        assert!(
            next.stderr()
                .contains(&format!("note: removed {}", s(&out.join(name)))),
            "{name} not named: {}",
            next.stderr()
        );
    }
    for name in users {
        assert_eq!(
            std::fs::read_to_string(out.join(name)).unwrap(),
            format!("{name}: a user's words"),
            "{}",
            next.stderr()
        );
    }
    let mut expected: Vec<&str> = users.to_vec();
    expected.push("scene.json");
    expected.sort();
    assert_eq!(listing(&out), expected);
    std::fs::remove_dir_all(&out).ok();
}
