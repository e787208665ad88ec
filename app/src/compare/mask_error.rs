//! The error of a deferred frame's lit shares (its mask) against the truth's.

/// RMSE of lit shares against the truth's, over the pixels where the mask matters: a surface
/// the light reaches at the camera time but for shadows (elsewhere the mask multiplies
/// nothing). `shadowed`: those of them where either image is below 1 (penumbra, umbra, and
/// wrong shadows).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaskError {
    pub rmse: f64,
    pub pixels: usize,
    pub rmse_shadowed: f64,
    pub shadowed_pixels: usize,
}

/// Below this a lit share counts as shadowed (f32 rounding of a fully lit pixel stays above).
const SHADOWED_BELOW: f32 = 1.0 - 1e-4;

/// The error of `lit` against `truth` over the pixels `counted` marks (all three per pixel,
/// the same length).
pub fn mask_error(lit: &[f32], truth: &[f32], counted: &[bool]) -> MaskError {
    let (mut sum, mut pixels, mut sum_shadowed, mut shadowed) = (0.0, 0, 0.0, 0);
    for ((&l, &t), _) in lit.iter().zip(truth).zip(counted).filter(|(_, c)| **c) {
        let e = f64::from(l) - f64::from(t);
        sum += e * e;
        pixels += 1;
        if l < SHADOWED_BELOW || t < SHADOWED_BELOW {
            sum_shadowed += e * e;
            shadowed += 1;
        }
    }
    let root = |s: f64, n: usize| if n == 0 { 0.0 } else { (s / n as f64).sqrt() };
    MaskError {
        rmse: root(sum, pixels),
        pixels,
        rmse_shadowed: root(sum_shadowed, shadowed),
        shadowed_pixels: shadowed,
    }
}

/// Pixels where both see the same triangle, among those `counted` marks: there the two lit
/// shares belong to the same point (up to rounding), so their difference is the mask's own;
/// elsewhere (silhouettes, where rasterization and a ray may see different faces) it may be
/// the difference of two points.
pub fn same_surface(counted: &[bool], seen: &[u32], truth_seen: &[u32]) -> Vec<bool> {
    (counted.iter().zip(seen).zip(truth_seen))
        .map(|((&c, &a), &b)| c && a == b)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Pixels left out are not counted; the shadowed subset is where either is below 1.
    #[test]
    fn counts_only_the_marked_pixels_and_splits_the_shadowed_ones() {
        let truth = [1.0, 0.5, 1.0, 0.0];
        let lit = [1.0, 0.7, 0.9, 1.0];
        let e = mask_error(&lit, &truth, &[true, true, true, false]);
        assert_eq!((e.pixels, e.shadowed_pixels), (3, 2));
        assert!((e.rmse - ((0.04f64 + 0.01) / 3.0).sqrt()).abs() < 1e-6);
        assert!((e.rmse_shadowed - ((0.04f64 + 0.01) / 2.0).sqrt()).abs() < 1e-6);
    }

    /// Counted pixels where both saw the same triangle, and only those.
    #[test]
    fn same_surface_keeps_counted_pixels_that_see_one_triangle() {
        let same = same_surface(&[true, true, false, true], &[3, 4, 5, 7], &[3, 9, 5, 7]);
        assert_eq!(same, [true, false, false, true]);
    }
}
