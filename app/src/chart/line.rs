//! Line charts: series of (x, y) points drawn as polylines with markers over axes with
//! "nice" ticks, a title, axis labels and a legend, on an [`Rgb8Image`].

use super::ChartError;
use super::csv::{place_point, significant_digits};
use crate::compare::{GLYPH_HEIGHT, Rgb8Image, draw_text, text_width};

/// Smallest chart [`render`] accepts: below it the labels leave no room for the plot.
pub const MIN_WIDTH: u32 = 160;
/// See [`MIN_WIDTH`].
pub const MIN_HEIGHT: u32 = 120;
/// Largest width or height [`render`] accepts, so a bad size is an error rather than a
/// failed multi-gigabyte allocation.
pub const MAX_SIDE: u32 = 16384;

/// Series colours: the Okabe-Ito palette, which stays distinguishable with the common
/// colour-vision deficiencies. Its black is left out (it would read as an axis) and its
/// yellow comes last because it is faint on white. Series past the seventh reuse colours.
pub const PALETTE: [[u8; 3]; 7] = [
    [0, 114, 178],   // blue
    [213, 94, 0],    // vermillion
    [0, 158, 115],   // bluish green
    [230, 159, 0],   // orange
    [86, 180, 233],  // sky blue
    [204, 121, 167], // reddish purple
    [240, 228, 66],  // yellow
];

const BACKGROUND: [u8; 3] = [255, 255, 255];
const TEXT: [u8; 3] = [30, 30, 30];
const AXIS: [u8; 3] = [70, 70, 70];
const GRID: [u8; 3] = [230, 230, 230];
const LEGEND_BORDER: [u8; 3] = [170, 170, 170];

/// One named line of a chart. Points are drawn in the given order, so sort them by x for a
/// usual line plot.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
}

impl Series {
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self {
            label: label.into(),
            points,
        }
    }
}

/// A line chart; see [`render`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LineChart {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
    pub log_x: bool,
    pub log_y: bool,
}

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

/// One axis: its scale and its range in plotting space (log10 of the data on a log axis).
struct Axis {
    log: bool,
    lo: f64,
    hi: f64,
}

