//! The series: each a 2-pixel polyline, broken at undrawable points, with square markers on
//! top, in its palette colour.

use super::data::LineChart;
use super::layout::Layout;
use super::palette::series_color;
use super::pixels::{Rect, draw_line, draw_marker};
use crate::compare::Rgb8Image;

/// Draws every series of `chart` in the plot of `layout`.
pub(super) fn draw_series(img: &mut Rgb8Image, chart: &LineChart, layout: &Layout) {
    let plot = layout.plot();
    let marker_half = i64::from(layout.scale) + 1;
    // Markers may overhang the plot edge by their size but stay off the tick labels.
    let marker_clip = Rect {
        left: plot.left - marker_half,
        top: plot.top - marker_half,
        right: plot.right + marker_half,
        bottom: plot.bottom + marker_half,
    };
    let drawable = |p: &(f64, f64)| chart.drawable(p);
    for (i, series) in chart.series.iter().enumerate() {
        let color = series_color(i);
        for pair in series.points.windows(2) {
            if drawable(&pair[0]) && drawable(&pair[1]) {
                let (a, b) = (layout.to_px(pair[0]), layout.to_px(pair[1]));
                draw_line(img, a, b, plot, color);
            }
        }
        for p in series.points.iter().copied().filter(drawable) {
            draw_marker(img, layout.to_px(p), marker_half, marker_clip, color);
        }
    }
}
