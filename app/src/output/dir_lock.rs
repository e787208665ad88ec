//! A lock on an output directory while a run renames its file set into place, so two runs
//! writing the same names never leave one's EXR beside the other's PNG: each set is
//! committed whole before the other starts. The lock is flock(2) on the directory itself,
//! so no lock file is left in it and a killed run's lock goes with its process. Where there
//! is no flock (not Unix), the commit is not locked.

#[cfg(unix)]
use std::fs::File;
use std::path::Path;

use super::OutputError;

/// Held until dropped.
pub(crate) struct DirLock {
    #[cfg(unix)]
    _dir: File,
}

impl DirLock {
    /// Takes the lock on `dir`, waiting while another run holds it (a commit is a few
    /// renames, so the wait is short); says so on stderr while it waits.
    pub(crate) fn acquire(dir: &Path) -> Result<Self, OutputError> {
        #[cfg(unix)]
        {
            use std::os::fd::AsRawFd as _;
            let file = File::open(dir).map_err(|e| OutputError::io(dir, e))?;
            let fd = file.as_raw_fd();
            // SAFETY: flock on a descriptor this function owns; no memory is involved.
            if unsafe { libc::flock(fd, libc::LOCK_EX | libc::LOCK_NB) } != 0 {
                let busy = std::io::Error::last_os_error();
                if busy.raw_os_error() != Some(libc::EWOULDBLOCK) {
                    return Err(OutputError::io(dir, busy));
                }
                eprintln!(
                    "note: waiting for another run to finish writing its files into {}",
                    dir.display()
                );
                loop {
                    // SAFETY: as above.
                    if unsafe { libc::flock(fd, libc::LOCK_EX) } == 0 {
                        break;
                    }
                    let e = std::io::Error::last_os_error();
                    if e.kind() != std::io::ErrorKind::Interrupted {
                        return Err(OutputError::io(dir, e));
                    }
                }
            }
            Ok(Self { _dir: file })
        }
        #[cfg(not(unix))]
        {
            let _ = dir;
            Ok(Self {})
        }
    }
}
