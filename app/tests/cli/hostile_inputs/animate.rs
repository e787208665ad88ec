//! `animate`: frame rates a GIF cannot hold, and starts far from 0.

use super::{SMALL, listing, run, s, temp_dir};

/// Case 1: `--fps` near 0 panicked building the GIF delay (1 / fps overflowed a
/// `Duration`); slightly larger ones were clamped to the longest GIF delay (655.35 s)
/// without a word. Both are refused by the option's parser, before anything is made.
#[test]
fn frame_rates_a_gif_cannot_hold_are_refused_naming_the_option() {
    let dir = temp_dir("fps");
    let out = dir.join("out");
    for fps in ["1e-20", "1e-45", "0.001", "0.0015"] {
        let r = run(&[
            "animate",
            "--scene",
            "fox-run",
            "--frames",
            "2",
            "--fps",
            fps,
            "--out",
            s(&out),
        ]);
        r.refused(&["--fps", "655.35 s", "at least 0.001526"]);
        assert!(!out.exists(), "--fps {fps} created the output directory");
    }
    // The slowest rate a GIF can hold is accepted (checked without rendering: the run is
    // stopped by another option that is checked after the rate).
    let r = run(&[
        "animate",
        "--fps",
        "0.001526",
        "--runs",
        "2",
        "--out",
        s(&out),
    ]);
    r.refused(&["--runs"]);
    std::fs::remove_dir_all(&dir).ok();
}

/// Case 5: frame times were single precision, so at `--start 1e8` (a step of 8 s there)
/// every frame of `game-level`, whose motions all loop, got the same time and the same
/// image. Times are f64 now, reduced modulo each loop.
#[test]
fn frames_far_from_time_zero_still_differ() {
    let dir = temp_dir("start");
    let mut args = vec![
        "animate",
        "--scene",
        "game-level",
        "--frames",
        "3",
        "--start",
        "1e8",
        "--method",
        "raytrace",
        "--out",
        s(&dir),
    ];
    args.extend(SMALL);
    let r = run(&args);
    assert!(r.succeeded(), "{}", r.stderr());
    let frames: Vec<Vec<u8>> = (0..3)
        .map(|i| std::fs::read(dir.join(format!("game-level-frame-{i:04}.png"))).unwrap())
        .collect();
    assert_ne!(frames[0], frames[1], "{:?}", listing(&dir));
    assert_ne!(frames[1], frames[2]);
    assert_ne!(frames[0], frames[2]);
    // Out of any sensible range: refused naming the option.
    let r = run(&["animate", "--start", "1e300", "--out", s(&dir)]);
    r.refused(&["--start", "1e9"]);
    std::fs::remove_dir_all(&dir).ok();
}
