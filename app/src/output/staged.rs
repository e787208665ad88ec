//! All-or-nothing output: every file of a run is written to a temporary file beside its
//! target and renamed into place only when all of them are complete, so a run that fails
//! (or is killed) never leaves a truncated image or a mixed EXR/PNG pair over good files.
//!
//! The output directory and the targets are checked when the run starts, before anything is
//! rendered: the directory is created, each temporary file is created in it (proving it is
//! writable), and a target that exists and is not a regular file (a directory, a device, a
//! FIFO, a socket, a symbolic link) is an error (`target.rs`). The renames happen under a
//! lock of the directory (`dir_lock.rs`), so two runs' sets never mix. Temporary files are
//! named `.<target name>.motion-shadows.partial-<owner>` (`partials.rs`) and listed in the
//! run's record (`run_record.rs`) before the first is made; they are removed when the run
//! fails. The next run into the same directory finishes, under the lock and naming each
//! file, what a run killed before or during its commit left (on Linux, where it can tell
//! that their process is gone): it removes the files of a run killed before its commit, and
//! renames into place the rest of a set whose commit was killed among its renames, so a
//! crash leaves neither stray files nor a mixed EXR/PNG pair once the directory is used
//! again. Files it did not list (a user's `.notes.partial-1`) are never touched.

use std::fs::File;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use super::OutputError;
use super::dir_lock::DirLock;
use super::partials::{is_plain_name, temp_name};
use super::run_record::{RunRecord, recover, sync_dir};
use super::target::check_replaceable;
use super::test_abort::abort_if_asked;

/// The files of one run, staged in one directory.
pub struct StagedFiles {
    entries: Vec<(PathBuf, PathBuf)>,
    names: Vec<String>,
    dir: PathBuf,
    /// Written when the first temporary file is asked for, so that a run killed while it
    /// renders leaves nothing; a mutex, not a cell, so the set can be shared by threads.
    record: Mutex<Option<RunRecord>>,
    state: State,
}

#[derive(PartialEq)]
enum State {
    Staging,
    Committed,
    /// A rename failed mid-commit: the temporary files and the commit's record stay, so the
    /// next run into the directory completes the set (`run_record.rs`).
    LeftToComplete,
}

impl StagedFiles {
    /// Creates `dir` if needed and checks that a temporary file for each of `names` (plain
    /// file names, no separators) can be made there. Fails before anything is written when a
    /// target is not a regular file or the directory is not writable. The temporary files
    /// are made by their writers ([`Self::temp_path`]); [`Self::commit`] fails naming one
    /// that was never written.
    pub fn prepare(dir: &Path, names: &[String]) -> Result<Self, OutputError> {
        std::fs::create_dir_all(dir).map_err(|e| OutputError::io(dir, e))?;
        if !dir.is_dir() {
            return Err(OutputError::io(
                dir,
                std::io::Error::other("the output path exists and is not a directory"),
            ));
        }
        let mut staged = Self {
            entries: Vec::with_capacity(names.len()),
            names: names.to_vec(),
            dir: dir.to_path_buf(),
            record: Mutex::new(None),
            state: State::Staging,
        };
        // Every target is checked before any temporary file is made.
        for name in names {
            if !is_plain_name(name) {
                return Err(OutputError::io(
                    &dir.join(name),
                    std::io::Error::other("output names must be plain file names"),
                ));
            }
            check_replaceable(&dir.join(name))?;
        }
        sweep(dir)?;
        // Recorded while the files are tried, so that even a kill now leaves nothing that
        // the next run cannot tell for this program's.
        *staged.record.get_mut().unwrap_or_else(|e| e.into_inner()) =
            Some(RunRecord::write(dir, names)?);
        for name in names {
            let target = dir.join(name);
            let temp = dir.join(temp_name(name));
            // Registered first, so Drop removes it even if creating it half-fails.
            staged.entries.push((temp.clone(), target));
            // Made once to prove the directory takes it, then removed: the writer makes it
            // again when the frame is done, so a run killed while it renders (an abort, a
            // signal) leaves nothing behind.
            File::create(&temp).map_err(|e| OutputError::io(&temp, e))?;
            std::fs::remove_file(&temp).map_err(|e| OutputError::io(&temp, e))?;
        }
        if let Some(record) = staged
            .record
            .get_mut()
            .unwrap_or_else(|e| e.into_inner())
            .take()
        {
            record.remove()?;
        }
        Ok(staged)
    }

    /// Where to write the file that will become `dir/name` (one of the prepared names). The
    /// first call records the run's temporary files in the directory (`run_record.rs`):
    /// only what a record lists is ever removed or completed by a later run.
    pub fn temp_path(&self, name: &str) -> Result<&Path, OutputError> {
        let target = self.dir.join(name);
        let temp = self
            .entries
            .iter()
            .find(|(_, t)| *t == target)
            .map(|(temp, _)| temp.as_path())
            .ok_or_else(|| {
                OutputError::io(
                    &target,
                    std::io::Error::other("not one of the run's prepared output files"),
                )
            })?;
        let mut record = self.record.lock().unwrap_or_else(|e| e.into_inner());
        if record.is_none() {
            *record = Some(RunRecord::write(&self.dir, &self.names)?);
        }
        Ok(temp)
    }

    /// The final paths, in the order they were prepared.
    pub fn targets(&self) -> impl Iterator<Item = &Path> {
        self.entries.iter().map(|(_, target)| target.as_path())
    }

