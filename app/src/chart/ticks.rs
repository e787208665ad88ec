//! Where an axis gets its ticks and what they read: multiples of 1, 2 or 5 times a power of
//! ten on a linear axis, powers of ten on a log axis, and compact labels ("2.5M").

use super::csv::{place_point, significant_digits};

/// Ticks at multiples of a "nice" step (1, 2 or 5 times a power of ten) from `lo` to `hi`:
/// the smallest such step that makes at most `max_intervals` intervals over the range.
/// Empty when the range is empty, not finite or too wide for f64.
pub fn nice_ticks(lo: f64, hi: f64, max_intervals: usize) -> Vec<f64> {
    let span = hi - lo;
    if !(span.is_finite() && span > 0.0) || max_intervals == 0 {
        return Vec::new();
    }
    let raw = span / max_intervals as f64;
    let exponent = raw.log10().floor();
    let magnitude = 10f64.powf(exponent);
    // The tolerance keeps a raw step of exactly 0.2 (computed as 0.2000000001) at 2, not 5.
    let Some(multiple) = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .find(|m| m * magnitude >= raw * (1.0 - 1e-9))
    else {
        return Vec::new();
    };
    let step = multiple * magnitude;
    if !(step.is_finite() && step > 0.0) {
        return Vec::new();
    }
    let first = (lo / step - 1e-9).ceil();
    let last = (hi / step + 1e-9).floor();
    // Bounded by max_intervals + 1 in exact arithmetic; the cap guards against rounding.
    if !(first.is_finite() && last.is_finite()) || last - first > max_intervals as f64 + 2.0 {
        return Vec::new();
    }
    // `i * multiple / 10^-exponent` instead of `i * step`: dividing by an exact power of
    // ten gives 0.3, not 0.30000000000000004, for the third tick of step 0.1.
    let scale = 10f64.powf(exponent.abs());
    // first..=last holds at most max_intervals + 3 whole numbers well inside i64.
    (first as i64..=last as i64)
        .map(|i| {
            let units = i as f64 * multiple;
            if exponent < 0.0 {
                units / scale
            } else {
                units * scale
            }
        })
        .collect()
}

/// Ticks for a log axis from `lo` to `hi` (both positive): powers of ten, with 2 and 5
/// times them in between when the range spans at most two decades, and only every k-th
/// power when more than `max_ticks` would not fit. Empty for an invalid range.
pub fn log_ticks(lo: f64, hi: f64, max_ticks: usize) -> Vec<f64> {
    if !(lo > 0.0 && hi > lo && hi.is_finite()) || max_ticks == 0 {
        return Vec::new();
    }
    // Tolerances so that lo = 1000 (log10 = 2.9999999999999996) still counts as 10^3.
    let first = (lo.log10() - 1e-9).ceil();
    let last = (hi.log10() + 1e-9).floor();
    if first > last {
        // No power of ten inside: fall back to linear ticks rather than none.
        return nice_ticks(lo, hi, max_ticks.saturating_sub(1).max(1));
    }
    // Both within about ±330 for positive finite f64, so the casts are exact.
    let (first, last) = (first as i32, last as i32);
    let decades = (last - first) as usize;
    let in_range = |v: f64| v >= lo * (1.0 - 1e-9) && v <= hi * (1.0 + 1e-9);
    if decades <= 2 {
        let dense: Vec<f64> = (first - 1..=last)
            .flat_map(|e| [1.0, 2.0, 5.0].map(|m| m * 10f64.powi(e)))
            .filter(|&v| in_range(v))
            .collect();
        if dense.len() <= max_ticks {
            return dense;
        }
    }
    let every = decades.div_ceil(max_ticks.saturating_sub(1).max(1)).max(1);
    (first..=last)
        .step_by(every)
        .map(|e| 10f64.powi(e))
        .collect()
}

