//! Outputs: what a run may replace, and how two runs share an output directory.

use std::io::{BufRead as _, BufReader};
use std::path::Path;

use super::{SMALL, listing, run, s, spawn, temp_dir};

/// A FIFO at `path` (mkfifo(1): no root needed).
fn mkfifo(path: &Path) {
    let status = std::process::Command::new("mkfifo")
        .arg(path)
        .status()
        .unwrap();
    assert!(status.success());
}

fn is_fifo(path: &Path) -> bool {
    use std::os::unix::fs::FileTypeExt as _;
    std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_fifo())
}

/// Case 3: `scene export --out PATH` renamed its staged file over whatever was at PATH: a
/// device (as root, `--out /dev/null` would replace the system's), a FIFO, a symbolic link
/// such as /dev/stdout. Every output commit refuses a target that exists and is not a
/// regular file, naming it, before anything is written; the thing there is left as it was.
#[test]
fn outputs_never_replace_links_fifos_or_devices() {
    let dir = temp_dir("non-regular");
    let kept = dir.join("kept.json");
    std::fs::write(&kept, "keep me").unwrap();
    let link = dir.join("link.json");
    std::os::unix::fs::symlink(&kept, &link).unwrap();
    let fifo = dir.join("fifo.json");
    mkfifo(&fifo);
    for (path, kind) in [(&link, "symbolic link"), (&fifo, "FIFO")] {
        let r = run(&["scene", "export", "cubes-toward-light", "--out", s(path)]);
        r.refused(&[s(path), kind, "not a regular file"]);
    }
    assert!(
        std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    assert_eq!(std::fs::read_to_string(&kept).unwrap(), "keep me");
    assert!(is_fifo(&fifo), "the FIFO was replaced");

    // The same rule for a render's files: refused before rendering, nothing replaced.
    let out = dir.join("out");
    std::fs::create_dir(&out).unwrap();
    let png = out.join("cubes-toward-light-temporal.png");
    mkfifo(&png);
    let mut args = vec!["render", "--out", s(&out)];
    args.extend(SMALL);
    let r = run(&args);
    r.refused(&["cubes-toward-light-temporal.png", "FIFO"]);
    assert!(
        !r.stderr().contains("lighting pass"),
        "refused after rendering"
    );
    assert!(is_fifo(&png));
    assert_eq!(listing(&out), ["cubes-toward-light-temporal.png"]);
    std::fs::remove_dir_all(&dir).ok();
}

/// Case 8: two runs committing into one `--out` could leave one's EXR beside the other's
/// PNG: the files were renamed one by one with no lock. A run renames its set holding a
/// lock (flock) of the output directory now. Here the test holds that lock: the run must
/// wait for it, saying so, and write nothing until it is released.
#[test]
fn a_run_commits_its_files_only_under_the_output_directorys_lock() {
    let out = temp_dir("lock");
    let lock = std::fs::File::open(&out).unwrap();
    {
        use std::os::fd::AsRawFd as _;
        // SAFETY: flock on a descriptor this test owns.
        assert_eq!(unsafe { libc::flock(lock.as_raw_fd(), libc::LOCK_EX) }, 0);
    }
    let mut args = vec!["render", "--method", "raytrace", "--out", s(&out)];
    args.extend(SMALL);
    let mut child = spawn(&args);
    let stderr = BufReader::new(child.stderr.take().unwrap());
    let mut seen = Vec::new();
    let mut waiting = false;
    let mut lines = stderr.lines();
    for line in lines.by_ref() {
        let line = line.unwrap();
        waiting = line.contains("waiting for another run");
        seen.push(line);
        if waiting {
            break;
        }
    }
    assert!(waiting, "the run never waited for the lock: {seen:?}");
    // Rendered and staged, but nothing committed while the lock is held.
    assert!(
        listing(&out).iter().all(|n| n.starts_with('.')),
        "{:?}",
        listing(&out)
    );
    drop(lock);
    let rest: Vec<String> = lines.map(Result::unwrap).collect();
    let status = child.wait().unwrap();
    assert!(status.success(), "{seen:?} {rest:?}");
    assert_eq!(
        listing(&out),
        [
            "cubes-toward-light-raytrace.exr",
            "cubes-toward-light-raytrace.png"
        ]
    );
    std::fs::remove_dir_all(&out).ok();
}

/// Case 11, second half: `bench --out` errors did not name the path. It is checked before
/// the device is made now, and named.
#[test]
fn bench_names_an_output_directory_it_cannot_use() {
    let dir = temp_dir("bench-out");
    let file = dir.join("a-file");
    std::fs::write(&file, "not a directory").unwrap();
    let out = file.join("bench");
    let r = run(&["bench", "--quick", "--preset", "spp", "--out", s(&out)]);
    r.refused(&[s(&out)]);
    std::fs::remove_dir_all(&dir).ok();
}

/// A run killed while it renders (SIGKILL: as an out-of-memory abort would end it) leaves
/// nothing in its output directory: the temporary files are made by their writers once the
/// frame is done, not when the run starts (they were, as empty `.partial-PID` files that
/// only the next run into the directory removed).
#[test]
fn a_run_killed_while_it_renders_leaves_no_partial_files() {
    let out = temp_dir("killed");
    let mut args = vec!["render", "--method", "raytrace", "--out", s(&out)];
    args.extend(["--width", "320", "--height", "240", "--spp", "64"]);
    let mut child = spawn(&args);
    let stderr = BufReader::new(child.stderr.take().unwrap());
    let mut seen = Vec::new();
    for line in stderr.lines() {
        let line = line.unwrap();
        let rendering = line.contains("raytrace: rows");
        seen.push(line);
        if rendering {
            break;
        }
    }
    assert!(
        seen.iter().any(|l| l.contains("raytrace: rows")),
        "the run never started rendering: {seen:?}"
    );
    child.kill().unwrap();
    child.wait().unwrap();
    assert_eq!(listing(&out), Vec::<String>::new(), "after {seen:?}");
}

/// A run killed after its writers made their temporary files (SIGKILL; an allocation
/// failure's abort ends a run as abruptly) leaves them behind, with the record that lists
/// them: nothing can remove them as the process dies. The next run into the directory, whatever it writes, removes them under
/// the directory's lock and names each: the directory then holds what a clean run leaves.
/// (`animate` makes its GIF's temporary file before the first frame and renames it only
/// after the last, so a kill lands in that window without racing the run.)
#[test]
fn files_a_killed_run_was_writing_are_removed_by_the_next_run() {
    let out = temp_dir("killed-writing");
    let mut args = vec![
        "animate",
        "--scene",
        "fox-run",
        "--frames",
        "50",
        "--out",
        s(&out),
    ];
    args.extend(SMALL);
    let mut child = spawn(&args);
    let stderr = super::drain(child.stderr.take().unwrap());
    let start = std::time::Instant::now();
    let partial = |out: &Path| listing(out).iter().any(|n| n.contains(".partial-"));
    while !partial(&out) && start.elapsed() < std::time::Duration::from_secs(120) {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before it wrote anything"
        );
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    let stderr = String::from_utf8_lossy(&stderr.join().unwrap()).into_owned();
    let left = listing(&out);
    assert!(!left.is_empty(), "{stderr}");
    // Its temporary files, and the record that lists them as its own (issue 36 item 8).
    assert!(
        left.iter()
            .all(|n| (n.starts_with(".fox-run") && n.contains(".partial-"))
                || n.starts_with(".motion-shadows-run-")),
        "{left:?}"
    );
    assert!(left.iter().any(|n| n.contains(".partial-")), "{left:?}");

    // Another run, other names: the killed run's files go, named, and its own arrive.
    let mut args = vec!["render", "--out", s(&out)];
    args.extend(SMALL);
    let r = run(&args);
    assert!(r.succeeded(), "{}", r.stderr());
    for name in &left {
        assert!(
            r.stderr()
                .contains(&format!("note: removed {}", s(&out.join(name)))),
            "{name} not named: {}",
            r.stderr()
        );
    }
    assert_eq!(
        listing(&out),
        [
            "cubes-toward-light-temporal.exr",
            "cubes-toward-light-temporal.png"
        ]
    );
    std::fs::remove_dir_all(&out).ok();
}
