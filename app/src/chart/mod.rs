//! Tables and charts for publishing measurements (used by `motion-shadows bench`): a CSV
//! table writer and a line chart rendered to an 8-bit RGB picture with the comparison
//! module's bitmap font, so that publishing results needs no plotting tool or extra crate.

mod csv;
mod line;

use std::path::{Path, PathBuf};

pub use self::csv::{Table, fmt_num};
pub use self::line::{
    LineChart, MAX_SIDE, MIN_HEIGHT, MIN_WIDTH, PALETTE, Series, format_tick, log_ticks,
    nice_ticks, render,
};

use crate::output::{OutputError, write_rgb8_png};

/// Why a table or chart could not be built or written.
#[derive(Debug, thiserror::Error)]
pub enum ChartError {
    #[error("row has {actual} fields but the table has {expected} columns")]
    RowLength { expected: usize, actual: usize },
    // The reason is repeated in the text (not only in `source()`) because callers often
    // print errors with `{}`, which would otherwise hide why the file could not be written.
    #[error("cannot write {}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error(
        "chart size {width}x{height} is outside the supported range \
         ({MIN_WIDTH}x{MIN_HEIGHT} to {MAX_SIDE}x{MAX_SIDE})"
    )]
    Size { width: u32, height: u32 },
    #[error("the chart has no series to draw")]
    NoSeries,
    #[error(transparent)]
    Output(#[from] OutputError),
}

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
