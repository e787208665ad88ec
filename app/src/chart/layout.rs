//! Where a chart's parts go on the picture: the text's scale, the rows of the title and the
//! axis labels, the plot rectangle, and the ticks that fit along its axes.

use super::ChartError;
use super::axis::Axis;
use super::data::LineChart;
use super::pixels::Rect;
use crate::compare::{GLYPH_HEIGHT, text_width};

/// The positions [`super::render`] draws at, in image pixels.
pub(super) struct Layout {
    pub(super) width: u32,
    /// Font pixels per glyph pixel: 2 from 640x400 up, else 1.
    pub(super) scale: u32,
    pub(super) char_h: u32,
    pub(super) gap: u32,
    pub(super) margin: u32,
    pub(super) tick_len: u32,
    pub(super) title_y: u32,
    pub(super) y_label_y: u32,
    pub(super) x_label_y: u32,
    /// The plot's edges.
    pub(super) left: u32,
    pub(super) right: u32,
    pub(super) top: u32,
    pub(super) bottom: u32,
    pub(super) plot_w: u32,
    pub(super) plot_h: u32,
    x_axis: Axis,
    y_axis: Axis,
    /// Tick values with their labels.
    pub(super) x_ticks: Vec<(f64, String)>,
    pub(super) y_ticks: Vec<(f64, String)>,
}

impl Layout {
    /// The layout of `chart` on a `width` x `height` picture (a size [`super::render`]
    /// accepts), its axes covering the drawable points. Errors with [`ChartError::Size`] when
    /// the labels leave a plot under 40x30 pixels.
    pub(super) fn new(chart: &LineChart, width: u32, height: u32) -> Result<Self, ChartError> {
        let scale = if width >= 640 && height >= 400 { 2 } else { 1 };
        let char_h = GLYPH_HEIGHT * scale;
        let gap = 4 * scale;
        let margin = 8 * scale;
        let tick_len = 4 * scale;

        let x_axis = Axis::covering(chart.log_x, chart.drawable_points().map(|p| p.0));
        let y_axis = Axis::covering(chart.log_y, chart.drawable_points().map(|p| p.1));

        // Vertical layout: title, y label, plot, tick labels, x label. The sizes are at least
        // MIN_HEIGHT, so the sums below stay far from overflow.
        let title_y = margin;
        let y_label_y = title_y + char_h + 2 * gap;
        let top = y_label_y + char_h + 2 * gap;
        let x_label_y = height - margin - char_h;
        let bottom = x_label_y - 2 * gap - char_h - gap - tick_len;
        let plot_h = bottom.saturating_sub(top);
        let y_ticks = y_axis.fitting_ticks(plot_h, |_| 3 * char_h);

        // Horizontal layout: y tick labels, plot, room for half of the last x tick label.
        let y_label_w = y_ticks
            .iter()
            .map(|(_, l)| text_width(l, scale))
            .max()
            .unwrap_or(0);
        let left = margin + y_label_w + gap + tick_len;
        let right = width.saturating_sub(margin + text_width("00.0k", scale) / 2);
        let plot_w = right.saturating_sub(left);
        if plot_w < 40 || plot_h < 30 {
            return Err(ChartError::Size { width, height });
        }
        let x_ticks = x_axis.fitting_ticks(plot_w, |labels| {
            labels
                .iter()
                .map(|l| text_width(l, scale))
                .max()
                .unwrap_or(0)
                + 3 * gap
        });
        Ok(Self {
            width,
            scale,
            char_h,
            gap,
            margin,
            tick_len,
            title_y,
            y_label_y,
            x_label_y,
            left,
            right,
            top,
            bottom,
            plot_w,
            plot_h,
            x_axis,
            y_axis,
            x_ticks,
            y_ticks,
        })
    }

    /// The plot area, edges included.
    pub(super) fn plot(&self) -> Rect {
        Rect {
            left: i64::from(self.left),
            top: i64::from(self.top),
            right: i64::from(self.right),
            bottom: i64::from(self.bottom),
        }
    }

    /// Where the data point (`x`, `y`) lies on the picture.
    pub(super) fn to_px(&self, (x, y): (f64, f64)) -> (f64, f64) {
        (
            f64::from(self.left) + self.x_axis.fraction(x) * f64::from(self.plot_w),
            f64::from(self.bottom) - self.y_axis.fraction(y) * f64::from(self.plot_h),
        )
    }
}

/// `text` shortened with ".." so that it is at most `max_width` pixels wide at `scale`.
pub(super) fn fit_text(text: &str, max_width: u32, scale: u32) -> String {
    if text_width(text, scale) <= max_width {
        return text.to_string();
    }
    let mut chars: Vec<char> = text.chars().collect();
    while !chars.is_empty() {
        chars.pop();
        let candidate: String = chars.iter().chain(['.', '.'].iter()).collect();
        if text_width(&candidate, scale) <= max_width {
            return candidate;
        }
    }
    String::new()
}
