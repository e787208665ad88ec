//! The record a run keeps in its output directory while it has temporary files there, and
//! the recovery, by a later run, of what a killed run left.
//!
//! A run writes `.motion-shadows-run-<owner>-<n>` before it makes its first temporary file:
//! a header line no user file starts with and the targets it stages, one JSON string a line
//! (`partials.rs` names each target's temporary file from the target and the owner). Once
//! every temporary file is complete and on disk, the run renames its record to
//! `.motion-shadows-commit-<owner>-<n>`, renames its files over their targets, and removes
//! the record. So a run killed at any point leaves exactly one record, which says what to do:
//!
//! - `run`: it was killed before its commit; its temporary files are removed (roll back:
//!   the targets still hold the previous set).
//! - `commit`: it was killed between its renames (the new EXR beside the old PNG); its
//!   temporary files are complete, so the rest are renamed into place (roll forward: the
//!   whole new set).
//!
//! Only files that a record of a dead owner lists, under the names this program gives them,
//! are ever touched: a user's `.notes.partial-4000000-1`, or a file with a record's name but
//! not its header, is left alone.

use std::fs::{File, OpenOptions};
use std::io::{Read as _, Write as _};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use super::OutputError;
use super::partials::{is_plain_name, own_tag, owner_gone, temp_name_of};
use super::target::check_replaceable;

const STAGING: &str = ".motion-shadows-run-";
const COMMITTING: &str = ".motion-shadows-commit-";
const HEADER: &str = "motion-shadows staged outputs/1";
/// A record lists a run's targets; anything longer is not one of ours and is not read whole.
const MAX_RECORD_BYTES: u64 = 1 << 20;

/// The record of a live run's staged files in one directory.
pub(super) struct RunRecord {
    dir: PathBuf,
    /// `<owner>-<n>`: `n` tells apart the sets one process stages in one directory.
    id: String,
    committing: bool,
}

impl RunRecord {
    /// Writes the record of a run that stages `names` (plain file names) in `dir`.
    pub(super) fn write(dir: &Path, names: &[String]) -> Result<Self, OutputError> {
        static NEXT: AtomicU64 = AtomicU64::new(0);
        let record = Self {
            dir: dir.to_path_buf(),
            id: format!("{}-{}", own_tag(), NEXT.fetch_add(1, Ordering::Relaxed)),
            committing: false,
        };
        let mut text = format!("{HEADER}\n");
        for name in names {
            // JSON strings: a name may hold a newline, which would split a plain line.
            text.push_str(&serde_json::Value::from(name.as_str()).to_string());
            text.push('\n');
        }
        let path = record.path();
        // create_new: never through a link or over a file someone put there.
        let mut file = OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&path)
            .map_err(|e| OutputError::io(&path, e))?;
        if let Err(e) = file.write_all(text.as_bytes()) {
            let _ = std::fs::remove_file(&path);
            return Err(OutputError::io(&path, e));
        }
        Ok(record)
    }

    fn path(&self) -> PathBuf {
        let prefix = if self.committing { COMMITTING } else { STAGING };
        self.dir.join(format!("{prefix}{}", self.id))
    }

    /// Marks the set as complete: from here on a run that finds this record after the
    /// process died renames the rest of the set into place rather than removing it. Reaches
    /// the disk before any target is replaced.
    pub(super) fn begin_commit(&mut self) -> Result<(), OutputError> {
        let staging = self.path();
        self.committing = true;
        let committing = self.path();
        if let Err(e) = File::open(&staging)
            .and_then(|f| f.sync_all())
            .and_then(|()| std::fs::rename(&staging, &committing))
        {
            self.committing = false;
            return Err(OutputError::io(&staging, e));
        }
        sync_dir(&self.dir);
        Ok(())
    }

    /// Removes the record: the run's temporary files are gone (renamed or removed).
    pub(super) fn remove(self) -> Result<(), OutputError> {
        let path = self.path();
        std::fs::remove_file(&path).map_err(|e| OutputError::io(&path, e))
    }
}

/// Best effort: not every platform can open a directory.
pub(super) fn sync_dir(dir: &Path) {
    if let Ok(d) = File::open(dir) {
        let _ = d.sync_all();
    }
}

