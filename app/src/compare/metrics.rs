//! Error metrics of a picture against a reference of the same scene.

use serde::Serialize;

use super::{CompareError, check_pair};
use crate::output::RadianceImage;

/// Root mean square error over all three channels of the pixels selected by `mask` (all
/// pixels when `None`), accumulated in f64.
///
/// `mask` has one entry per pixel in the images' order (row-major, top row first). A NaN or
/// infinite channel makes the result NaN or infinite: such a value is a rendering bug that the
/// metric must not hide.
pub fn rmse(
    image: &RadianceImage,
    reference: &RadianceImage,
    mask: Option<&[bool]>,
) -> Result<f64, CompareError> {
    check_pair(image, reference)?;
    let pixels = image.rgb.len() / 3;
    if pixels == 0 {
        return Err(CompareError::EmptyImage {
            width: image.width,
            height: image.height,
        });
    }
    if let Some(mask) = mask {
        if mask.len() != pixels {
            return Err(CompareError::MaskLength {
                mask_len: mask.len(),
                pixels,
            });
        }
    }

    let selected = |i: usize| mask.is_none_or(|m| m[i]);
    let mut sum = 0.0f64;
    let mut count = 0usize;
    for (i, (a, b)) in image
        .rgb
        .chunks_exact(3)
        .zip(reference.rgb.chunks_exact(3))
        .enumerate()
    {
        if !selected(i) {
            continue;
        }
        count += 1;
        for c in 0..3 {
            let d = f64::from(a[c]) - f64::from(b[c]);
            sum += d * d;
        }
    }
    if count == 0 {
        return Err(CompareError::EmptyMask { pixels });
    }
    Ok((sum / (3 * count) as f64).sqrt())
}

/// Peak signal-to-noise ratio in dB, `20 log10(peak / rmse)`; `f64::INFINITY` for a perfect
/// match (`rmse == 0`), where the formula would divide by zero.
pub fn psnr(rmse: f64, peak: f64) -> f64 {
    if rmse == 0.0 {
        return f64::INFINITY;
    }
    20.0 * (peak / rmse).log10()
}

/// The peak value for PSNR on HDR radiance: the 99.9th percentile (nearest rank) of all the
/// reference's channel values.
///
/// Radiance has no fixed white level such as 1.0 or 255, and its maximum is decided by a few
/// very bright pixels (the lit spot under the light, specular highlights, sampling
/// fireflies). Using the maximum would let those few pixels set the PSNR scale, so two
/// renders of the same quality could differ by several dB. The 99.9th percentile follows the
/// brightness of the bulk of the picture and ignores the brightest 0.1%.
///
/// Non-finite values are ignored. When no positive percentile exists (an empty or black
/// reference) the result is 1.0, the display white level, so PSNR stays finite and defined.
pub fn peak_radiance(reference: &RadianceImage) -> f64 {
    let mut values: Vec<f32> = reference
        .rgb
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .collect();
    if values.is_empty() {
        return 1.0;
    }
    // Nearest rank: the smallest value with at least 99.9% of the values at or below it.
    let rank = ((values.len() as f64 * 0.999).ceil() as usize).clamp(1, values.len()) - 1;
    let (_, &mut peak, _) = values.select_nth_unstable_by(rank, f32::total_cmp);
    if peak > 0.0 { f64::from(peak) } else { 1.0 }
}

/// Errors of one picture against the reference, as reported by `motion-shadows compare`.
///
/// Both PSNRs use the same peak ([`peak_radiance`] of the reference), so the whole-image
/// and masked figures are on one scale. serde_json writes an infinite PSNR (a perfect match)
/// as `null`.
#[derive(Debug, Clone, Serialize)]
pub struct ErrorStats {
    pub rmse: f64,
    pub psnr_db: f64,
    /// RMSE over the masked pixels only; `None` when no mask was given.
    pub rmse_masked: Option<f64>,
    pub psnr_masked_db: Option<f64>,
    /// How many pixels the mask selects; 0 when no mask was given.
    pub masked_pixels: usize,
}

