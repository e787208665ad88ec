//! The engine preset's equal-quality verdict against the exact mask: the cheapest TSM
//! configuration (maps N, map size) whose RMSE against the truth is at or below the exact
//! mask's, or, where none is, TSM's best.

/// One TSM configuration of the ladder as measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct TsmPoint {
    pub maps: u32,
    /// The side of the square maps, in texels.
    pub map: u32,
    /// GPU ms of the shadow pass plus the mask.
    pub ms: f64,
    pub rmse: f64,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Verdict {
    /// The cheapest TSM at or below the exact mask's RMSE.
    Matches(TsmPoint),
    /// No TSM measured reaches the exact mask's RMSE; the one closest to it, if any was
    /// measured.
    Above { best: Option<TsmPoint> },
}

/// The verdict over `ladder` (in any order: the cheapest by time, not the first in the
/// ladder, since a larger map with fewer maps may cost less than a smaller one with many).
/// No slack: the exact mask has no spatial floor to share with TSM, unlike the depth-line mask.
pub(super) fn verdict(ladder: &[TsmPoint], exact_rmse: f64) -> Verdict {
    let matching = ladder
        .iter()
        .filter(|p| p.rmse <= exact_rmse)
        .min_by(|a, b| a.ms.total_cmp(&b.ms));
    match matching {
        Some(p) => Verdict::Matches(*p),
        None => Verdict::Above {
            best: ladder
                .iter()
                .min_by(|a, b| a.rmse.total_cmp(&b.rmse))
                .copied(),
        },
    }
}

/// What a TSM row of the table says against the exact mask: `cheapest match` (the verdict's
/// row), `matches` (at or below its RMSE, but dearer) or `above`.
pub(super) fn row_label(point: &TsmPoint, exact_rmse: f64, verdict: &Verdict) -> &'static str {
    match verdict {
        Verdict::Matches(p) if p == point => "cheapest match",
        _ if point.rmse <= exact_rmse => "matches",
        _ => "above",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(maps: u32, map: u32, ms: f64, rmse: f64) -> TsmPoint {
        TsmPoint {
            maps,
            map,
            ms,
            rmse,
        }
    }

    /// The ladder runs N up at the small map, then N up at the large one: the first match
    /// in that order (TSM-64 at 512) is dearer than a later one (TSM-4 at 1024), which the
    /// verdict must pick; a match exactly at the exact mask's RMSE counts.
    #[test]
    fn the_verdict_is_the_cheapest_match_not_the_first() {
        let exact = 0.01;
        let ladder = [
            point(1, 512, 10.0, 0.05),
            point(64, 512, 80.0, 0.009),
            point(1, 1024, 15.0, 0.03),
            point(4, 1024, 30.0, 0.01),
            point(64, 1024, 200.0, 0.002),
        ];
        let v = verdict(&ladder, exact);
        assert_eq!(v, Verdict::Matches(ladder[3]));
        let labels: Vec<&str> = ladder.iter().map(|p| row_label(p, exact, &v)).collect();
        assert_eq!(
            labels,
            ["above", "matches", "above", "cheapest match", "matches"]
        );
    }

    /// Nothing at or below: the verdict names the TSM of least RMSE (not the last measured,
    /// not the dearest), and every row is above.
    #[test]
    fn without_a_match_the_verdict_names_tsms_best() {
        let exact = 0.001;
        let ladder = [
            point(1, 512, 10.0, 0.05),
            point(8, 1024, 40.0, 0.02),
            point(32, 1024, 90.0, 0.021),
        ];
        let v = verdict(&ladder, exact);
        assert_eq!(
            v,
            Verdict::Above {
                best: Some(ladder[1])
            }
        );
        assert!(ladder.iter().all(|p| row_label(p, exact, &v) == "above"));
        assert_eq!(verdict(&[], exact), Verdict::Above { best: None });
    }
}