/// Finishes what runs killed in `dir` left, from their records (see the module's text), and
/// returns a line for each file removed or renamed. The caller holds the directory's lock, so
/// no live run is between its renames and two runs never recover one record at once. Fails,
/// naming both paths and leaving the record for a later run, where a killed commit's file
/// cannot be renamed into place (something that is not a regular file is there now).
pub(super) fn recover(dir: &Path) -> Result<Vec<String>, OutputError> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Ok(Vec::new());
    };
    let mut records: Vec<(PathBuf, bool, String)> = entries
        .flatten()
        .filter_map(|entry| {
            let name = entry.file_name().into_string().ok()?;
            let (committing, id) = match name.strip_prefix(COMMITTING) {
                Some(id) => (true, id),
                None => (false, name.strip_prefix(STAGING)?),
            };
            let (tag, n) = id.rsplit_once('-')?;
            let ours = n.parse::<u64>().is_ok() && owner_gone(tag);
            ours.then(|| (entry.path(), committing, tag.to_owned()))
        })
        .collect();
    records.sort();
    let mut notes = Vec::new();
    for (path, committing, tag) in records {
        let Some(targets) = read_targets(&path) else {
            continue;
        };
        for target in targets {
            let temp = dir.join(temp_name_of(&target, &tag));
            if !std::fs::symlink_metadata(&temp).is_ok_and(|m| m.is_file()) {
                continue;
            }
            if committing {
                complete(&temp, &dir.join(&target), &mut notes)?;
            } else if std::fs::remove_file(&temp).is_ok() {
                notes.push(format!(
                    "removed {}, a temporary file left by a run that was killed before it \
                     committed its outputs",
                    temp.display()
                ));
            }
        }
        sync_dir(dir);
        if std::fs::remove_file(&path).is_ok() {
            notes.push(format!(
                "removed {}, the record of a run that was killed while it {}",
                path.display(),
                if committing {
                    "renamed its outputs into place"
                } else {
                    "wrote its outputs"
                }
            ));
        }
    }
    Ok(notes)
}

/// Renames a killed commit's complete `temp` over `target`.
fn complete(temp: &Path, target: &Path, notes: &mut Vec<String>) -> Result<(), OutputError> {
    let blocked = |reason: String| {
        OutputError::io(
            temp,
            std::io::Error::other(format!(
                "a run killed while it renamed its outputs into place left this complete \
                 file to replace {}, which cannot be done: {reason}; move what is in the way \
                 (or this file) and run again",
                target.display()
            )),
        )
    };
    check_replaceable(target).map_err(|e| blocked(e.to_string()))?;
    std::fs::rename(temp, target).map_err(|e| blocked(e.to_string()))?;
    notes.push(format!(
        "completed {}: a run killed while it renamed its outputs into place had written it \
         in full ({}), and the rest of its set was already in place",
        target.display(),
        temp.display()
    ));
    Ok(())
}

