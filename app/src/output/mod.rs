//! Writing rendered pictures to disk: linear radiance as 32-bit float OpenEXR, and
//! display-referred sRGB 8-bit PNG for quick viewing and for other pictures (heat maps).

mod dir_lock;
mod exr;
mod partials;
mod png;
mod run_record;
mod staged;
mod target;
mod test_abort;

use std::path::{Path, PathBuf};

pub use self::exr::{read_exr, write_exr};
pub use self::png::{encode_srgb8, write_png, write_rgb8_png};
pub use self::staged::{StagedFiles, write_file_atomically, write_through_temp};

/// Why a picture could not be written or read.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    // The reason is repeated in the text (not only in `source()`) because callers often print
    // errors with `{}`, which would otherwise hide why the file could not be opened.
    #[error("cannot access {}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("EXR error for {}: {message}", path.display())]
    Exr { path: PathBuf, message: String },
    #[error("PNG error for {}: {message}", path.display())]
    Png { path: PathBuf, message: String },
    #[error("pixel data has {actual} values, but the image size needs {expected}")]
    Size { expected: usize, actual: usize },
}

impl OutputError {
    pub(crate) fn io(path: &Path, source: std::io::Error) -> Self {
        Self::Io {
            path: path.to_path_buf(),
            source,
        }
    }
}

/// Number of values `width * height * channels` needs; `usize::MAX` when that does not fit,
/// which no real buffer can match, so an oversized image is reported as a size mismatch.
pub(crate) fn expected_len(width: u32, height: u32, channels: usize) -> usize {
    (width as usize)
        .checked_mul(height as usize)
        .and_then(|n| n.checked_mul(channels))
        .unwrap_or(usize::MAX)
}

/// Linear scene radiance, row-major with the top row first, 3 floats (R, G, B) per pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct RadianceImage {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<f32>,
}

impl RadianceImage {
    /// Wraps `rgb`, which must hold exactly `width * height * 3` floats.
    pub fn new(width: u32, height: u32, rgb: Vec<f32>) -> Result<Self, OutputError> {
        let image = Self { width, height, rgb };
        image.check_len()?;
        Ok(image)
    }

    /// The fields are public, so an image may have been built without `new`; writers call
    /// this before indexing pixels so a mismatch is an error rather than a panic.
    pub(crate) fn check_len(&self) -> Result<(), OutputError> {
        let expected = expected_len(self.width, self.height, 3);
        if self.rgb.len() != expected {
            return Err(OutputError::Size {
                expected,
                actual: self.rgb.len(),
            });
        }
        Ok(())
    }

    /// The pixel at column `x`, row `y` (row 0 is the top).
    pub fn pixel(&self, x: u32, y: u32) -> [f32; 3] {
        let i = (y as usize * self.width as usize + x as usize) * 3;
        [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
    }
}

/// Rec. 709 / sRGB relative luminance of a linear RGB triple.
pub fn luminance(rgb: [f32; 3]) -> f32 {
    0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]
}

/// Exposure in stops that maps the 99th percentile (nearest rank) of the luminance of the
/// lit pixels to 0.9, so a few highlights may clip but the picture is not dominated by them.
///
/// Pixels with zero, negative or non-finite luminance are ignored: shadowed background would
/// otherwise pull the percentile down. An image with no lit pixel gets 0.0.
pub fn auto_exposure(image: &RadianceImage) -> f32 {
    let mut lit: Vec<f32> = image
        .rgb
        .chunks_exact(3)
        .map(|p| luminance([p[0], p[1], p[2]]))
        .filter(|l| l.is_finite() && *l > 0.0)
        .collect();
    if lit.is_empty() {
        return 0.0;
    }
    // Nearest-rank percentile: the smallest value with at least 99% of samples at or below it.
    let rank = ((lit.len() as f64 * 0.99).ceil() as usize).clamp(1, lit.len()) - 1;
    let (_, &mut p99, _) = lit.select_nth_unstable_by(rank, f32::total_cmp);
    (0.9 / f64::from(p99)).log2() as f32
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// A fresh path in the system temp directory; unique per process and call so tests that
    /// run in parallel never share a file.
    pub(crate) fn temp_path(name: &str) -> PathBuf {
        static COUNTER: AtomicUsize = AtomicUsize::new(0);
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        std::env::temp_dir().join(format!(
            "motion-shadows-output-{}-{n}-{name}",
            std::process::id()
        ))
    }

    #[test]
    fn new_checks_length() {
        let err = RadianceImage::new(4, 3, vec![0.0; 35]).unwrap_err();
        assert!(matches!(
            err,
            OutputError::Size {
                expected: 36,
                actual: 35
            }
        ));
        assert!(RadianceImage::new(4, 3, vec![0.0; 36]).is_ok());
    }

    #[test]
    fn auto_exposure_of_black_is_zero() {
        let image = RadianceImage::new(3, 2, vec![0.0; 18]).unwrap();
        assert_eq!(auto_exposure(&image), 0.0);
    }

    #[test]
    fn auto_exposure_maps_p99_to_0_9() {
        // 200 lit grey pixels with luminance 1..=200 plus black ones that must be ignored.
        let mut rgb = Vec::new();
        for i in 1..=200 {
            let v = i as f32;
            rgb.extend_from_slice(&[v, v, v]);
        }
        rgb.extend(std::iter::repeat_n(0.0, 3 * 100));
        let image = RadianceImage::new(300, 1, rgb).unwrap();
        let exposure = auto_exposure(&image);
        // Nearest rank of 99% of 200 samples is the 198th smallest.
        let p99 = luminance([198.0, 198.0, 198.0]);
        assert!((p99 * exposure.exp2() - 0.9).abs() < 1e-4, "{exposure}");
    }

    #[test]
    fn error_text_names_path() {
        let err = OutputError::io(
            Path::new("/nowhere/x.exr"),
            std::io::Error::from(std::io::ErrorKind::NotFound),
        );
        assert!(err.to_string().contains("/nowhere/x.exr"));
    }
}
