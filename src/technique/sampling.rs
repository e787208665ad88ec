//! The CPU mirror of the lighting pass's sampling (`glsl/shared.glsl`: `pcg_hash`,
//! `pixel_key`, `stratum_rotation`, `time_stratum`, `pixel_sample`), so that a host can know
//! the time and the position in the pixel of every sample the pass takes.
//!
//! The arithmetic is the shaders', operation for operation (u32 wrapping products, the same
//! f32 scalings), so the results are the same bits. Each sample's camera ray is then
//! `ray00 + x ray_dx + y ray_dy` of the target's [`CameraParams`](super::CameraParams) at
//! `(x, y) = pixel + offset`, as `camera_ray` in the shaders.

use glam::Vec2;

/// The PCG-RXS-M-XS hash of one 32-bit word (`pcg_hash`).
pub fn pcg_hash(v: u32) -> u32 {
    let state = v.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

/// The hash every sample of pixel `(x, y)` derives from (`pixel_key`; `seed` is
/// [`LightingView::seed`](super::LightingView::seed)).
pub fn pixel_key(x: u32, y: u32, seed: u32) -> u32 {
    pcg_hash(x.wrapping_add(pcg_hash(y.wrapping_add(pcg_hash(seed)))))
}

/// The pixel's rotation of time strata against sample indices (`stratum_rotation`).
pub fn stratum_rotation(key: u32, spp: u32) -> u32 {
    key % spp
}

/// The time stratum of sample `k` of `spp`: `(k + rotation) mod spp` (`time_stratum`).
pub fn time_stratum(rotation: u32, k: u32, spp: u32) -> u32 {
    let s = k + rotation;
    if s >= spp { s - spp } else { s }
}

/// Sample `k` of `spp` of the pixel with `key` (`pixel_sample`): its shutter time, inside
/// stratum [`time_stratum`] of `spp` equal strata of [0, 1] (f32 rounding may put it on the
/// stratum's upper end), and its position in the pixel in (0, 1)^2 from the pixel's top-left
/// corner.
pub fn pixel_sample(key: u32, k: u32, spp: u32) -> (f32, Vec2) {
    let rotation = stratum_rotation(key, spp);
    let h = pcg_hash(key ^ pcg_hash(k));
    let t = (time_stratum(rotation, k, spp) as f32 + (h >> 8) as f32 * (1.0 / 16_777_216.0))
        / spp as f32;
    let g = pcg_hash(h);
    let offset = (Vec2::new((g & 0xffff) as f32, (g >> 16) as f32) + 0.5) * (1.0 / 65536.0);
    (t, offset)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shaders' contract: every pixel uses each time stratum exactly once, and every
    /// sample lies inside its stratum and its pixel.
    #[test]
    fn each_pixel_takes_every_stratum_once() {
        for spp in [1, 2, 3, 7, 8, 64] {
            for (x, y) in [(0, 0), (5, 3), (1023, 767)] {
                let key = pixel_key(x, y, 9);
                let rotation = stratum_rotation(key, spp);
                let mut seen = vec![false; spp as usize];
                for k in 0..spp {
                    let (t, offset) = pixel_sample(key, k, spp);
                    let stratum = time_stratum(rotation, k, spp);
                    assert!(
                        !seen[stratum as usize],
                        "stratum {stratum} twice ({spp} spp)"
                    );
                    seen[stratum as usize] = true;
                    let (lo, hi) = (
                        stratum as f32 / spp as f32,
                        (stratum + 1) as f32 / spp as f32,
                    );
                    assert!(lo <= t && t <= hi, "{t} outside stratum {stratum} of {spp}");
                    assert!(offset.cmpgt(Vec2::ZERO).all() && offset.cmplt(Vec2::ONE).all());
                }
            }
        }
    }

    /// Seeds and pixels decorrelate: neighbouring pixels and seeds give other keys.
    #[test]
    fn keys_differ_across_pixels_and_seeds() {
        let keys = [
            pixel_key(0, 0, 1),
            pixel_key(1, 0, 1),
            pixel_key(0, 1, 1),
            pixel_key(0, 0, 2),
        ];
        for i in 0..keys.len() {
            for j in i + 1..keys.len() {
                assert_ne!(keys[i], keys[j]);
            }
        }
    }
}
