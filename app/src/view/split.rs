//! The split view's line in the overlay: both methods, each with its own shadow passes' GPU
//! ms (the G-buffer, the shading and the copy serve both halves and are listed apart).

use super::method::ViewMethod;
use super::record::SPLIT_PASS_PREFIX;

/// The passes that draw one method's shadows (the timestamps' names, without the split
/// side's prefix).
const SHADOW_PASSES: [&str; 4] = ["collection", "generation", "mask", "tsm + mask"];

/// GPU ms of one side's shadow passes in `pass_ms` (the last frame's): the left method's, or
/// the right one's (`right`: named with [`SPLIT_PASS_PREFIX`]).
pub fn side_ms(pass_ms: &[(String, f64)], right: bool) -> f64 {
    pass_ms
        .iter()
        .filter(|(pass, _)| {
            let name = if right {
                pass.strip_prefix(SPLIT_PASS_PREFIX)
            } else {
                Some(pass.as_str())
            };
            name.is_some_and(|n| SHADOW_PASSES.contains(&n))
        })
        .map(|(_, ms)| ms)
        .sum()
}

/// The overlay's line for the split view of `left` and `right`.
pub fn split_line(left: ViewMethod, right: ViewMethod, pass_ms: &[(String, f64)]) -> String {
    format!(
        "split: left {} {:.1} ms | right {} {:.1} ms (shadow passes)",
        left.name(),
        side_ms(pass_ms, false),
        right.name(),
        side_ms(pass_ms, true)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each side sums its own shadow passes only: not the other side's, not the passes
    /// both share.
    #[test]
    fn each_side_counts_its_own_shadow_passes() {
        let ms = |pass: &str, ms: f64| (pass.to_owned(), ms);
        let passes = [
            ms("g-buffer", 100.0),
            ms("collection", 1.0),
            ms("generation", 2.0),
            ms("mask", 4.0),
            ms("split tsm + mask", 8.0),
            ms("shade", 200.0),
            ms("present copy", 400.0),
        ];
        assert_eq!(side_ms(&passes, false), 7.0);
        assert_eq!(side_ms(&passes, true), 8.0);
        let line = split_line(ViewMethod::Temporal, ViewMethod::Tsm { maps: 4 }, &passes);
        assert_eq!(
            line,
            "split: left temporal 7.0 ms | right tsm-4 8.0 ms (shadow passes)"
        );
    }
}
