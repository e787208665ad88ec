//! Writing a chart as a PNG file.

use std::path::Path;

use super::ChartError;
use super::data::LineChart;
use super::line::render;
use crate::output::write_rgb8_png;

/// Renders `chart` (see [`render`]) and writes it as a PNG at `path`.
pub fn write_chart(
    path: impl AsRef<Path>,
    chart: &LineChart,
    width: u32,
    height: u32,
) -> Result<(), ChartError> {
    let image = render(chart, width, height)?;
    write_rgb8_png(path.as_ref(), image.width, image.height, &image.data)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::chart::Series;

    #[test]
    fn write_chart_writes_decodable_png() {
        let path = std::env::temp_dir().join(format!(
            "motion-shadows-chart-{}-write.png",
            std::process::id()
        ));
        let chart = LineChart {
            title: "t".into(),
            series: vec![Series::new("a", vec![(1.0, 2.0), (2.0, 3.0)])],
            ..LineChart::default()
        };
        write_chart(&path, &chart, 320, 200).unwrap();
        let decoded = image::open(&path).unwrap().to_rgb8();
        std::fs::remove_file(&path).unwrap();
        assert_eq!(decoded.dimensions(), (320, 200));
    }

    #[test]
    fn write_chart_reports_bad_path_and_size() {
        let path = std::env::temp_dir()
            .join("motion-shadows-chart-no-such-dir")
            .join("x.png");
        let chart = LineChart {
            series: vec![Series::new("a", vec![(1.0, 2.0)])],
            ..LineChart::default()
        };
        let err = write_chart(&path, &chart, 320, 200).unwrap_err();
        assert!(err.to_string().contains(&*path.to_string_lossy()), "{err}");
        assert!(matches!(
            write_chart(&path, &chart, 10, 10),
            Err(ChartError::Size {
                width: 10,
                height: 10
            })
        ));
    }
}
