//! False-colour pictures of the per-pixel error against a reference, with a colour bar, and
//! the small 8-bit RGB canvas the comparison pictures are drawn on.

use super::font::{GLYPH_HEIGHT, draw_text, text_width};
use super::{CompareError, check_data, check_pair};
use crate::output::{RadianceImage, encode_srgb8, expected_len, luminance};

/// A display-ready picture: 8-bit sRGB, 3 bytes per pixel, row-major with the top row first
/// (the layout [`crate::output::write_rgb8_png`] takes).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Rgb8Image {
    pub width: u32,
    pub height: u32,
    pub data: Vec<u8>,
}

impl Rgb8Image {
    /// A black `width` x `height` picture.
    ///
    /// Panics, like any allocation, when the size does not fit in memory.
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            data: vec![0; expected_len(width, height, 3)],
        }
    }

    /// `image` scaled by `2^exposure` and encoded to sRGB as by [`encode_srgb8`], for laying
    /// rendered pictures out next to error pictures.
    pub fn from_radiance(image: &RadianceImage, exposure: f32) -> Result<Self, CompareError> {
        check_data("image", image)?;
        Ok(Self {
            width: image.width,
            height: image.height,
            data: encode_srgb8(image, exposure),
        })
    }

    /// Byte offset of pixel (`x`, `y`), or `None` outside the picture. Also `None` when
    /// `data` (a public field) is shorter than the size says, so a malformed picture never
    /// makes drawing panic.
    fn offset(&self, x: u32, y: u32) -> Option<usize> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = (y as usize * self.width as usize + x as usize) * 3;
        (i + 3 <= self.data.len()).then_some(i)
    }

    /// Sets pixel (`x`, `y`); does nothing outside the picture, so drawing code may run off
    /// the edges without checking.
    pub fn put(&mut self, x: u32, y: u32, color: [u8; 3]) {
        if let Some(i) = self.offset(x, y) {
            self.data[i..i + 3].copy_from_slice(&color);
        }
    }

    /// Pixel (`x`, `y`), or `None` outside the picture.
    pub fn get(&self, x: u32, y: u32) -> Option<[u8; 3]> {
        self.offset(x, y)
            .map(|i| [self.data[i], self.data[i + 1], self.data[i + 2]])
    }

    /// Fills the `width` x `height` rectangle with top-left corner (`x`, `y`), clipped to
    /// the picture.
    pub fn fill_rect(&mut self, x: u32, y: u32, width: u32, height: u32, color: [u8; 3]) {
        let x_end = x.saturating_add(width).min(self.width);
        let y_end = y.saturating_add(height).min(self.height);
        for py in y..y_end {
            for px in x..x_end {
                self.put(px, py, color);
            }
        }
    }

    /// Copies `other` with its top-left corner at (`x`, `y`), clipped to this picture.
    pub fn blit(&mut self, other: &Rgb8Image, x: u32, y: u32) {
        for oy in 0..other.height {
            let Some(ty) = y.checked_add(oy).filter(|&ty| ty < self.height) else {
                break;
            };
            for ox in 0..other.width {
                let Some(tx) = x.checked_add(ox).filter(|&tx| tx < self.width) else {
                    break;
                };
                if let Some(color) = other.get(ox, oy) {
                    self.put(tx, ty, color);
                }
            }
        }
    }
}

/// Control points of the colormap: matplotlib's "inferno" (sRGB) sampled at ten evenly
/// spaced positions. Inferno is perceptually uniform and its lightness rises monotonically,
/// so a brighter colour always means a larger error, also in greyscale print.
const INFERNO: [[u8; 3]; 10] = [
    [0, 0, 4],
    [27, 12, 65],
    [74, 12, 107],
    [120, 28, 109],
    [165, 44, 96],
    [207, 68, 70],
    [237, 105, 37],
    [251, 155, 6],
    [247, 209, 61],
    [252, 255, 164],
];

