//! OpenEXR output of linear radiance, 32-bit float RGB.

use std::fs::File;
use std::io::{BufReader, BufWriter, Write};
use std::path::Path;

use ::exr::prelude::{
    Blocks, Compression, Encoding, Image, Layer, LayerAttributes, LineOrder, ReadChannels,
    ReadLayers, SpecificChannels, Vec2, WritableImage,
};

use super::{OutputError, RadianceImage};

/// ZIP of 16-scanline blocks: lossless, about half the size of uncompressed float data, and
/// deterministic. Blocks are written in increasing order so that the parallel compressor
/// cannot reorder chunks between runs; the same input therefore gives the same bytes.
const ENCODING: Encoding = Encoding {
    compression: Compression::ZIP16,
    blocks: Blocks::ScanLines,
    line_order: LineOrder::Increasing,
};

fn exr_error(path: &Path, error: ::exr::error::Error) -> OutputError {
    match error {
        ::exr::error::Error::Io(source) => OutputError::io(path, source),
        other => OutputError::Exr {
            path: path.to_path_buf(),
            message: other.to_string(),
        },
    }
}

/// Writes `image` as a single-layer RGB EXR with 32-bit float channels and linear values.
pub fn write_exr(path: &Path, image: &RadianceImage) -> Result<(), OutputError> {
    image.check_len()?;
    let width = image.width as usize;
    let rgb = &image.rgb;
    let pixels = SpecificChannels::rgb(|pos: Vec2<usize>| {
        let i = (pos.y() * width + pos.x()) * 3;
        (rgb[i], rgb[i + 1], rgb[i + 2])
    });
    let layer = Layer::new(
        (width, image.height as usize),
        LayerAttributes::default(),
        ENCODING,
        pixels,
    );

    let file = File::create(path).map_err(|e| OutputError::io(path, e))?;
    let mut writer = BufWriter::new(file);
    Image::from_layer(layer)
        .write()
        .to_buffered(&mut writer)
        .map_err(|e| exr_error(path, e))?;
    // Flushing explicitly because dropping a BufWriter discards write errors (e.g. disk full).
    writer.flush().map_err(|e| OutputError::io(path, e))
}

/// Reads the R, G and B channels of the first layer of an EXR file, converted to f32.
pub fn read_exr(path: &Path) -> Result<RadianceImage, OutputError> {
    let file = File::open(path).map_err(|e| OutputError::io(path, e))?;
    let image = ::exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .rgb_channels(
            |resolution, _| (resolution, vec![0.0f32; resolution.area() * 3]),
            |(resolution, rgb): &mut (Vec2<usize>, Vec<f32>),
             pos: Vec2<usize>,
             (r, g, b): (f32, f32, f32)| {
                let i = (pos.y() * resolution.width() + pos.x()) * 3;
                rgb[i..i + 3].copy_from_slice(&[r, g, b]);
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_buffered(BufReader::new(file))
        .map_err(|e| exr_error(path, e))?;

    let (resolution, rgb) = image.layer_data.channel_data.pixels;
    let too_large = || OutputError::Exr {
        path: path.to_path_buf(),
        message: format!(
            "{}x{} pixels is too large",
            resolution.width(),
            resolution.height()
        ),
    };
    let width = u32::try_from(resolution.width()).map_err(|_| too_large())?;
    let height = u32::try_from(resolution.height()).map_err(|_| too_large())?;
    RadianceImage::new(width, height, rgb)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::tests::temp_path;

    fn test_image(width: u32, height: u32) -> RadianceImage {
        // Values that exercise the whole f32 range, including ones f16 could not hold, so a
        // lossy or half-float path would be caught.
        let rgb = (0..width * height * 3)
            .map(|i| match i % 7 {
                0 => 0.0,
                1 => 1.0e-8 * i as f32,
                2 => 123_456.79 + i as f32,
                3 => -0.5,
                4 => f32::from_bits(0x3f80_0001 + i),
                5 => 1.0 / 3.0,
                _ => i as f32 / 17.0,
            })
            .collect();
        RadianceImage::new(width, height, rgb).unwrap()
    }

    #[test]
    fn round_trip_is_bit_exact() {
        let image = test_image(37, 23);
        let path = temp_path("round_trip.exr");
        write_exr(&path, &image).unwrap();
        let back = read_exr(&path).unwrap();
        std::fs::remove_file(&path).unwrap();
        assert_eq!((back.width, back.height), (37, 23));
        let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&back.rgb), bits(&image.rgb));
    }

    #[test]
    fn same_input_gives_same_bytes() {
        // Large enough for many blocks, so parallel compression could reorder them.
        let image = test_image(640, 480);
        let (a, b) = (temp_path("det_a.exr"), temp_path("det_b.exr"));
        write_exr(&a, &image).unwrap();
        write_exr(&b, &image).unwrap();
        let (bytes_a, bytes_b) = (std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
        std::fs::remove_file(&a).unwrap();
        std::fs::remove_file(&b).unwrap();
        assert!(bytes_a == bytes_b, "two writes of the same image differ");
    }

    #[test]
    fn missing_file_is_io_error_naming_path() {
        let path = temp_path("does_not_exist.exr");
        let err = read_exr(&path).unwrap_err();
        assert!(matches!(err, OutputError::Io { .. }));
        assert!(err.to_string().contains(&*path.to_string_lossy()));
    }

    #[test]
    fn inconsistent_image_is_size_error() {
        let image = RadianceImage {
            width: 2,
            height: 2,
            rgb: vec![0.0; 5],
        };
        let path = temp_path("bad.exr");
        let err = write_exr(&path, &image).unwrap_err();
        assert!(matches!(
            err,
            OutputError::Size {
                expected: 12,
                actual: 5
            }
        ));
        assert!(!path.exists());
    }
}