/// A compact tick label with at most 4 significant digits: "0.5", "10", "1k", "2.5M",
/// "-1.2G"; scientific for magnitudes below 0.001 or from 1e15 ("1e-4", "2.5e15").
pub fn format_tick(v: f64) -> String {
    if !v.is_finite() {
        return super::fmt_num(v);
    }
    if v == 0.0 {
        return "0".into();
    }
    let sign = if v < 0.0 { "-" } else { "" };
    // Rounded first, so that 999_950 becomes "1M" and not "1000k".
    let (digits, exponent) = significant_digits(v.abs(), 4);
    let body = match exponent {
        -3..=2 => place_point(&digits, exponent + 1),
        3..=14 => {
            let group = exponent / 3;
            let suffix = ["k", "M", "G", "T"][(group - 1) as usize];
            format!("{}{suffix}", place_point(&digits, exponent - 3 * group + 1))
        }
        _ => format!("{}e{exponent}", place_point(&digits, 1)),
    };
    format!("{sign}{body}")
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    pub(in crate::chart) fn assert_ticks(actual: &[f64], expected: &[f64]) {
        assert_eq!(actual.len(), expected.len(), "{actual:?} vs {expected:?}");
        for (a, e) in actual.iter().zip(expected) {
            assert!(
                (a - e).abs() <= 1e-12 * e.abs().max(1.0),
                "{actual:?} vs {expected:?}"
            );
        }
    }

    #[test]
    fn linear_ticks_use_1_2_5_steps() {
        assert_ticks(&nice_ticks(0.0, 1.0, 5), &[0.0, 0.2, 0.4, 0.6, 0.8, 1.0]);
        assert_ticks(
            &nice_ticks(0.0, 1.0, 10),
            &[0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0],
        );
        assert_ticks(&nice_ticks(3.0, 97.0, 5), &[20.0, 40.0, 60.0, 80.0]);
        assert_ticks(
            &nice_ticks(3.0, 97.0, 10),
            &[10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0, 90.0],
        );
        assert_ticks(&nice_ticks(-7.0, 12.0, 4), &[-5.0, 0.0, 5.0, 10.0]);
        assert_ticks(
            &nice_ticks(1500.0, 2600.0, 6),
            &[1600.0, 1800.0, 2000.0, 2200.0, 2400.0, 2600.0],
        );
        // The labels of steps like 0.1 are exact decimals.
        assert_eq!(nice_ticks(0.0, 1.0, 10)[3], 0.3);
        assert!(nice_ticks(1.0, 1.0, 5).is_empty());
        assert!(nice_ticks(0.0, f64::NAN, 5).is_empty());
        assert!(nice_ticks(-f64::MAX, f64::MAX, 5).is_empty());
    }

    #[test]
    fn log_ticks_are_powers_of_ten() {
        assert_ticks(&log_ticks(1.0, 1000.0, 10), &[1.0, 10.0, 100.0, 1000.0]);
        assert_ticks(
            &log_ticks(1.0, 100.0, 10),
            &[1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0],
        );
        assert_ticks(&log_ticks(1.0, 100.0, 4), &[1.0, 10.0, 100.0]);
        assert_ticks(&log_ticks(1e-3, 1e9, 5), &[1e-3, 1e0, 1e3, 1e6, 1e9]);
        assert!(log_ticks(0.0, 10.0, 5).is_empty());
        // No power of ten inside: linear ticks instead of none.
        assert!(!log_ticks(2.0, 8.0, 5).is_empty());
    }

    #[test]
    fn tick_labels_are_compact() {
        let cases = [
            (0.0, "0"),
            (0.5, "0.5"),
            (10.0, "10"),
            (1000.0, "1k"),
            (2.5e6, "2.5M"),
            (-1500.0, "-1.5k"),
            (12_340.0, "12.34k"),
            (999_950.0, "1M"),
            (3e9, "3G"),
            (0.1 + 0.2, "0.3"),
            (0.001, "0.001"),
            (1e-4, "1e-4"),
            (2.5e15, "2.5e15"),
            (123.456, "123.5"),
        ];
        for (v, expected) in cases {
            assert_eq!(format_tick(v), expected, "for {v:e}");
        }
    }
}
