//! Line charts: series of (x, y) points drawn as polylines with markers over axes with
//! "nice" ticks, a title, axis labels and a legend, on an [`Rgb8Image`]: [`render`] lays the
//! chart out and draws its parts in order, so that text is never drawn over.

use super::ChartError;
use super::data::LineChart;
use super::grid::draw_grid_and_axes;
use super::layout::{Layout, fit_text};
use super::legend::draw_legend;
use super::palette::{BACKGROUND, TEXT};
use super::series::draw_series;
use crate::compare::{Rgb8Image, draw_text, text_width};

/// Smallest chart [`render`] accepts: below it the labels leave no room for the plot.
pub const MIN_WIDTH: u32 = 160;
/// See [`MIN_WIDTH`].
pub const MIN_HEIGHT: u32 = 120;
/// Largest width or height [`render`] accepts, so a bad size is an error rather than a
/// failed multi-gigabyte allocation.
pub const MAX_SIDE: u32 = 16384;

/// Draws `chart` on a `width` x `height` white picture: the title centred at the top, the
/// y label above the y axis (the font cannot rotate), the x label centred below the
/// x axis, axes with tick marks, numeric labels ([`super::format_tick`]) and light grid lines,
/// each series as a 2-pixel polyline with square markers in its [`super::PALETTE`] colour, and a
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
    let layout = Layout::new(chart, width, height)?;
    let mut img = Rgb8Image::new(width, height);
    img.fill_rect(0, 0, width, height, BACKGROUND);
    draw_grid_and_axes(&mut img, &layout);
    draw_series(&mut img, chart, &layout);
    draw_legend(&mut img, chart, &layout);
    draw_titles(&mut img, chart, &layout);
    Ok(img)
}

/// Draws the title centred at the top, the y label above the y axis (the font cannot
/// rotate) and the x label centred below the x axis. Drawn last, so nothing is drawn over
/// them; too-long texts are shortened with "..", so the margins (whose width is at most
/// MIN_WIDTH / 8) always leave room.
fn draw_titles(img: &mut Rgb8Image, chart: &LineChart, layout: &Layout) {
    let Layout {
        width,
        scale,
        margin,
        title_y,
        y_label_y,
        x_label_y,
        left,
        plot_w,
        ..
    } = *layout;
    let text_room = width - 2 * margin;
    let title = fit_text(&chart.title, text_room, scale);
    let title_x = (width - text_width(&title, scale)) / 2;
    draw_text(img, title_x, title_y, &title, scale, TEXT);
    let y_label = fit_text(&chart.y_label, text_room, scale);
    draw_text(img, margin, y_label_y, &y_label, scale, TEXT);
    let x_label = fit_text(&chart.x_label, text_room, scale);
    let x_label_w = text_width(&x_label, scale);
    let x_label_x = (left + plot_w / 2).saturating_sub(x_label_w / 2);
    let x_label_x = x_label_x.min(width - margin - x_label_w).max(margin);
    draw_text(img, x_label_x, x_label_y, &x_label, scale, TEXT);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::chart::Series;
    use crate::chart::palette::{AXIS, PALETTE};
    use crate::compare::GLYPH_HEIGHT;

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
