//! Display-referred 8-bit sRGB PNG output.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

use image::codecs::png::PngEncoder;
use image::{ExtendedColorType, ImageEncoder, ImageError};

use super::{OutputError, RadianceImage, expected_len};

/// The exact sRGB opto-electronic transfer function (IEC 61966-2-1) of a value in [0, 1].
fn srgb_encode(linear: f64) -> f64 {
    if linear <= 0.003_130_8 {
        12.92 * linear
    } else {
        1.055 * linear.powf(1.0 / 2.4) - 0.055
    }
}

/// One channel: clamp to [0, 1], encode, round to the nearest of 256 levels. NaN gives 0,
/// because a NaN is a rendering bug and black makes it visible without spreading.
fn srgb8(linear: f64) -> u8 {
    let clamped = if linear.is_nan() {
        0.0
    } else {
        linear.clamp(0.0, 1.0)
    };
    // Cannot truncate: the encoded value is within [0, 1], so the product is within [0, 255].
    (srgb_encode(clamped) * 255.0).round() as u8
}

/// Converts linear radiance to 8-bit sRGB, 3 bytes per pixel in the image's pixel order.
///
/// Each channel is scaled by `2^exposure`, clamped to [0, 1] (negative values and -inf give
/// 0, +inf gives 255), put through the exact sRGB transfer function and rounded to nearest.
/// NaN channels give 0, as does a NaN exposure. The arithmetic is done in f64 so that the
/// result matches the textbook formula at the rounding boundaries.
pub fn encode_srgb8(image: &RadianceImage, exposure: f32) -> Vec<u8> {
    let scale = f64::from(exposure).exp2();
    image
        .rgb
        .iter()
        .map(|&v| srgb8(f64::from(v) * scale))
        .collect()
}

/// Writes `image` as an 8-bit sRGB PNG after scaling it by `2^exposure` (see
/// [`encode_srgb8`]).
pub fn write_png(path: &Path, image: &RadianceImage, exposure: f32) -> Result<(), OutputError> {
    image.check_len()?;
    write_rgb8_png(
        path,
        image.width,
        image.height,
        &encode_srgb8(image, exposure),
    )
}

/// Writes already display-ready RGB8 bytes (row-major, top row first) as a PNG, for pictures
/// that are not radiance, such as heat maps.
pub fn write_rgb8_png(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<(), OutputError> {
    let expected = expected_len(width, height, 3);
    if rgb.len() != expected {
        return Err(OutputError::Size {
            expected,
            actual: rgb.len(),
        });
    }
    let file = File::create(path).map_err(|e| OutputError::io(path, e))?;
    let mut writer = BufWriter::new(file);
    PngEncoder::new(&mut writer)
        .write_image(rgb, width, height, ExtendedColorType::Rgb8)
        .map_err(|e| match e {
            ImageError::IoError(source) => OutputError::io(path, source),
            other => OutputError::Png {
                path: path.to_path_buf(),
                message: other.to_string(),
            },
        })?;
    // Flushing explicitly because dropping a BufWriter discards write errors (e.g. disk full).
    writer.flush().map_err(|e| OutputError::io(path, e))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::tests::temp_path;

    /// The sRGB formula written out independently of the code under test.
    fn reference(linear: f64) -> u8 {
        let x = linear.clamp(0.0, 1.0);
        let s = if x <= 0.0031308 {
            x * 12.92
        } else {
            1.055 * x.powf(1.0 / 2.4) - 0.055
        };
        (s * 255.0).round() as u8
    }

    fn encode_one(v: f32, exposure: f32) -> u8 {
        let image = RadianceImage::new(1, 1, vec![v, v, v]).unwrap();
        let bytes = encode_srgb8(&image, exposure);
        assert_eq!(bytes[0], bytes[1]);
        assert_eq!(bytes[0], bytes[2]);
        bytes[0]
    }

    #[test]
    fn known_values() {
        assert_eq!(encode_one(0.0, 0.0), 0);
        assert_eq!(encode_one(1.0, 0.0), 255);
        // 1.055 * 0.5^(1/2.4) - 0.055 = 0.73536, times 255 = 187.52.
        assert_eq!(encode_one(0.5, 0.0), 188);
        assert_eq!(reference(0.5), 188);
        // Both sides of the linear/power split meet at 0.0404500 * 255 = 10.31.
        assert_eq!(encode_one(0.003_130_8, 0.0), 10);
        assert_eq!(encode_one(0.003_130_9, 0.0), 10);
        assert_eq!(encode_one(0.003_130_7, 0.0), 10);
        assert_eq!(encode_one(0.18, 0.0), 118);
    }

    #[test]
    fn matches_reference_formula() {
        for i in 0..=4096 {
            let v = i as f32 / 4096.0;
            assert_eq!(encode_one(v, 0.0), reference(f64::from(v)), "at {v}");
        }
    }

    #[test]
    fn out_of_range_and_nan() {
        assert_eq!(encode_one(-1.0, 0.0), 0);
        assert_eq!(encode_one(2.0, 0.0), 255);
        assert_eq!(encode_one(f32::INFINITY, 0.0), 255);
        assert_eq!(encode_one(f32::NEG_INFINITY, 0.0), 0);
        assert_eq!(encode_one(f32::NAN, 0.0), 0);
        assert_eq!(encode_one(0.5, f32::NAN), 0);
    }

    #[test]
    fn one_stop_doubles_radiance() {
        for i in 0..=1000 {
            let v = i as f32 / 2000.0;
            assert_eq!(encode_one(v, 1.0), encode_one(2.0 * v, 0.0), "at {v}");
            assert_eq!(encode_one(v, -1.0), encode_one(0.5 * v, 0.0), "at {v}");
        }
        assert_eq!(encode_one(0.25, 1.0), 188);
    }

    #[test]
    fn png_is_decodable_with_right_size() {
        let (width, height) = (5u32, 3u32);
        let rgb: Vec<f32> = (0..width * height * 3).map(|i| i as f32 / 45.0).collect();
        let image = RadianceImage::new(width, height, rgb).unwrap();
        let path = temp_path("picture.png");
        write_png(&path, &image, 0.0).unwrap();
        let decoded = image::open(&path).unwrap().to_rgb8();
        std::fs::remove_file(&path).unwrap();
        assert_eq!(decoded.dimensions(), (width, height));
        assert_eq!(decoded.into_raw(), encode_srgb8(&image, 0.0));
    }

    #[test]
    fn rgb8_png_wrong_length_is_size_error() {
        let path = temp_path("wrong.png");
        let err = write_rgb8_png(&path, 4, 4, &[0u8; 47]).unwrap_err();
        assert!(matches!(
            err,
            OutputError::Size {
                expected: 48,
                actual: 47
            }
        ));
        assert!(!path.exists());
    }

    #[test]
    fn unwritable_path_is_io_error_naming_path() {
        let path = temp_path("no_such_dir").join("x.png");
        let err = write_rgb8_png(&path, 1, 1, &[1, 2, 3]).unwrap_err();
        assert!(matches!(err, OutputError::Io { .. }));
        assert!(err.to_string().contains(&*path.to_string_lossy()));
    }
}