/// Whole-image and (with a mask) masked RMSE and PSNR of `image` against `reference`.
pub fn error_stats(
    image: &RadianceImage,
    reference: &RadianceImage,
    mask: Option<&[bool]>,
) -> Result<ErrorStats, CompareError> {
    let all = rmse(image, reference, None)?;
    let peak = peak_radiance(reference);
    let masked = mask.map(|m| rmse(image, reference, Some(m))).transpose()?;
    Ok(ErrorStats {
        rmse: all,
        psnr_db: psnr(all, peak),
        rmse_masked: masked,
        psnr_masked_db: masked.map(|r| psnr(r, peak)),
        masked_pixels: mask.map_or(0, |m| m.iter().filter(|&&b| b).count()),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn constant(width: u32, height: u32, value: f32) -> RadianceImage {
        RadianceImage {
            width,
            height,
            rgb: vec![value; (width * height * 3) as usize],
        }
    }

    #[test]
    fn identical_images_have_zero_error() {
        let a = RadianceImage {
            width: 3,
            height: 2,
            rgb: (0..18).map(|i| i as f32 * 0.37).collect(),
        };
        assert_eq!(rmse(&a, &a, None).unwrap(), 0.0);
        let stats = error_stats(&a, &a, None).unwrap();
        assert_eq!(stats.psnr_db, f64::INFINITY);
    }

    #[test]
    fn constant_offset_is_the_rmse() {
        // 0.75 - 0.5 = 0.25 is exact in binary, so the result must be exact too.
        let reference = constant(4, 3, 0.5);
        let image = constant(4, 3, 0.75);
        assert_eq!(rmse(&image, &reference, None).unwrap(), 0.25);
    }

    #[test]
    fn mask_restricts_to_the_differing_pixels() {
        // 10 pixels, of which 2 differ by 0.5 in every channel.
        let reference = constant(5, 2, 1.0);
        let mut image = reference.clone();
        let mut mask = vec![false; 10];
        for p in [3usize, 7] {
            image.rgb[3 * p..3 * p + 3].fill(1.5);
            mask[p] = true;
        }
        let masked = rmse(&image, &reference, Some(&mask)).unwrap();
        assert_eq!(masked, 0.5);
        let all = rmse(&image, &reference, None).unwrap();
        assert!((all - 0.5 * 0.2f64.sqrt()).abs() < 1e-12, "{all}");

        let stats = error_stats(&image, &reference, Some(&mask)).unwrap();
        assert_eq!(stats.masked_pixels, 2);
        assert_eq!(stats.rmse_masked, Some(0.5));
        // The peak comes from the reference, which is 1.0 everywhere: 1.0 / 0.5 = 2.
        let expected = 20.0 * 2.0f64.log10();
        assert!((stats.psnr_masked_db.unwrap() - expected).abs() < 1e-9);
    }

    #[test]
    fn psnr_of_known_values() {
        assert!((psnr(0.1, 1.0) - 20.0).abs() < 1e-12);
        assert!((psnr(1.0, 100.0) - 40.0).abs() < 1e-12);
        assert_eq!(psnr(0.0, 1.0), f64::INFINITY);
    }

    #[test]
    fn peak_ignores_the_brightest_tenth_of_a_percent() {
        // 3000 values of 1.0 and one outlier: the outlier is above the 99.9th percentile.
        let mut reference = constant(1000, 1, 1.0);
        reference.rgb[17] = 1000.0;
        assert_eq!(peak_radiance(&reference), 1.0);
        assert_eq!(peak_radiance(&constant(2, 2, 0.0)), 1.0);
    }

    #[test]
    fn mismatches_are_errors() {
        let a = constant(4, 3, 0.0);
        let b = constant(3, 4, 0.0);
        let err = rmse(&a, &b, None).unwrap_err();
        assert!(matches!(err, CompareError::SizeMismatch { .. }));
        assert!(err.to_string().contains("4x3") && err.to_string().contains("3x4"));

        let err = rmse(&a, &a, Some(&[true; 11])).unwrap_err();
        assert_eq!(
            err,
            CompareError::MaskLength {
                mask_len: 11,
                pixels: 12
            }
        );
        let err = rmse(&a, &a, Some(&[false; 12])).unwrap_err();
        assert_eq!(err, CompareError::EmptyMask { pixels: 12 });
        assert!(error_stats(&a, &a, Some(&[false; 12])).is_err());

        let mut short = a.clone();
        short.rgb.pop();
        let err = rmse(&a, &short, None).unwrap_err();
        assert!(matches!(
            err,
            CompareError::DataLength {
                which: "reference",
                expected: 36,
                actual: 35,
                ..
            }
        ));

        let empty = constant(0, 5, 0.0);
        assert!(matches!(
            rmse(&empty, &empty, None),
            Err(CompareError::EmptyImage { .. })
        ));
    }
}
