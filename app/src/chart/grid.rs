//! The plot's frame: light grid lines at the ticks, the tick marks and their labels, and the
//! two axis lines.

use super::layout::Layout;
use super::palette::{AXIS, GRID, TEXT};
use super::pixels::px;
use crate::compare::{Rgb8Image, draw_text, text_width};

/// Draws the grid, the ticks with their labels and the axes of `layout` on `img`.
pub(super) fn draw_grid_and_axes(img: &mut Rgb8Image, layout: &Layout) {
    let Layout {
        width,
        scale,
        char_h,
        gap,
        tick_len,
        left,
        right,
        top,
        bottom,
        plot_w,
        plot_h,
        ..
    } = *layout;
    // Positions are within the plot (the ticks lie in the range).
    for (v, label) in &layout.x_ticks {
        let x = px(layout.to_px((*v, 1.0)).0.round() as i64);
        if x > left && x < right {
            img.fill_rect(x, top, 1, plot_h, GRID);
        }
        img.fill_rect(x, bottom, 1, tick_len + 1, AXIS);
        let w = text_width(label, scale);
        let label_x = x.saturating_sub(w / 2).min(width.saturating_sub(w));
        draw_text(img, label_x, bottom + tick_len + gap, label, scale, TEXT);
    }
    for (v, label) in &layout.y_ticks {
        let y = px(layout.to_px((1.0, *v)).1.round() as i64);
        if y > top && y < bottom {
            img.fill_rect(left, y, plot_w + 1, 1, GRID);
        }
        img.fill_rect(left - tick_len, y, tick_len, 1, AXIS);
        let w = text_width(label, scale);
        draw_text(
            img,
            (left - tick_len - gap).saturating_sub(w),
            y.saturating_sub(char_h / 2),
            label,
            scale,
            TEXT,
        );
    }
    // Axes: a line on the left and the bottom, 1 px at scale 1, 2 px at scale 2.
    img.fill_rect(left - (scale - 1), top, scale, plot_h + scale, AXIS);
    img.fill_rect(left - (scale - 1), bottom, plot_w + scale, scale, AXIS);
}
