//! The legend: a swatch and a label per series, in the top inner corner of the plot that
//! hides less of the data.

use super::data::LineChart;
use super::layout::{Layout, fit_text};
use super::palette::{BACKGROUND, LEGEND_BORDER, TEXT, series_color};
use super::pixels::{Rect, draw_line, draw_marker, px};
use crate::compare::{GLYPH_HEIGHT, Rgb8Image, draw_text, text_width};

/// Draws the legend (a swatch of line and marker, then the label, per series) in the top
/// inner corner of the plot that hides less of the data (the right one on a tie).
/// Nothing is drawn when every label is empty.
pub(super) fn draw_legend(img: &mut Rgb8Image, chart: &LineChart, layout: &Layout) {
    let (plot, scale) = (layout.plot(), layout.scale);
    if chart.series.iter().all(|s| s.label.is_empty()) {
        return;
    }
    let char_h = i64::from(GLYPH_HEIGHT * scale);
    let pad = i64::from(4 * scale);
    let swatch_w = 3 * char_h;
    let row_h = char_h + pad;
    let plot_w = plot.right - plot.left;
    let plot_h = plot.bottom - plot.top;

    // At most half the plot's width and two thirds of its height, so the data stays
    // visible: labels are shortened, and series that do not fit are summed up in a last
    // "+N more" row.
    let max_label_w = u32::try_from(plot_w / 2 - 3 * pad - swatch_w).unwrap_or(0);
    let rows = usize::try_from((plot_h * 2 / 3 - pad) / row_h).unwrap_or(0);
    let shown = if chart.series.len() <= rows {
        chart.series.len()
    } else {
        rows.saturating_sub(1)
    };
    let mut labels: Vec<(Option<[u8; 3]>, String)> = chart
        .series
        .iter()
        .take(shown)
        .enumerate()
        .map(|(i, s)| {
            let color = series_color(i);
            (Some(color), fit_text(&s.label, max_label_w, scale))
        })
        .collect();
    if shown < chart.series.len() && rows > 0 {
        let more = format!("+{} more", chart.series.len() - shown);
        labels.push((None, fit_text(&more, max_label_w, scale)));
    }
    if labels.is_empty() {
        return;
    }
    let label_w = labels
        .iter()
        .map(|(_, l)| i64::from(text_width(l, scale)))
        .max()
        .unwrap_or(0);
    // The row count is bounded by the plot height, so it fits in i64.
    let box_w = pad + swatch_w + pad + label_w + pad;
    let box_h = pad + labels.len() as i64 * row_h;

    let top = plot.top + pad;
    let right_box = Rect {
        left: plot.right - pad - box_w,
        top,
        right: plot.right - pad,
        bottom: top + box_h,
    };
    let left_box = Rect {
        left: plot.left + pad + i64::from(scale),
        top,
        right: plot.left + pad + i64::from(scale) + box_w,
        bottom: top + box_h,
    };
    let covered = |r: Rect| data_hidden_by(r, chart, layout);
    let legend = if covered(left_box) < covered(right_box) {
        left_box
    } else {
        right_box
    };

    img.fill_rect(
        px(legend.left),
        px(legend.top),
        px(box_w),
        px(box_h),
        LEGEND_BORDER,
    );
    img.fill_rect(
        px(legend.left + 1),
        px(legend.top + 1),
        px(box_w - 2),
        px(box_h - 2),
        BACKGROUND,
    );
    let marker_half = i64::from(scale) + 1;
    for (i, (color, label)) in labels.iter().enumerate() {
        // `i` < rows, bounded by the plot height.
        let row_top = legend.top + pad + i as i64 * row_h;
        let mid_y = (row_top + char_h / 2) as f64;
        let x0 = (legend.left + pad) as f64;
        if let Some(color) = *color {
            draw_line(
                img,
                (x0, mid_y),
                (x0 + swatch_w as f64, mid_y),
                legend,
                color,
            );
            let centre = (x0 + swatch_w as f64 / 2.0, mid_y);
            draw_marker(img, centre, marker_half, legend, color);
        }
        let text_x = legend.left + pad + swatch_w + pad;
        draw_text(img, px(text_x), px(row_top), label, scale, TEXT);
    }
}

/// How much of the data the box `r` would hide: points along every drawn segment, sampled
/// about every 4 pixels, within the box grown by a marker's size.
fn data_hidden_by(r: Rect, chart: &LineChart, layout: &Layout) -> usize {
    let grow = (2 * i64::from(layout.scale) + 2) as f64;
    let inside = |(x, y): (f64, f64)| {
        x >= r.left as f64 - grow
            && x <= r.right as f64 + grow
            && y >= r.top as f64 - grow
            && y <= r.bottom as f64 + grow
    };
    let mut count = 0usize;
    for series in &chart.series {
        let mut previous: Option<(f64, f64)> = None;
        for p in &series.points {
            let here = chart.drawable(p).then(|| layout.to_px(*p));
            if let Some(b) = here {
                count += usize::from(inside(b));
                if let Some(a) = previous {
                    // Capped so that far-off points cost no more than a long line.
                    let steps = ((b.0 - a.0).hypot(b.1 - a.1) / 4.0).clamp(1.0, 1000.0);
                    let steps = steps as usize;
                    count += (1..steps)
                        .map(|k| k as f64 / steps as f64)
                        .filter(|t| inside((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1))))
                        .count();
                }
            }
            previous = here;
        }
    }
    count
}
