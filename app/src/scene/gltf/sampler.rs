//! Keyframe interpolation as the glTF 2.0 specification defines it (Appendix C): STEP,
//! LINEAR (spherical for rotations) and CUBICSPLINE (cubic Hermite with per-key in and out
//! tangents scaled by the key interval). Times before the first key or after the last clamp
//! to the end values, as the specification requires.

use glam::Quat;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Interpolation {
    Step,
    Linear,
    CubicSpline,
}

/// A channel's keys: `values` holds `width` floats per key, or for CUBICSPLINE three groups
/// of `width` per key (in-tangent, value, out-tangent).
#[derive(Debug, Clone)]
pub(super) struct Keyframes {
    pub times: Vec<f32>,
    pub values: Vec<f32>,
    pub width: usize,
    pub interpolation: Interpolation,
}

impl Keyframes {
    /// Checks the shape the sampling relies on; `width` may be deduced for morph weights.
    pub(super) fn new(
        times: Vec<f32>,
        values: Vec<f32>,
        interpolation: Interpolation,
        width: Option<usize>,
    ) -> Result<Self, String> {
        if times.is_empty() {
            return Err("animation sampler has no keys".into());
        }
        if times.iter().any(|t| !t.is_finite()) || times.windows(2).any(|w| w[1] < w[0]) {
            return Err("animation sampler key times are not finite and increasing".into());
        }
        let per_key = if interpolation == Interpolation::CubicSpline {
            3
        } else {
            1
        };
        let groups = times.len() * per_key;
        let width = width.unwrap_or(values.len() / groups);
        if width == 0 || values.len() != groups * width {
            return Err(format!(
                "animation sampler has {} output values for {} keys ({interpolation:?}), \
                 expected {} per key",
                values.len(),
                times.len(),
                per_key * width.max(1)
            ));
        }
        // Checked here, where every channel's values pass: sampling would carry a NaN into
        // a translation (refused later as a posed vertex), but a rotation's normalisation
        // turned it into no rotation at all, a wrong image without a word.
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            return Err(format!(
                "animation sampler output value {i} (key {}) is {}, not a finite number",
                i / (per_key * width),
                values[i]
            ));
        }
        Ok(Keyframes {
            times,
            values,
            width,
            interpolation,
        })
    }

    /// Refuses rotation keys of length 0, which have no direction to normalise to (they
    /// were taken as no rotation). Other lengths are normalised, as viewers do.
    pub(super) fn check_rotations(&self) -> Result<(), String> {
        match (0..self.times.len()).find(|&k| {
            let v = self.value(k);
            Quat::from_xyzw(v[0], v[1], v[2], v[3]).length() < 1e-6
        }) {
            Some(k) => Err(format!(
                "rotation key {k} is {:?}, not a unit quaternion (length 0)",
                self.value(k)
            )),
            None => Ok(()),
        }
    }

    /// Group `g` of key `k` (for CUBICSPLINE: 0 in-tangent, 1 value, 2 out-tangent).
    fn group(&self, k: usize, g: usize) -> &[f32] {
        let per_key = if self.interpolation == Interpolation::CubicSpline {
            3
        } else {
            1
        };
        let start = (k * per_key + g) * self.width;
        &self.values[start..start + self.width]
    }

    fn value(&self, k: usize) -> &[f32] {
        let g = usize::from(self.interpolation == Interpolation::CubicSpline);
        self.group(k, g)
    }

    /// The value at time `t`. `rotation`: the values are unit quaternions (x, y, z, w), so
    /// LINEAR is a slerp and every result is normalised.
    pub(super) fn sample(&self, t: f32, rotation: bool) -> Vec<f32> {
        let last = self.times.len() - 1;
        let k = self.times.partition_point(|&key| key <= t);
        let out = if k == 0 {
            self.value(0).to_vec()
        } else if k > last {
            self.value(last).to_vec()
        } else {
            let k = k - 1;
            let dt = self.times[k + 1] - self.times[k];
            let s = if dt > 0.0 {
                (t - self.times[k]) / dt
            } else {
                1.0
            };
            self.between(k, s, dt, rotation)
        };
        if rotation { normalized(&out) } else { out }
    }

    /// Between keys `k` and `k + 1`, at fraction `s` of the interval `dt` seconds long.
    fn between(&self, k: usize, s: f32, dt: f32, rotation: bool) -> Vec<f32> {
        let (a, b) = (self.value(k), self.value(k + 1));
        match self.interpolation {
            Interpolation::Step => a.to_vec(),
            Interpolation::Linear if rotation => {
                let q = |v: &[f32]| Quat::from_xyzw(v[0], v[1], v[2], v[3]).normalize();
                q(a).slerp(q(b), s).to_array().to_vec()
            }
            Interpolation::Linear => a.iter().zip(b).map(|(&a, &b)| a + s * (b - a)).collect(),
            Interpolation::CubicSpline => {
                let (s2, s3) = (s * s, s * s * s);
                let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
                let h10 = s3 - 2.0 * s2 + s;
                let h01 = -2.0 * s3 + 3.0 * s2;
                let h11 = s3 - s2;
                let out_tangent = self.group(k, 2);
                let in_tangent = self.group(k + 1, 0);
                (0..self.width)
                    .map(|i| {
                        h00 * a[i]
                            + h10 * dt * out_tangent[i]
                            + h01 * b[i]
                            + h11 * dt * in_tangent[i]
                    })
                    .collect()
            }
        }
    }
}