/// The "inferno" colour of `t` in [0, 1] (clamped), by linear interpolation between the
/// control points. NaN gives the colour of 1 so that a NaN error, a rendering bug, stands
/// out instead of passing for a perfect match.
pub fn inferno(t: f32) -> [u8; 3] {
    // Each channel lies between two bytes, so the cast cannot truncate.
    inferno_unrounded(t).map(|c| c.round() as u8)
}

/// [`inferno`] before rounding to bytes, in byte units.
fn inferno_unrounded(t: f32) -> [f32; 3] {
    let t = if t.is_nan() { 1.0 } else { t.clamp(0.0, 1.0) };
    let segments = INFERNO.len() - 1;
    let pos = t * segments as f32;
    // `pos` is within [0, segments], so the cast cannot truncate; the last point belongs to
    // the last segment.
    let i = (pos as usize).min(segments - 1);
    let frac = pos - i as f32;
    let (a, b) = (INFERNO[i], INFERNO[i + 1]);
    std::array::from_fn(|c| f32::from(a[c]) + (f32::from(b[c]) - f32::from(a[c])) * frac)
}

/// Gap in pixels between the error picture, the colour bar and its labels.
const GAP: u32 = 4;
/// Width in pixels of the colour bar.
const BAR_WIDTH: u32 = 24;
/// Fill of the area around the colour bar: dark grey rather than black, so that the bar's
/// black zero end is still visible against it.
const PANEL_BACKGROUND: [u8; 3] = [40, 40, 40];
const LABEL_COLOR: [u8; 3] = [255, 255, 255];

/// `value` with 3 significant digits: fixed point from 0.001 to below 1000 ("0.0123",
/// "1.50", "250"), scientific otherwise ("1.23e4"), "0" for zero.
fn format_3_significant(value: f32) -> String {
    let value = f64::from(value);
    if value == 0.0 || !value.is_finite() {
        return format!("{value}");
    }
    // Round first, then choose the decimals: 9.996 must become "10.0", not "10.00".
    let exponent = value.abs().log10().floor();
    let step = 10f64.powf(exponent - 2.0);
    let rounded = (value / step).round() * step;
    let exponent = rounded.abs().log10().floor();
    if (-3.0..3.0).contains(&exponent) {
        // Within [-3, 3), so the cast cannot truncate.
        let decimals = (2.0 - exponent).max(0.0) as usize;
        format!("{rounded:.decimals$}")
    } else {
        format!("{rounded:.2e}")
    }
}

/// False-colour picture of the absolute luminance error `|L(image) - L(reference)|` per
/// pixel, as a [`heat_map`] from 0 to `max_error`.
pub fn error_image(
    image: &RadianceImage,
    reference: &RadianceImage,
    max_error: f32,
) -> Result<Rgb8Image, CompareError> {
    check_pair(image, reference)?;
    let errors: Vec<f32> = image
        .rgb
        .chunks_exact(3)
        .zip(reference.rgb.chunks_exact(3))
        .map(|(a, b)| (luminance([a[0], a[1], a[2]]) - luminance([b[0], b[1], b[2]])).abs())
        .collect();
    heat_map(&errors, image.width, image.height, max_error)
}

