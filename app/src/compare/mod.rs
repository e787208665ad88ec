//! CPU tools for judging a method's picture against a reference of the same scene: error
//! metrics (RMSE, PSNR, optionally restricted to a mask such as the penumbra pixels), a
//! false-colour error picture with a colour bar, and labelled side-by-side layouts.
//!
//! Everything here works on finished images in host memory and needs no GPU, so the
//! comparison can be tested and rerun on saved EXRs.

mod false_color;
mod font;
mod layout;
mod mask_error;
mod metrics;

pub use self::false_color::{Rgb8Image, error_image, heat_map, inferno};
pub use self::font::{GLYPH_HEIGHT, GLYPH_WIDTH, draw_text, text_width};
pub use self::layout::{TITLE_BAR_HEIGHT, side_by_side};
pub use self::mask_error::{MaskError, mask_error, same_surface};
pub use self::metrics::{ErrorStats, error_stats, peak_radiance, psnr, rmse};

/// Why two images could not be compared.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CompareError {
    #[error(
        "image is {image_width}x{image_height} pixels but the reference is \
         {reference_width}x{reference_height}"
    )]
    SizeMismatch {
        image_width: u32,
        image_height: u32,
        reference_width: u32,
        reference_height: u32,
    },
    #[error("the {which} holds {actual} values, but {width}x{height} RGB needs {expected}")]
    DataLength {
        /// Which input is malformed: "image" or "reference".
        which: &'static str,
        width: u32,
        height: u32,
        expected: usize,
        actual: usize,
    },
    #[error("the mask has {mask_len} entries but the images have {pixels} pixels")]
    MaskLength { mask_len: usize, pixels: usize },
    #[error("the mask selects none of the {pixels} pixels")]
    EmptyMask { pixels: usize },
    #[error("the images are {width}x{height}: there is no pixel to compare")]
    EmptyImage { width: u32, height: u32 },
    #[error("the maximum error of the colour scale must be finite and positive, got {0}")]
    MaxError(f32),
}

use crate::output::{RadianceImage, expected_len};

/// Checks that `image` holds as many values as its size says. The fields of
/// [`RadianceImage`] are public, so it may have been built without its checking constructor;
/// checking here turns a malformed input into an error instead of an index panic.
fn check_data(which: &'static str, image: &RadianceImage) -> Result<(), CompareError> {
    let expected = expected_len(image.width, image.height, 3);
    if image.rgb.len() != expected {
        return Err(CompareError::DataLength {
            which,
            width: image.width,
            height: image.height,
            expected,
            actual: image.rgb.len(),
        });
    }
    Ok(())
}

/// Checks that `image` and `reference` are well formed and of the same size.
fn check_pair(image: &RadianceImage, reference: &RadianceImage) -> Result<(), CompareError> {
    if (image.width, image.height) != (reference.width, reference.height) {
        return Err(CompareError::SizeMismatch {
            image_width: image.width,
            image_height: image.height,
            reference_width: reference.width,
            reference_height: reference.height,
        });
    }
    check_data("image", image)?;
    check_data("reference", reference)
}