impl Axis {
    /// The axis covering `values` (the drawable coordinates): padded by 5% of the span on
    /// a linear axis, widened to whole decades on a log axis. Without values, [0, 1]
    /// (linear) or [1, 10] (log, where 0 cannot be shown).
    fn covering(log: bool, values: impl Iterator<Item = f64>) -> Self {
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
    fn fraction(&self, v: f64) -> f64 {
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
    fn fitting_ticks(
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

/// The plot area in image pixels, edges included.
#[derive(Clone, Copy)]
struct Rect {
    left: i64,
    top: i64,
    right: i64,
    bottom: i64,
}

impl Rect {
    fn contains(&self, x: i64, y: i64) -> bool {
        (self.left..=self.right).contains(&x) && (self.top..=self.bottom).contains(&y)
    }
}

/// Sets pixel (`x`, `y`) when it lies inside `clip`.
fn put_clipped(img: &mut Rgb8Image, clip: Rect, x: i64, y: i64, color: [u8; 3]) {
    if clip.contains(x, y) {
        // Inside the clip rectangle, which lies inside the image, so both fit in u32.
        if let (Ok(x), Ok(y)) = (u32::try_from(x), u32::try_from(y)) {
            img.put(x, y, color);
        }
    }
}

/// Clips the segment from `a` to `b` to `clip` (Liang-Barsky), so that far-off endpoints
/// never make the rasteriser walk millions of pixels outside the picture.
fn clip_segment(a: (f64, f64), b: (f64, f64), clip: Rect) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, a.0 - clip.left as f64),
        (dx, clip.right as f64 - a.0),
        (-dy, a.1 - clip.top as f64),
        (dy, clip.bottom as f64 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    let clipped = (
        (a.0 + t0 * dx, a.1 + t0 * dy),
        (a.0 + t1 * dx, a.1 + t1 * dy),
    );
    (t0 <= t1 && t0.is_finite() && t1.is_finite()).then_some(clipped)
}

/// A 2-pixel-thick line from `a` to `b`, clipped to `clip` (Bresenham, each step a 2x2
/// block).
fn draw_line(img: &mut Rgb8Image, a: (f64, f64), b: (f64, f64), clip: Rect, color: [u8; 3]) {
    let Some((a, b)) = clip_segment(a, b, clip) else {
        return;
    };
    // Clipped into the picture, so the rounded coordinates are small.
    let (mut x, mut y) = (a.0.round() as i64, a.1.round() as i64);
    let (x1, y1) = (b.0.round() as i64, b.1.round() as i64);
    let (dx, dy) = ((x1 - x).abs(), -(y1 - y).abs());
    let (sx, sy) = ((x1 - x).signum(), (y1 - y).signum());
    let mut err = dx + dy;
    loop {
        for (ox, oy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            put_clipped(img, clip, x + ox, y + oy, color);
        }
        if x == x1 && y == y1 {
            break;
        }
        let e2 = 2 * err;
        if e2 >= dy {
            err += dy;
            x += sx;
        }
        if e2 <= dx {
            err += dx;
            y += sy;
        }
    }
}

/// A filled square marker of side `2 * half + 1` centred on `p`, clipped to `clip`.
fn draw_marker(img: &mut Rgb8Image, p: (f64, f64), half: i64, clip: Rect, color: [u8; 3]) {
    let (cx, cy) = (p.0.round() as i64, p.1.round() as i64);
    for y in cy - half..=cy + half {
        for x in cx - half..=cx + half {
            put_clipped(img, clip, x, y, color);
        }
    }
}

/// `text` shortened with ".." so that it is at most `max_width` pixels wide at `scale`.
fn fit_text(text: &str, max_width: u32, scale: u32) -> String {
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

/// `v` as a pixel coordinate (u32), clamped into the picture.
fn px(v: i64) -> u32 {
    u32::try_from(v.max(0)).unwrap_or(u32::MAX)
}

/// Draws `chart` on a `width` x `height` white picture: the title centred at the top, the
/// y label above the y axis (the font cannot rotate), the x label centred below the
/// x axis, axes with tick marks, numeric labels ([`format_tick`]) and light grid lines,
/// each series as a 2-pixel polyline with square markers in its [`PALETTE`] colour, and a
/// legend in whichever top inner corner hides less of the data (at most half the plot
/// wide and two thirds high: long labels are shortened with "..", extra series summed up
/// as "+N more"). Past the palette's seven colours, series reuse them. Too-long titles and
/// axis labels are shortened with "..".
///
/// Points with a non-finite coordinate, or a coordinate <= 0 on a log axis, are skipped
/// and break the line there. Series may be empty; with no drawable point at all the axes
/// still show [0, 1] (linear) or [1, 10] (log). Text is drawn at scale 2 from 640x400 up,
/// at scale 1 below.
///
/// Errors: [`ChartError::Size`] outside [`MIN_WIDTH`]x[`MIN_HEIGHT`] to
/// [`MAX_SIDE`]x[`MAX_SIDE`], [`ChartError::NoSeries`] when `chart.series` is empty.
pub fn render(chart: &LineChart, width: u32, height: u32) -> Result<Rgb8Image, ChartError> {
    if !(MIN_WIDTH..=MAX_SIDE).contains(&width) || !(MIN_HEIGHT..=MAX_SIDE).contains(&height) {
        return Err(ChartError::Size { width, height });
    }
    if chart.series.is_empty() {
        return Err(ChartError::NoSeries);
    }
    let scale = if width >= 640 && height >= 400 { 2 } else { 1 };
    let char_h = GLYPH_HEIGHT * scale;
    let gap = 4 * scale;
    let margin = 8 * scale;
    let tick_len = 4 * scale;

    let mut img = Rgb8Image::new(width, height);
    img.fill_rect(0, 0, width, height, BACKGROUND);

    let drawable = |&(x, y): &(f64, f64)| {
        x.is_finite() && y.is_finite() && (!chart.log_x || x > 0.0) && (!chart.log_y || y > 0.0)
    };
    let points = || {
        chart
            .series
            .iter()
            .flat_map(|s| s.points.iter().copied().filter(drawable))
    };
    let x_axis = Axis::covering(chart.log_x, points().map(|p| p.0));
    let y_axis = Axis::covering(chart.log_y, points().map(|p| p.1));

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

    let plot = Rect {
        left: i64::from(left),
        top: i64::from(top),
        right: i64::from(right),
        bottom: i64::from(bottom),
    };
    let to_px = |(x, y): (f64, f64)| {
        (
            f64::from(left) + x_axis.fraction(x) * f64::from(plot_w),
            f64::from(bottom) - y_axis.fraction(y) * f64::from(plot_h),
        )
    };

    // Grid lines and ticks. Positions are within the plot (the ticks lie in the range).
    for (v, label) in &x_ticks {
        let x = px(to_px((*v, 1.0)).0.round() as i64);
        if x > left && x < right {
            img.fill_rect(x, top, 1, plot_h, GRID);
        }
        img.fill_rect(x, bottom, 1, tick_len + 1, AXIS);
        let w = text_width(label, scale);
        let label_x = x.saturating_sub(w / 2).min(width.saturating_sub(w));
        draw_text(
            &mut img,
            label_x,
            bottom + tick_len + gap,
            label,
            scale,
            TEXT,
        );
    }
    for (v, label) in &y_ticks {
        let y = px(to_px((1.0, *v)).1.round() as i64);
        if y > top && y < bottom {
            img.fill_rect(left, y, plot_w + 1, 1, GRID);
        }
        img.fill_rect(left - tick_len, y, tick_len, 1, AXIS);
        let w = text_width(label, scale);
        draw_text(
            &mut img,
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

    // Series: lines broken at undrawable points, then the markers on top.
    let marker_half = i64::from(scale) + 1;
    // Markers may overhang the plot edge by their size but stay off the tick labels.
    let marker_clip = Rect {
        left: plot.left - marker_half,
        top: plot.top - marker_half,
        right: plot.right + marker_half,
        bottom: plot.bottom + marker_half,
    };
    for (i, series) in chart.series.iter().enumerate() {
        let color = PALETTE[i % PALETTE.len()];
        for pair in series.points.windows(2) {
            if drawable(&pair[0]) && drawable(&pair[1]) {
                draw_line(&mut img, to_px(pair[0]), to_px(pair[1]), plot, color);
            }
        }
        for p in series.points.iter().copied().filter(drawable) {
            draw_marker(&mut img, to_px(p), marker_half, marker_clip, color);
        }
    }

    draw_legend(&mut img, chart, plot, scale, &|p| to_px(p), &drawable);

    // Text last, so nothing is drawn over it; too-long texts are shortened with "..", so
    // the margins (whose width is at most MIN_WIDTH / 8) always leave room.
    let text_room = width - 2 * margin;
    let title = fit_text(&chart.title, text_room, scale);
    let title_x = (width - text_width(&title, scale)) / 2;
    draw_text(&mut img, title_x, title_y, &title, scale, TEXT);
    let y_label = fit_text(&chart.y_label, text_room, scale);
    draw_text(&mut img, margin, y_label_y, &y_label, scale, TEXT);
    let x_label = fit_text(&chart.x_label, text_room, scale);
    let x_label_w = text_width(&x_label, scale);
    let x_label_x = (left + plot_w / 2).saturating_sub(x_label_w / 2);
    let x_label_x = x_label_x.min(width - margin - x_label_w).max(margin);
    draw_text(&mut img, x_label_x, x_label_y, &x_label, scale, TEXT);
    Ok(img)
}

/// Draws the legend (a swatch of line and marker, then the label, per series) in the top
/// inner corner of `plot` that hides less of the data (the right one on a tie).
/// Nothing is drawn when every label is empty.
fn draw_legend(
    img: &mut Rgb8Image,
    chart: &LineChart,
    plot: Rect,
    scale: u32,
    to_px: &dyn Fn((f64, f64)) -> (f64, f64),
    drawable: &dyn Fn(&(f64, f64)) -> bool,
) {
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
            let color = PALETTE[i % PALETTE.len()];
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
    // How much of the data a box would hide: points along every drawn segment, sampled
    // about every 4 pixels, within the box grown by a marker's size.
    let covered = |r: Rect| {
        let grow = (2 * i64::from(scale) + 2) as f64;
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
                let here = drawable(p).then(|| to_px(*p));
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
    };
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

#[cfg(test)]
mod tests {
    use super::*;

    fn assert_ticks(actual: &[f64], expected: &[f64]) {
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

    fn has_color(img: &Rgb8Image, color: [u8; 3]) -> bool {
        img.data.chunks_exact(3).any(|p| p == color)
    }

    fn example() -> LineChart {
        LineChart {
            title: "Shadow pass time vs. moving cubes".into(),
            x_label: "cubes".into(),
            y_label: "GPU time (ms)".into(),
            series: vec![
                Series::new(
                    "temporal",
                    vec![(100.0, 0.8), (1000.0, 2.1), (4000.0, 6.5), (16000.0, 24.0)],
                ),
                Series::new(
                    "coverage",
                    vec![(100.0, 0.9), (1000.0, 2.6), (4000.0, 8.0), (16000.0, 31.0)],
                ),
                Series::new(
                    "tsm",
                    vec![
                        (100.0, 1.5),
                        (1000.0, 3.0),
                        (4000.0, f64::NAN),
                        (16000.0, 12.0),
                    ],
                ),
                Series::new("reference", vec![]),
            ],
            log_x: true,
            log_y: false,
        }
    }

    #[test]
    fn render_draws_every_series_and_the_title() {
        for (w, h) in [(800, 500), (320, 200), (MIN_WIDTH, MIN_HEIGHT)] {
            let img = render(&example(), w, h).unwrap();
            assert_eq!((img.width, img.height), (w, h));
            assert_eq!(img.data.len(), (w * h * 3) as usize);
            for color in &PALETTE[..3] {
                assert!(has_color(&img, *color), "{w}x{h}: no {color:?}");
            }
            let scale = if w >= 640 { 2 } else { 1 };
            let title_rows = 8 * scale..(8 + GLYPH_HEIGHT) * scale;
            let dark = title_rows
                .flat_map(|y| (0..w).map(move |x| (x, y)))
                .filter(|&(x, y)| img.get(x, y).is_some_and(|p| p.iter().all(|&c| c < 80)))
                .count();
            assert!(dark > 20, "{w}x{h}: title has {dark} dark pixels");
        }
    }

    #[test]
    fn undrawable_points_are_skipped() {
        // Unlabelled, so that the legend's swatches do not show the colours.
        let chart = LineChart {
            series: vec![
                Series::new("", vec![(f64::NAN, 1.0), (1.0, f64::INFINITY)]),
                Series::new("", vec![(0.0, 1.0), (1.0, 0.0), (-1.0, 5.0)]),
                Series::new("", vec![(10.0, 10.0), (100.0, 20.0)]),
            ],
            log_x: true,
            log_y: true,
            ..LineChart::default()
        };
        let img = render(&chart, 400, 300).unwrap();
        assert!(!has_color(&img, PALETTE[0]));
        assert!(!has_color(&img, PALETTE[1]));
        assert!(has_color(&img, PALETTE[2]));

        // Nothing drawable at all, linear and log: axes only.
        for log in [false, true] {
            let chart = LineChart {
                series: vec![Series::new("", vec![(f64::NAN, f64::NAN), (0.0, -1.0)])],
                log_x: log,
                log_y: log,
                ..LineChart::default()
            };
            let img = render(&chart, 400, 300).unwrap();
            assert!(has_color(&img, AXIS));
        }
    }

    #[test]
    fn extreme_values_neither_panic_nor_hang() {
        let chart = LineChart {
            series: vec![
                Series::new("huge", vec![(-f64::MAX, f64::MAX), (f64::MAX, -f64::MAX)]),
                Series::new("tiny", vec![(1e-300, 5e-324), (0.0, 0.0)]),
                Series::new("same", vec![(2.0, 2.0), (2.0, 2.0)]),
            ],
            ..LineChart::default()
        };
        render(&chart, 400, 300).unwrap();
        let log = LineChart {
            log_x: true,
            log_y: true,
            ..chart
        };
        render(&log, 400, 300).unwrap();
    }

    #[test]
    fn bad_size_and_no_series_are_errors() {
        assert!(matches!(
            render(&example(), MIN_WIDTH - 1, 300),
            Err(ChartError::Size { .. })
        ));
        assert!(matches!(
            render(&example(), 300, MAX_SIDE + 1),
            Err(ChartError::Size { .. })
        ));
        assert!(matches!(
            render(&LineChart::default(), 300, 200),
            Err(ChartError::NoSeries)
        ));
    }

    /// Writes example charts for looking at: `cargo test --lib chart -- --ignored`.
    #[test]
    #[ignore]
    fn write_example() {
        let dir = std::env::temp_dir();
        let write = |name: &str, chart: &LineChart, w, h| {
            super::super::write_chart(dir.join(name), chart, w, h).unwrap();
        };
        write("chart-example.png", &example(), 800, 500);
        write("chart-example-small.png", &example(), 320, 200);
        let many = LineChart {
            title: "Error against the reference (a very long title that will not fit at all)"
                .into(),
            x_label: "samples per pixel".into(),
            y_label: "RMSE".into(),
            series: (0..9)
                .map(|i| {
                    let points = (0..=6)
                        .map(|k| {
                            let spp = f64::from(1 << k);
                            (spp, (0.3 + 0.05 * f64::from(i)) / spp.sqrt() - 0.02)
                        })
                        .collect();
                    Series::new(format!("method {i} with a rather long label"), points)
                })
                .collect(),
            log_x: true,
            log_y: true,
        };
        write("chart-example-many.png", &many, 640, 400);
        let linear = LineChart {
            title: "Signed drift".into(),
            x_label: "frame".into(),
            y_label: "offset (px)".into(),
            series: vec![
                Series::new(
                    "a",
                    (0..50)
                        .map(|i| (f64::from(i), (f64::from(i) * 0.3).sin() * 1500.0))
                        .collect(),
                ),
                Series::new(
                    "b",
                    (0..50)
                        .map(|i| (f64::from(i), f64::from(i) * 40.0 - 900.0))
                        .collect(),
                ),
            ],
            ..LineChart::default()
        };
        write("chart-example-linear.png", &linear, 600, 360);
    }
}