    /// Flushes every temporary file to disk, then, holding the directory's lock, checks
    /// the targets again (something may have appeared there while the run rendered), marks
    /// the set complete in its record and renames each file over its target. Returns the
    /// targets. Until this is called nothing in the directory but the temporary files and
    /// the record changed; a run killed among the renames has its set completed by the next
    /// run into the directory.
    pub fn commit(mut self) -> Result<Vec<PathBuf>, OutputError> {
        for (temp, _) in &self.entries {
            File::open(temp)
                .and_then(|f| f.sync_all())
                .map_err(|e| OutputError::io(temp, e))?;
        }
        let _lock = DirLock::acquire(&self.dir)?;
        for (_, target) in &self.entries {
            check_replaceable(target)?;
        }
        abort_if_asked("before-commit");
        let record = self.record.get_mut().unwrap_or_else(|e| e.into_inner());
        if let Some(record) = record.as_mut() {
            record.begin_commit()?;
        }
        for (i, (temp, target)) in self.entries.iter().enumerate() {
            if let Err(e) = std::fs::rename(temp, target) {
                self.state = State::LeftToComplete;
                let why = format!(
                    "{e}; the files of this run that are not in place yet stay, and the next \
                     run into {} renames them into place",
                    self.dir.display()
                );
                return Err(OutputError::io(target, std::io::Error::new(e.kind(), why)));
            }
            if i == 0 {
                abort_if_asked("between-renames");
            }
        }
        // The renames themselves reach the disk with the directory.
        sync_dir(&self.dir);
        self.state = State::Committed;
        if let Some(record) = self
            .record
            .get_mut()
            .unwrap_or_else(|e| e.into_inner())
            .take()
        {
            record.remove()?;
        }
        Ok(self.entries.iter().map(|(_, t)| t.clone()).collect())
    }
}

impl Drop for StagedFiles {
    fn drop(&mut self) {
        if self.state != State::Staging {
            return;
        }
        for (temp, _) in &self.entries {
            let _ = std::fs::remove_file(temp);
        }
        if let Some(record) = self
            .record
            .get_mut()
            .unwrap_or_else(|e| e.into_inner())
            .take()
        {
            let _ = record.remove();
        }
    }
}

/// Finishes, under the directory's lock, what runs killed in `dir` left (their temporary
/// files removed, or a commit killed among its renames completed), and says what on stderr.
fn sweep(dir: &Path) -> Result<(), OutputError> {
    let _lock = DirLock::acquire(dir)?;
    for note in recover(dir)? {
        eprintln!("note: {note}");
    }
    Ok(())
}

/// Writes `bytes` to `path` through a temporary file and a rename: a failure leaves any
/// previous file at `path` as it was.
pub fn write_file_atomically(path: &Path, bytes: &[u8]) -> Result<(), OutputError> {
    write_through_temp(path, |temp| {
        std::fs::write(temp, bytes).map_err(|e| OutputError::io(temp, e))
    })
}

/// `write` fills a temporary file beside `path`, which is then renamed over it as a run's
/// outputs are (a regular file or nothing is replaced; see `StagedFiles`).
pub fn write_through_temp(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<(), OutputError>,
) -> Result<(), OutputError> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let name = path
        .file_name()
        .and_then(|n| n.to_str())
        .filter(|n| !n.starts_with('.'))
        .ok_or_else(|| {
            OutputError::io(
                path,
                std::io::Error::other("not a plain, visible file name"),
            )
        })?
        .to_owned();
    let staged = StagedFiles::prepare(dir, std::slice::from_ref(&name))?;
    write(staged.temp_path(&name)?)?;
    staged.commit().map(|_| ())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::tests::temp_path;

    #[test]
    fn nothing_changes_until_commit_and_a_failed_run_leaves_nothing() {
        let dir = temp_path("staged");
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("a.png"), b"old a").unwrap();
        let names = ["a.png".to_string(), "b.exr".to_string()];
        let staged = StagedFiles::prepare(&dir, &names).unwrap();
        std::fs::write(staged.temp_path("a.png").unwrap(), b"new a").unwrap();
        assert_eq!(std::fs::read(dir.join("a.png")).unwrap(), b"old a");
        drop(staged); // the run failed before b.exr was written
        let left: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .flatten()
            .map(|e| e.file_name())
            .collect();
        assert_eq!(left, ["a.png"]);
        assert_eq!(std::fs::read(dir.join("a.png")).unwrap(), b"old a");

        let staged = StagedFiles::prepare(&dir, &names).unwrap();
        for name in &names {
            std::fs::write(staged.temp_path(name).unwrap(), name.as_bytes()).unwrap();
        }
        let written = staged.commit().unwrap();
        assert_eq!(written, [dir.join("a.png"), dir.join("b.exr")]);
        assert_eq!(std::fs::read(dir.join("a.png")).unwrap(), b"a.png");
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 2);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_directory_in_the_way_and_path_names_are_refused_up_front() {
        let dir = temp_path("staged-dir");
        std::fs::create_dir_all(dir.join("x.png")).unwrap();
        let e = StagedFiles::prepare(&dir, &["y.exr".into(), "x.png".into()])
            .err()
            .unwrap();
        assert!(
            e.to_string().contains("x.png") && e.to_string().contains("directory"),
            "{e}"
        );
        // The temporary file of y.exr, made before x.png was refused, is gone again.
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
        for bad in ["../up.png", "/abs.png", ".hidden.png", "a/b.png"] {
            assert!(
                StagedFiles::prepare(&dir, &[bad.to_string()]).is_err(),
                "{bad}"
            );
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
