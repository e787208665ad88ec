//! Tables and charts for publishing measurements (used by `motion-shadows bench`): a CSV
//! table writer and a line chart rendered to an 8-bit RGB picture with the comparison
//! module's bitmap font, so that publishing results needs no plotting tool or extra crate.

mod axis;
mod csv;
mod data;
mod grid;
mod layout;
mod legend;
mod line;
mod palette;
mod pixels;
mod png;
mod series;
mod ticks;

use std::path::PathBuf;

pub use self::csv::{Table, fmt_num};
pub use self::data::{LineChart, Series};
pub use self::line::{MAX_SIDE, MIN_HEIGHT, MIN_WIDTH, render};
pub use self::palette::PALETTE;
pub use self::png::write_chart;
pub use self::ticks::{format_tick, log_ticks, nice_ticks};

use crate::output::OutputError;

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