/// The targets a record lists, or None when the file is not a record this program wrote
/// (a user's file with a record's name): its first line is not the header.
fn read_targets(path: &Path) -> Option<Vec<String>> {
    if !std::fs::symlink_metadata(path).is_ok_and(|m| m.is_file()) {
        return None;
    }
    let mut text = String::new();
    File::open(path)
        .ok()?
        .take(MAX_RECORD_BYTES)
        .read_to_string(&mut text)
        .ok()?;
    let mut lines = text.lines();
    if lines.next() != Some(HEADER) {
        return None;
    }
    // A line that does not parse (a record cut short) names no file of the run.
    Some(
        lines
            .filter_map(|line| serde_json::from_str::<String>(line).ok())
            .filter(|name| is_plain_name(name))
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::tests::temp_path;

    /// A dead owner: no process has pid 4294967295.
    const DEAD: &str = "4294967295-7";

    fn write(dir: &Path, name: &str, bytes: &[u8]) {
        std::fs::write(dir.join(name), bytes).unwrap();
    }

    fn record(targets: &[&str]) -> String {
        let mut text = format!("{HEADER}\n");
        for t in targets {
            text.push_str(&format!("{t:?}\n"));
        }
        text
    }

    #[test]
    fn a_dead_runs_staged_files_are_removed_and_a_dead_commit_is_completed() {
        if !Path::new("/proc/self/stat").exists() {
            return; // no owner is known to be gone
        }
        let dir = temp_path("records");
        std::fs::create_dir_all(&dir).unwrap();
        // A run killed before its commit: its half-written file goes, the target stays.
        write(&dir, "a.png", b"old a");
        write(&dir, &temp_name_of("a.png", DEAD), b"half");
        write(
            &dir,
            &format!("{STAGING}{DEAD}-0"),
            record(&["a.png"]).as_bytes(),
        );
        // A run killed between its renames: x.exr is new, x.png still to be renamed.
        write(&dir, "x.exr", b"new x.exr");
        write(&dir, "x.png", b"old x.png");
        write(&dir, &temp_name_of("x.png", DEAD), b"new x.png");
        let commit = record(&["x.exr", "x.png"]);
        write(&dir, &format!("{COMMITTING}{DEAD}-1"), commit.as_bytes());
        // A live run's record and file (this process's) are not touched.
        let live = RunRecord::write(&dir, &["b.png".to_owned()]).unwrap();
        write(&dir, &temp_name_of("b.png", own_tag()), b"being written");

        let notes = recover(&dir).unwrap();
        assert_eq!(notes.len(), 4, "{notes:?}");
        assert_eq!(std::fs::read(dir.join("a.png")).unwrap(), b"old a");
        assert_eq!(std::fs::read(dir.join("x.png")).unwrap(), b"new x.png");
        assert_eq!(std::fs::read(dir.join("x.exr")).unwrap(), b"new x.exr");
        let mut left: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        left.sort();
        let mut expected = vec![
            "a.png".to_owned(),
            "x.exr".to_owned(),
            "x.png".to_owned(),
            temp_name_of("b.png", own_tag()),
            live.path()
                .file_name()
                .unwrap()
                .to_str()
                .unwrap()
                .to_owned(),
        ];
        expected.sort();
        assert_eq!(left, expected);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn what_no_record_of_a_dead_run_lists_is_left_alone() {
        if !Path::new("/proc/self/stat").exists() {
            return;
        }
        let dir = temp_path("not-records");
        std::fs::create_dir_all(&dir).unwrap();
        let users = [
            ".thesis.tex.partial-999999".to_owned(),
            ".notes.partial-4000000-1".to_owned(),
            // This program's naming, but no record lists it.
            temp_name_of("c.png", DEAD),
            // A record's name without the header: a user's file.
            format!("{STAGING}{DEAD}-2"),
            format!("{COMMITTING}{DEAD}-3"),
        ];
        for name in &users {
            write(&dir, name, b"a user's words");
        }
        // A record of a dead run cannot name a file outside its own temporary files.
        write(&dir, "d.png", b"kept");
        write(
            &dir,
            &format!("{STAGING}{DEAD}-4"),
            record(&["../d.png", ".d.png"]).as_bytes(),
        );
        let notes = recover(&dir).unwrap();
        assert_eq!(notes.len(), 1, "only the record itself goes: {notes:?}");
        for name in users.iter().chain([&"d.png".to_owned()]) {
            assert!(dir.join(name).exists(), "{name} removed");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_dead_commit_that_cannot_be_completed_is_refused_naming_both_paths() {
        if !Path::new("/proc/self/stat").exists() {
            return;
        }
        let dir = temp_path("blocked-commit");
        std::fs::create_dir_all(dir.join("y.png")).unwrap();
        write(&dir, &temp_name_of("y.png", DEAD), b"new y.png");
        let record_name = format!("{COMMITTING}{DEAD}-5");
        write(&dir, &record_name, record(&["y.png"]).as_bytes());
        let e = recover(&dir).unwrap_err().to_string();
        assert!(
            e.contains(&*dir.join("y.png").to_string_lossy())
                && e.contains(&temp_name_of("y.png", DEAD))
                && e.contains("is a directory"),
            "{e}"
        );
        assert!(dir.join(&record_name).exists(), "kept for a later run");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
