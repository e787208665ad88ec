//! What an output may replace: nothing, or a regular file. Renaming a staged file over a
//! path replaces whatever is there, so a device node (`--out /dev/null` run as root would
//! replace the system's), a FIFO, a socket or a symbolic link (such as `/dev/stdout`) would
//! be destroyed rather than written to. Such targets are refused, naming the path; the
//! user can remove them or choose another path.

use std::path::Path;

use super::OutputError;

/// Ok when `target` does not exist or is a regular file (not followed if it is a link).
pub(crate) fn check_replaceable(target: &Path) -> Result<(), OutputError> {
    let kind = match std::fs::symlink_metadata(target) {
        Ok(meta) if meta.file_type().is_file() => return Ok(()),
        Ok(meta) => kind_name(&meta.file_type()),
        // Absent: nothing is replaced. Any other error shows again when the file is written.
        Err(_) => return Ok(()),
    };
    let reason = if kind == "a directory" {
        // The wording the earlier check used, which scripts and tests may match.
        "is a directory; it would not be replaced by the image".to_owned()
    } else {
        format!(
            "is {kind}, not a regular file; outputs only replace regular files, so it is left \
             as it is (remove it or choose another path)"
        )
    };
    Err(OutputError::io(target, std::io::Error::other(reason)))
}

fn kind_name(file_type: &std::fs::FileType) -> &'static str {
    if file_type.is_dir() {
        return "a directory";
    }
    if file_type.is_symlink() {
        return "a symbolic link";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt as _;
        if file_type.is_char_device() {
            return "a character device";
        }
        if file_type.is_block_device() {
            return "a block device";
        }
        if file_type.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if file_type.is_socket() {
            return "a socket";
        }
    }
    "not a regular file"
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regular_files_and_absent_paths_may_be_replaced_the_rest_not() {
        let dir = crate::output::tests::temp_path("target");
        std::fs::create_dir_all(&dir).unwrap();
        assert!(check_replaceable(&dir.join("absent.png")).is_ok());
        std::fs::write(dir.join("file.png"), b"x").unwrap();
        assert!(check_replaceable(&dir.join("file.png")).is_ok());
        let e = check_replaceable(&dir).unwrap_err().to_string();
        assert!(e.contains("is a directory"), "{e}");
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(dir.join("file.png"), dir.join("link.png")).unwrap();
            let e = check_replaceable(&dir.join("link.png"))
                .unwrap_err()
                .to_string();
            assert!(e.contains("link.png") && e.contains("symbolic link"), "{e}");
            let e = check_replaceable(Path::new("/dev/null"))
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("/dev/null") && e.contains("character device"),
                "{e}"
            );
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