fn normalized(v: &[f32]) -> Vec<f32> {
    let q = Quat::from_xyzw(v[0], v[1], v[2], v[3]);
    let len = q.length();
    if len > 0.0 {
        (q / len).to_array().to_vec()
    } else {
        Quat::IDENTITY.to_array().to_vec()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scalar(times: &[f32], values: &[f32], i: Interpolation) -> Keyframes {
        Keyframes::new(times.to_vec(), values.to_vec(), i, Some(1)).unwrap()
    }

    #[test]
    fn step_and_linear_scalars_and_clamping() {
        let step = scalar(&[1.0, 2.0, 4.0], &[10.0, 20.0, 40.0], Interpolation::Step);
        assert_eq!(step.sample(0.0, false), [10.0]);
        assert_eq!(step.sample(1.9, false), [10.0]);
        assert_eq!(step.sample(2.0, false), [20.0]);
        assert_eq!(step.sample(9.0, false), [40.0]);
        let linear = scalar(&[1.0, 2.0, 4.0], &[10.0, 20.0, 40.0], Interpolation::Linear);
        assert_eq!(linear.sample(1.5, false), [15.0]);
        assert_eq!(linear.sample(3.0, false), [30.0]);
        assert_eq!(linear.sample(-1.0, false), [10.0]);
        assert_eq!(linear.sample(5.0, false), [40.0]);
    }

    #[test]
    fn cubic_spline_is_the_hermite_curve_with_tangents_scaled_by_the_interval() {
        // Keys at 0 and 2 s, values 0 and 0, out-tangent 1 at the first key: the curve is
        // dt * (s^3 - 2 s^2 + s) with dt = 2; at t = 0.5, s = 0.25: 2 * 0.140625.
        let k = scalar(
            &[0.0, 2.0],
            &[9.0, 0.0, 1.0, 0.0, 0.0, 9.0],
            Interpolation::CubicSpline,
        );
        let v = k.sample(0.5, false)[0];
        assert!((v - 0.28125).abs() < 1e-6, "{v}");
        // Outside the keys only the values count, never the tangents (9).
        assert_eq!(k.sample(-1.0, false), [0.0]);
        assert_eq!(k.sample(3.0, false), [0.0]);
    }

    #[test]
    fn linear_rotation_is_a_slerp() {
        let q = |deg: f32| Quat::from_rotation_z(deg.to_radians()).to_array();
        let values: Vec<f32> = [q(0.0), q(120.0)].concat();
        let k = Keyframes::new(vec![0.0, 1.0], values, Interpolation::Linear, Some(4)).unwrap();
        let v = k.sample(0.25, true);
        let got = Quat::from_xyzw(v[0], v[1], v[2], v[3]);
        // A component-wise lerp (normalised) would give about 27.8 degrees here; the slerp gives 30.
        assert!(got.angle_between(Quat::from_rotation_z(30f32.to_radians())) < 1e-5);
    }

    #[test]
    fn malformed_samplers_are_refused() {
        assert!(Keyframes::new(vec![], vec![], Interpolation::Linear, Some(1)).is_err());
        assert!(
            Keyframes::new(vec![1.0, 0.0], vec![0.0; 2], Interpolation::Linear, Some(1)).is_err()
        );
        assert!(
            Keyframes::new(vec![0.0, 1.0], vec![0.0; 3], Interpolation::Linear, Some(1)).is_err()
        );
        assert!(
            Keyframes::new(
                vec![0.0, 1.0],
                vec![0.0; 4],
                Interpolation::CubicSpline,
                Some(1)
            )
            .is_err()
        );
    }
}
