//! The repository's size report: every source file over `TARGET_LINES` lines (issue 42's
//! target for a file that holds one concept), printed largest first
//! (`cargo test --test repository -- source_sizes --nocapture` shows it). The files over the target today
//! are listed in `OVERSIZED` with their line counts; a listed file may only shrink, and no
//! other file may cross the target, so the list can only get shorter. Splitting a listed file
//! below the target means deleting its line here (the test says so).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

const TARGET_LINES: usize = 600;

/// The extensions of the files the report counts: the Rust, GLSL and scripts people read and
/// edit (not data, images, lock files or configuration).
const SOURCE_EXTENSIONS: [&str; 8] = ["rs", "glsl", "comp", "frag", "vert", "geom", "sh", "py"];

/// The files over `TARGET_LINES` lines, relative to the repository root, with the most lines
/// each may have.
const OVERSIZED: [(&str, usize); 0] = [];

/// Every source file under `root` with its line count, skipping build output (`target`) and
/// hidden directories (`.git`, `.cargo`).
fn source_files(root: &Path) -> BTreeMap<String, usize> {
    let mut found = BTreeMap::new();
    let mut pending = vec![root.to_path_buf()];
    while let Some(dir) = pending.pop() {
        let entries = std::fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("reading directory {}: {e}", dir.display()));
        for entry in entries {
            let entry = entry.unwrap_or_else(|e| panic!("listing {}: {e}", dir.display()));
            let path = entry.path();
            let name = entry.file_name().to_string_lossy().into_owned();
            let kind = entry
                .file_type()
                .unwrap_or_else(|e| panic!("reading the type of {}: {e}", path.display()));
            if kind.is_dir() {
                if name != "target" && !name.starts_with('.') {
                    pending.push(path);
                }
            } else if kind.is_file() && is_source(&path) {
                let text = std::fs::read_to_string(&path)
                    .unwrap_or_else(|e| panic!("reading {}: {e}", path.display()));
                found.insert(relative(root, &path), text.lines().count());
            }
        }
    }
    found
}

fn is_source(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| SOURCE_EXTENSIONS.contains(&e))
}

fn relative(root: &Path, path: &Path) -> String {
    let inside: PathBuf = path
        .strip_prefix(root)
        .unwrap_or_else(|_| panic!("{} is not under {}", path.display(), root.display()))
        .to_path_buf();
    inside
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect::<Vec<_>>()
        .join("/")
}

/// What is wrong with the tree against the allow-list, one line per file: a file over the
/// target that is not listed, a listed file that grew, a listed file now within the target
/// (or gone) whose line should be deleted.
fn violations(files: &BTreeMap<String, usize>, oversized: &[(&str, usize)]) -> Vec<String> {
    let mut found = Vec::new();
    for (path, &lines) in files {
        if lines <= TARGET_LINES {
            continue;
        }
        match oversized.iter().find(|(listed, _)| listed == path) {
            None => found.push(format!(
                "{path}: {lines} lines, over the {TARGET_LINES}-line target: split it along its \
                 seams (a new file may not join OVERSIZED)"
            )),
            Some(&(_, most)) if lines > most => found.push(format!(
                "{path}: {lines} lines, grew past its {most} in OVERSIZED (a listed file may \
                 only shrink)"
            )),
            Some(_) => {}
        }
    }
    for &(listed, most) in oversized {
        match files.get(listed) {
            None => found.push(format!(
                "{listed}: listed in OVERSIZED ({most} lines) but not found: delete its line"
            )),
            Some(&lines) if lines <= TARGET_LINES => found.push(format!(
                "{listed}: {lines} lines, within the target now: delete its line in OVERSIZED"
            )),
            Some(_) => {}
        }
    }
    found
}

#[test]
fn no_source_file_crosses_the_target_and_listed_ones_only_shrink() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let files = source_files(root);
    assert!(
        files.contains_key("src/lib.rs") && files.contains_key("app/src/main.rs"),
        "the walk from {} missed the crates' roots",
        root.display()
    );
    let mut report: Vec<(&String, &usize)> = files
        .iter()
        .filter(|(_, lines)| **lines > TARGET_LINES)
        .collect();
    report.sort_by(|a, b| b.1.cmp(a.1).then(a.0.cmp(b.0)));
    eprintln!(
        "{} source files, {} over {TARGET_LINES} lines:",
        files.len(),
        report.len()
    );
    for (path, lines) in &report {
        eprintln!("{lines:>6}  {path}");
    }
    let found = violations(&files, &OVERSIZED);
    assert!(found.is_empty(), "{}", found.join("\n"));
}

#[test]
fn the_check_refuses_a_new_oversized_file_a_grown_one_and_a_stale_entry() {
    let files: BTreeMap<String, usize> = [
        ("a.rs".to_string(), TARGET_LINES + 1),
        ("b.rs".to_string(), 700),
        ("c.rs".to_string(), 650),
        ("d.rs".to_string(), TARGET_LINES),
    ]
    .into();
    let oversized = [("b.rs", 699), ("c.rs", 660), ("d.rs", 640), ("e.rs", 900)];
    let found = violations(&files, &oversized);
    let about = |name: &str| found.iter().filter(|v| v.starts_with(name)).count();
    // New (a), grown (b), shrunk within the target (d), gone (e); c shrank and stays listed.
    assert_eq!(
        [
            about("a.rs"),
            about("b.rs"),
            about("c.rs"),
            about("d.rs"),
            about("e.rs")
        ],
        [1, 1, 0, 1, 1],
        "{found:?}"
    );
}
