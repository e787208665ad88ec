//! The temporary files of a run (`.<target name>.partial-<owner>`) and the sweep of those a
//! run left when it was killed or aborted before its commit (SIGKILL, an allocation failure):
//! nothing can remove them as the process dies, so the next run into the same directory does,
//! under the directory's lock, and names each one it removes.
//!
//! The owner is the process's id and, on Linux, its start time (clock ticks after boot, field
//! 22 of /proc/PID/stat): a file is stale when no process with that id and that start time
//! runs. The start time is what tells a dead run's file from a running one's after the id has
//! been reused by some other process. Where /proc is missing nothing is known to be stale, and
//! nothing is removed.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

const PARTIAL: &str = ".partial-";

/// The temporary file's name for the target `name`, owned by this process.
pub(super) fn temp_name(name: &str) -> String {
    format!(".{name}{PARTIAL}{}", own_tag())
}

fn own_tag() -> &'static str {
    static TAG: OnceLock<String> = OnceLock::new();
    TAG.get_or_init(|| {
        let pid = std::process::id();
        match start_time(pid) {
            Some(start) => format!("{pid}-{start}"),
            None => pid.to_string(),
        }
    })
}

/// The start time of process `pid` (field 22 of /proc/PID/stat), if it runs (or is a zombie
/// not yet reaped) and /proc says.
fn start_time(pid: u32) -> Option<u64> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // The command name (field 2) is in parentheses and may hold spaces and parentheses:
    // the fields after it start after the last ')'. State is field 3, so 22 is the 20th.
    let after_name = &stat[stat.rfind(')')? + 1..];
    after_name.split_whitespace().nth(19)?.parse().ok()
}

/// Whether the process named by `tag` (`<pid>-<start>`, or `<pid>` as older runs and systems
/// without a start time wrote it) is known to be gone.
fn owner_gone(tag: &str) -> bool {
    if !Path::new("/proc/self/stat").exists() {
        return false;
    }
    match tag.split_once('-') {
        Some((pid, start)) => match (pid.parse::<u32>(), start.parse::<u64>()) {
            (Ok(pid), Ok(start)) => start_time(pid) != Some(start),
            _ => false,
        },
        None => tag
            .parse::<u32>()
            .is_ok_and(|pid| !Path::new("/proc").join(pid.to_string()).exists()),
    }
}

/// Removes the temporary files in `dir` whose run is gone (regular files named as
/// [`temp_name`] names them, for any target); returns the paths removed. The caller holds
/// the directory's lock, so two runs sweeping at once do not both claim one file.
pub(super) fn remove_stale(dir: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut removed = Vec::new();
    for entry in entries.flatten() {
        let file_name = entry.file_name();
        let Some(name) = file_name.to_str() else {
            continue;
        };
        let Some((target, tag)) = name.rsplit_once(PARTIAL) else {
            continue;
        };
        if !target.starts_with('.') || target.len() < 2 || !owner_gone(tag) {
            continue;
        }
        let path = entry.path();
        let regular = std::fs::symlink_metadata(&path).is_ok_and(|m| m.is_file());
        if regular && std::fs::remove_file(&path).is_ok() {
            removed.push(path);
        }
    }
    removed.sort();
    removed
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::tests::temp_path;

    #[test]
    fn own_start_time_is_read_and_names_carry_it() {
        let linux = Path::new("/proc/self/stat").exists();
        let own = start_time(std::process::id());
        assert_eq!(own.is_some(), linux);
        let name = temp_name("a.png");
        let tag = name.strip_prefix(".a.png.partial-").unwrap();
        assert!(!owner_gone(tag), "{name}: this process runs");
        if let Some(start) = own {
            assert_eq!(tag, format!("{}-{start}", std::process::id()));
        }
    }

    #[test]
    fn only_files_of_gone_runs_are_removed() {
        let dir = temp_path("partials-sweep");
        std::fs::create_dir_all(&dir).unwrap();
        let pid = std::process::id();
        let linux = Path::new("/proc/self/stat").exists();
        let start = start_time(pid).unwrap_or(0);
        // No process has pid 4294967295 (Linux pids stay below 2^22).
        let gone = [
            format!(".a.png{PARTIAL}4294967295"),
            format!(".b.exr{PARTIAL}4294967295-12"),
            // This process's id with another start time: a dead run whose id was reused.
            format!(".c.gif{PARTIAL}{pid}-{}", start + 1),
        ];
        let kept = [
            temp_name("d.png"),
            format!(".e.png{PARTIAL}{pid}"),
            format!("f.png{PARTIAL}4294967295"), // not a hidden temporary name
            format!(".g.png{PARTIAL}x-1"),
            "h.png".to_owned(),
        ];
        for name in gone.iter().chain(&kept) {
            std::fs::write(dir.join(name), b"half").unwrap();
        }
        // A directory with a temporary name is not a file this program wrote.
        std::fs::create_dir(dir.join(format!(".i.png{PARTIAL}4294967295"))).unwrap();
        let removed = remove_stale(&dir);
        let mut expected: Vec<PathBuf> = if linux {
            gone.iter().map(|n| dir.join(n)).collect()
        } else {
            Vec::new()
        };
        expected.sort();
        assert_eq!(removed, expected);
        for name in &kept {
            assert!(dir.join(name).exists(), "{name}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
