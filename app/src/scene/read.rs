//! Reading a scene file or an OBJ model with a size bound. A regular file's size is checked
//! before a byte is read; a stream (a pipe, `/dev/stdin`, `/dev/zero`) reports no size, so
//! its reading stops one byte past the bound, and a directory is refused by name.

use std::io::Read;
use std::path::Path;

/// Why a bounded read failed; the caller wraps it with the file's role (scene, OBJ).
#[derive(Debug)]
pub(crate) enum ReadError {
    Io(std::io::Error),
    /// A directory, or (when streams are not allowed) a device, pipe or socket.
    NotAFile(&'static str),
    TooLarge {
        limit: u64,
        size: Option<u64>,
    },
}

impl std::fmt::Display for ReadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ReadError::Io(e) => write!(f, "{e}"),
            ReadError::NotAFile(kind) => write!(f, "is {kind}, not a regular file"),
            ReadError::TooLarge { limit, size } => {
                let mib = |b: u64| b as f64 / (1024.0 * 1024.0);
                match size {
                    Some(s) => write!(f, "is {:.1} MiB", mib(*s))?,
                    None => write!(f, "holds more than {:.0} MiB", mib(*limit))?,
                }
                write!(
                    f,
                    ", over the limit of {:.0} MiB (docs/scene-format.md, \"Limits\")",
                    mib(*limit)
                )
            }
        }
    }
}

/// The whole of `path`, at most `limit` bytes. `allow_streams`: whether a pipe or device
/// may be read (bounded); otherwise only regular files are.
pub(crate) fn read_bounded(
    path: &Path,
    limit: u64,
    allow_streams: bool,
) -> Result<Vec<u8>, ReadError> {
    let meta = std::fs::metadata(path).map_err(ReadError::Io)?;
    let kind = meta.file_type();
    if kind.is_dir() {
        return Err(ReadError::NotAFile("a directory"));
    }
    if kind.is_file() {
        if meta.len() > limit {
            return Err(ReadError::TooLarge {
                limit,
                size: Some(meta.len()),
            });
        }
    } else if !allow_streams {
        return Err(ReadError::NotAFile("a device, pipe or socket"));
    }
    let file = std::fs::File::open(path).map_err(ReadError::Io)?;
    // A regular file may have grown since its metadata was read, and a stream has no size:
    // the bound holds while reading too. One byte more than the limit tells "too large".
    let mut bytes = Vec::new();
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(ReadError::Io)?;
    if bytes.len() as u64 > limit {
        return Err(ReadError::TooLarge { limit, size: None });
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_bounded_and_directories_refused() {
        // /dev/zero never ends: reading stops one byte past the bound.
        match read_bounded(Path::new("/dev/zero"), 1000, true) {
            Err(ReadError::TooLarge {
                limit: 1000,
                size: None,
            }) => {}
            other => panic!("{other:?}"),
        }
        assert!(matches!(
            read_bounded(Path::new("/dev/zero"), 1000, false),
            Err(ReadError::NotAFile(_))
        ));
        let dir = std::env::temp_dir();
        let e = read_bounded(&dir, 1000, true).unwrap_err();
        assert!(e.to_string().contains("directory"), "{e}");
    }

    #[test]
    fn a_regular_file_over_the_bound_is_refused_by_its_size() {
        let path = std::env::temp_dir().join(format!("ms-read-{}.txt", std::process::id()));
        std::fs::write(&path, [b'x'; 2048]).unwrap();
        let too_large = read_bounded(&path, 1024, false).unwrap_err();
        let fits = read_bounded(&path, 2048, false).map(|b| b.len());
        std::fs::remove_file(&path).unwrap();
        match too_large {
            ReadError::TooLarge {
                size: Some(2048), ..
            } => {}
            other => panic!("{other:?}"),
        }
        assert_eq!(fits.unwrap(), 2048);
    }
}
