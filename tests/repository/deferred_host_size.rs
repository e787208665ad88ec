//! Issue 37's target for the example engine (`examples/deferred_host/`): an outside host
//! doing all that it does (own device and allocator, G-buffer with motion and ids, the mask
//! with moving receivers, three frames in flight, reserved room, host barriers) in at most
//! `TARGET_LINES` lines of Rust with at most `TARGET_UNSAFE_BLOCKS` `unsafe` blocks, so that
//! the library's API stays small enough for a host to be small. The `unsafe` target is met;
//! the lines are not yet, so the gate holds today's count (`LINES_TODAY`), which may only come
//! down (lower it when the example shrinks, to `TARGET_LINES` at the most).

use std::path::{Path, PathBuf};

const TARGET_LINES: usize = 800;
const TARGET_UNSAFE_BLOCKS: usize = 20;
/// 2026-12-07: 2,481 lines and 50 `unsafe` blocks before the rewrite, 1,666 and 19 after
/// (formatted as the rest of the workspace); 2026-12-08: 1,124 and 15 (buffers, images,
/// pipelines and the shading's set from `research::gpu`, the library's `Light`); 1,024 and 15
/// (from the engine API: its barriers `HostBarrier`'s, its device `create_device`'s, its
/// allocator `Context::new_allocator`'s, its moved lights `LightShadow::set_light`'s).
const LINES_TODAY: usize = 1_024;

/// Every `.rs` file under `dir` (its `build.rs` included), skipping build output.
fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let entries =
        std::fs::read_dir(dir).unwrap_or_else(|e| panic!("reading {}: {e}", dir.display()));
    for entry in entries {
        let path = entry
            .unwrap_or_else(|e| panic!("listing {}: {e}", dir.display()))
            .path();
        if path.is_dir() && !path.ends_with("target") {
            found.extend(rust_files(&path));
        } else if path.extension().is_some_and(|e| e == "rs") {
            found.push(path);
        }
    }
    found
}

/// The `unsafe` blocks of `source`: the keyword followed by `{`, outside `//` comments (an
/// `unsafe fn` or `unsafe impl` is no block; its body's operations need blocks of their own,
/// as the workspace's `unsafe_op_in_unsafe_fn` lint requires).
fn unsafe_blocks(source: &str) -> usize {
    source
        .lines()
        .map(|line| line.split("//").next().unwrap_or(""))
        .map(|code| {
            code.match_indices("unsafe")
                .filter(|(at, _)| code[at + "unsafe".len()..].trim_start().starts_with('{'))
                .count()
        })
        .sum()
}

#[test]
fn unsafe_blocks_are_counted_by_the_keyword_before_a_brace() {
    let source = "let a = unsafe { f() };\n// unsafe { comment }\nunsafe fn g() {}\n\
                  let b = |c| unsafe {\n    d(c)\n};\nlet e = unsafe{ h() }; let i = unsafe { j() };";
    assert_eq!(unsafe_blocks(source), 4);
}

#[test]
fn the_deferred_host_example_meets_the_unsafe_target_and_does_not_grow() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/deferred_host");
    let files = rust_files(&root);
    assert!(!files.is_empty(), "no Rust files under {}", root.display());
    let (mut lines, mut blocks) = (0, 0);
    for file in &files {
        let text = std::fs::read_to_string(file)
            .unwrap_or_else(|e| panic!("reading {}: {e}", file.display()));
        let (l, b) = (text.lines().count(), unsafe_blocks(&text));
        eprintln!("{:>5} lines {b:>3} unsafe  {}", l, file.display());
        lines += l;
        blocks += b;
    }
    eprintln!(
        "{lines} lines, {blocks} unsafe blocks in {} files",
        files.len()
    );
    eprintln!("issue 37's target: {TARGET_LINES} lines, {TARGET_UNSAFE_BLOCKS} unsafe blocks");
    assert!(
        lines <= LINES_TODAY,
        "examples/deferred_host: {lines} lines of Rust, more than the {LINES_TODAY} it had \
         (issue 37's target: {TARGET_LINES})"
    );
    assert!(
        blocks <= TARGET_UNSAFE_BLOCKS,
        "examples/deferred_host: {blocks} unsafe blocks, the target is {TARGET_UNSAFE_BLOCKS}"
    );
}
