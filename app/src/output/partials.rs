//! The names of a run's temporary files (`.<target name>.motion-shadows.partial-<owner>`) and
//! who owns them.
//!
//! The owner is the process's id and, on Linux, its start time (clock ticks after boot, field
//! 22 of /proc/PID/stat): a file is stale when no process with that id and that start time
//! runs. The start time is what tells a dead run's file from a running one's after the id has
//! been reused by some other process. Where /proc is missing nothing is known to be stale.
//!
//! A name alone proves nothing (a user may keep `.notes.partial-4000000-1`), so a temporary
//! file is only ever removed when the run that made it listed it in its record
//! (`run_record.rs`): the sweep starts from records, never from names that look alike.

use std::path::Path;
use std::sync::OnceLock;

/// What sets this program's temporary files apart from a user's `.x.partial-N`.
const PARTIAL: &str = ".motion-shadows.partial-";

/// The temporary file's name for the target `name`, owned by this process.
pub(super) fn temp_name(name: &str) -> String {
    temp_name_of(name, own_tag())
}

/// The temporary file's name for the target `name` of the run `tag`.
pub(super) fn temp_name_of(name: &str, tag: &str) -> String {
    format!(".{name}{PARTIAL}{tag}")
}

/// A name of a file directly in the output directory, visible: no separator, no `..`, not
/// starting with `.` (the temporary files and records are the hidden ones).
pub(super) fn is_plain_name(name: &str) -> bool {
    !name.starts_with('.') && Path::new(name).file_name().is_some_and(|n| n == name)
}

/// This process's owner tag: `<pid>-<start>`, or `<pid>` where the start time is unknown.
pub(super) fn own_tag() -> &'static str {
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
pub(super) fn start_time(pid: u32) -> Option<u64> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // The command name (field 2) is in parentheses and may hold spaces and parentheses:
    // the fields after it start after the last ')'. State is field 3, so 22 is the 20th.
    let after_name = &stat[stat.rfind(')')? + 1..];
    after_name.split_whitespace().nth(19)?.parse().ok()
}

/// Whether the process named by `tag` (`<pid>-<start>`, or `<pid>` on systems without a
/// start time) is known to be gone.
pub(super) fn owner_gone(tag: &str) -> bool {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn own_start_time_is_read_and_names_carry_it() {
        let linux = Path::new("/proc/self/stat").exists();
        let own = start_time(std::process::id());
        assert_eq!(own.is_some(), linux);
        let name = temp_name("a.png");
        let tag = name.strip_prefix(".a.png.motion-shadows.partial-").unwrap();
        assert!(!owner_gone(tag), "{name}: this process runs");
        if let Some(start) = own {
            assert_eq!(tag, format!("{}-{start}", std::process::id()));
        }
    }

    #[test]
    fn owners_are_gone_when_no_process_has_their_id_and_start_time() {
        if !Path::new("/proc/self/stat").exists() {
            return;
        }
        let pid = std::process::id();
        let start = start_time(pid).unwrap_or(0);
        // No process has pid 4294967295 (Linux pids stay below 2^22).
        for gone in [
            "4294967295".to_owned(),
            "4294967295-12".to_owned(),
            // This process's id with another start time: a dead run whose id was reused.
            format!("{pid}-{}", start + 1),
        ] {
            assert!(owner_gone(&gone), "{gone}");
        }
        for running_or_unknown in [own_tag().to_owned(), pid.to_string(), "x-1".to_owned()] {
            assert!(!owner_gone(&running_or_unknown), "{running_or_unknown}");
        }
    }
}
