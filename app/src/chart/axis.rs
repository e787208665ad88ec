//! An axis's scale (linear or log) and range, and which of its ticks fit its length.

use super::ticks::{format_tick, log_ticks, nice_ticks};

/// One axis: its scale and its range in plotting space (log10 of the data on a log axis).
pub(super) struct Axis {
    log: bool,
    lo: f64,
    hi: f64,
}

impl Axis {
    /// The axis covering `values` (the drawable coordinates): padded by 5% of the span on
    /// a linear axis, widened to whole decades on a log axis. Without values, [0, 1]
    /// (linear) or [1, 10] (log, where 0 cannot be shown).
    pub(super) fn covering(log: bool, values: impl Iterator<Item = f64>) -> Self {
        let (min, max) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
        if min > max {
            return Self {
                log,
                lo: 0.0,
                hi: 1.0,
            };
        }
        if log {
            let (mut lo, mut hi) = (min.log10().floor(), max.log10().ceil());
            if lo == hi {
                // One value on a power of ten: centre it in two decades.
                lo -= 1.0;
                hi += 1.0;
            }
            return Self { log, lo, hi };
        }
        let (mut lo, mut hi) = (min, max);
        if lo == hi {
            // One distinct value: give it a range around it to sit in the middle of.
            let half = if lo == 0.0 { 0.5 } else { lo.abs() * 0.1 };
            lo -= half;
            hi += half;
        }
        let pad = 0.05 * (hi - lo);
        Self {
            log,
            lo: lo - pad,
            hi: hi + pad,
        }
    }

    /// `v` in plotting space.
    fn transform(&self, v: f64) -> f64 {
        if self.log { v.log10() } else { v }
    }

    /// Where `v` lies on the axis: 0 at the start, 1 at the end.
    pub(super) fn fraction(&self, v: f64) -> f64 {
        (self.transform(v) - self.lo) / (self.hi - self.lo)
    }

    /// Tick values for at most about `intervals` intervals.
    fn ticks(&self, intervals: usize) -> Vec<f64> {
        if self.log {
            log_ticks(10f64.powf(self.lo), 10f64.powf(self.hi), intervals + 1)
        } else {
            nice_ticks(self.lo, self.hi, intervals)
        }
    }

    /// The densest ticks whose labels are at least `min_spacing(labels)` pixels apart on an
    /// axis `length` pixels long.
    pub(super) fn fitting_ticks(
        &self,
        length: u32,
        min_spacing: impl Fn(&[String]) -> u32,
    ) -> Vec<(f64, String)> {
        let most = (length / 12).clamp(1, 20) as usize;
        let mut chosen = Vec::new();
        for intervals in (1..=most).rev() {
            let ticks = self.ticks(intervals);
            let labels: Vec<String> = ticks.iter().map(|&v| format_tick(v)).collect();
            let fits = ticks.len() < 2 || {
                let gaps = u32::try_from(ticks.len() - 1).unwrap_or(u32::MAX);
                length / gaps >= min_spacing(&labels)
            };
            chosen = ticks.into_iter().zip(labels).collect();
            if fits {
                break;
            }
        }
        chosen
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::chart::ticks::tests::assert_ticks;

    #[test]
    fn padded_axis_gets_round_end_ticks() {
        // Data from 3 to 97, padded by 5% to [-1.7, 101.7], is labelled 0 to 100.
        let axis = Axis::covering(false, [3.0, 50.0, 97.0].into_iter());
        assert_ticks(&axis.ticks(3), &[0.0, 50.0, 100.0]);
        assert_ticks(&axis.ticks(6), &[0.0, 20.0, 40.0, 60.0, 80.0, 100.0]);
        let empty = Axis::covering(false, std::iter::empty());
        assert_eq!((empty.lo, empty.hi), (0.0, 1.0));
        let log = Axis::covering(true, [3.0, 420.0].into_iter());
        assert_eq!((log.lo, log.hi), (0.0, 3.0));
    }
}