/// False-colour picture of one value per pixel (row-major, top row first), mapped through
/// [`inferno`] from 0 (black) to `max_value` (pale yellow; larger values are clamped), with a
/// colour bar on the right labelled "0" at the bottom and `max_value` (3 significant digits)
/// at the top.
///
/// The picture occupies columns `0..width` and rows `0..height` of the result; the bar and
/// labels follow to the right on a dark grey background. Very short images get a taller
/// result (the rows below the picture dark grey) so that both labels fit.
pub fn heat_map(
    values: &[f32],
    width: u32,
    height: u32,
    max_value: f32,
) -> Result<Rgb8Image, CompareError> {
    let expected = width as usize * height as usize;
    if values.len() != expected {
        return Err(CompareError::DataLength {
            which: "heat map values",
            width,
            height,
            expected,
            actual: values.len(),
        });
    }
    if !(max_value.is_finite() && max_value > 0.0) {
        return Err(CompareError::MaxError(max_value));
    }

    // Large labels for ordinary pictures, small ones where they would crowd a tiny image.
    let scale = if height >= 96 { 2 } else { 1 };
    let top_label = format_3_significant(max_value);
    let label_width = text_width(&top_label, scale).max(text_width("0", scale));
    let glyph_height = GLYPH_HEIGHT * scale;
    let out_height = height.max(2 * glyph_height + GAP);
    let bar_x = width.saturating_add(GAP);
    let label_x = bar_x.saturating_add(BAR_WIDTH + GAP);
    let out_width = label_x.saturating_add(label_width + GAP);

    let mut out = Rgb8Image::new(out_width, out_height);
    out.fill_rect(0, 0, out_width, out_height, PANEL_BACKGROUND);
    let columns = (0..height).flat_map(|y| (0..width).map(move |x| (x, y)));
    for ((x, y), v) in columns.zip(values) {
        out.put(x, y, inferno(v / max_value));
    }

    // Bottom row exactly 0, top row exactly `max_value`, as the labels say.
    for y in 0..out_height {
        let t = (out_height - 1 - y) as f32 / (out_height - 1) as f32;
        out.fill_rect(bar_x, y, BAR_WIDTH, 1, inferno(t));
    }
    draw_text(&mut out, label_x, 0, &top_label, scale, LABEL_COLOR);
    draw_text(
        &mut out,
        label_x,
        out_height - glyph_height,
        "0",
        scale,
        LABEL_COLOR,
    );
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(width: u32, height: u32, rgb: impl Fn(u32, u32) -> [f32; 3]) -> RadianceImage {
        let mut data = Vec::new();
        for y in 0..height {
            for x in 0..width {
                data.extend_from_slice(&rgb(x, y));
            }
        }
        RadianceImage::new(width, height, data).unwrap()
    }

    /// Rec. 709 luminance of an sRGB colour in byte units, after decoding to linear light.
    fn display_luminance(c: [f32; 3]) -> f32 {
        let linear = |v: f32| {
            let v = v / 255.0;
            if v <= 0.04045 {
                v / 12.92
            } else {
                ((v + 0.055) / 1.055).powf(2.4)
            }
        };
        luminance([linear(c[0]), linear(c[1]), linear(c[2])])
    }

    #[test]
    fn identical_images_are_the_zero_colour() {
        let a = image(37, 21, |x, y| [x as f32 * 0.1, y as f32, 0.5]);
        let out = error_image(&a, &a, 0.5).unwrap();
        let zero = inferno(0.0);
        assert_eq!(zero, [0, 0, 4]);
        for y in 0..a.height {
            for x in 0..a.width {
                assert_eq!(out.get(x, y), Some(zero), "({x}, {y})");
            }
        }
    }

    #[test]
    fn colormap_lightness_increases_with_the_error() {
        let bytes = |t: f32| inferno(t).map(f32::from);
        // The interpolated colours, densely: strictly increasing.
        let mut last = display_luminance(inferno_unrounded(0.0));
        for i in 1..=10_000 {
            let t = i as f32 / 10_000.0;
            let l = display_luminance(inferno_unrounded(t));
            assert!(l > last, "luminance drops at t = {t}");
            last = l;
        }
        // The bytes at 256 levels (what an 8-bit picture can resolve): never decreasing.
        // Finer steps may wobble by a rounding step where one channel falls while the
        // others rise, which no 8-bit colormap with such segments can avoid.
        let mut last = display_luminance(bytes(0.0));
        for i in 1..=255 {
            let t = i as f32 / 255.0;
            let l = display_luminance(bytes(t));
            assert!(l >= last, "8-bit luminance drops at t = {t}");
            last = l;
        }
        assert!(last > display_luminance(bytes(0.0)) + 0.8);
        assert!(INFERNO.windows(2).all(|w| {
            display_luminance(w[0].map(f32::from)) < display_luminance(w[1].map(f32::from))
        }));
    }

    #[test]
    fn errors_map_through_the_scale_and_bar() {
        let reference = image(4, 100, |_, _| [1.0; 3]);
        // Column x has a luminance error of x * 0.5 (grey offsets keep luminance exact).
        let test = image(4, 100, |x, _| [1.0 + x as f32 * 0.5; 3]);
        let out = error_image(&test, &reference, 1.0).unwrap();
        assert_eq!(out.get(0, 50), Some(inferno(0.0)));
        assert_eq!(out.get(1, 50), Some(inferno(0.5)));
        assert_eq!(out.get(2, 50), Some(inferno(1.0)));
        // Clamped above the maximum.
        assert_eq!(out.get(3, 50), Some(inferno(1.0)));

        let bar_x = 4 + GAP;
        assert_eq!(out.get(bar_x, 0), Some(inferno(1.0)));
        assert_eq!(out.get(bar_x + BAR_WIDTH - 1, 99), Some(inferno(0.0)));
        assert_eq!(out.height, 100);
        assert_eq!(
            out.width,
            bar_x + BAR_WIDTH + GAP + text_width("1.00", 2) + GAP
        );
        // The labels drew something white right of the bar, at the top and at the bottom.
        let white_in_rows = |rows: std::ops::Range<u32>| {
            rows.flat_map(|y| (bar_x + BAR_WIDTH..out.width).map(move |x| (x, y)))
                .any(|(x, y)| out.get(x, y) == Some(LABEL_COLOR))
        };
        assert!(white_in_rows(0..14));
        assert!(white_in_rows(86..100));
    }

    #[test]
    fn tiny_images_get_room_for_the_labels() {
        let a = image(2, 1, |_, _| [0.0; 3]);
        let out = error_image(&a, &a, 2.0).unwrap();
        assert_eq!(out.height, 2 * GLYPH_HEIGHT + GAP);
        assert_eq!(out.get(0, 0), Some(inferno(0.0)));
        assert_eq!(out.get(0, 1), Some(PANEL_BACKGROUND));
    }

    #[test]
    fn bad_inputs_are_errors() {
        let a = image(4, 3, |_, _| [0.0; 3]);
        let b = image(3, 4, |_, _| [0.0; 3]);
        assert!(matches!(
            error_image(&a, &b, 1.0),
            Err(CompareError::SizeMismatch { .. })
        ));
        for bad in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            assert!(matches!(
                error_image(&a, &a, bad),
                Err(CompareError::MaxError(_))
            ));
        }
        let mut short = a.clone();
        short.rgb.truncate(5);
        assert!(matches!(
            Rgb8Image::from_radiance(&short, 0.0),
            Err(CompareError::DataLength { .. })
        ));
    }

    #[test]
    fn three_significant_digits() {
        assert_eq!(format_3_significant(0.0), "0");
        assert_eq!(format_3_significant(1.0), "1.00");
        assert_eq!(format_3_significant(0.0123456), "0.0123");
        assert_eq!(format_3_significant(12.345), "12.3");
        assert_eq!(format_3_significant(250.0), "250");
        assert_eq!(format_3_significant(9.996), "10.0");
        assert_eq!(format_3_significant(12345.0), "1.23e4");
        assert_eq!(format_3_significant(0.00012345), "1.23e-4");
    }

    #[test]
    fn canvas_operations_clip() {
        let mut canvas = Rgb8Image::new(5, 4);
        canvas.put(5, 0, [1, 2, 3]);
        assert_eq!(canvas.get(5, 0), None);
        canvas.fill_rect(3, 2, 10, 10, [9, 9, 9]);
        assert_eq!(canvas.get(4, 3), Some([9, 9, 9]));
        assert_eq!(canvas.get(2, 3), Some([0, 0, 0]));
        let mut patch = Rgb8Image::new(3, 3);
        patch.fill_rect(0, 0, 3, 3, [7, 7, 7]);
        canvas.blit(&patch, 3, 3);
        canvas.blit(&patch, u32::MAX, 0);
        assert_eq!(canvas.get(4, 3), Some([7, 7, 7]));
        assert_eq!(canvas.get(3, 2), Some([9, 9, 9]));
        assert_eq!(canvas.data.len(), 5 * 4 * 3);
    }
}
