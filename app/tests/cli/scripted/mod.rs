//! The `motion-shadows` binary as users script it: `--json` output, scene export and
//! re-import, bench output files, and a clear error without a Vulkan device. Every run has the
//! validation layer on (MOTION_SHADOWS_VALIDATION=1) and fails if it reports anything.

mod animate;
mod bench_presets;
mod no_device;
mod raytrace_method;
mod render_report;
mod scene_export;

use crate::common::temp_dir;
use motion_shadows_app::scene::{BuiltinOptions, builtin};
use std::path::Path;
use std::process::Command;

fn motion_shadows(args: &[&str], out: &Path) -> std::process::Output {
    let output = crate::common::run_with_out(args, out);
    assert!(
        output.status.success(),
        "{args:?} failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

/// Whether a figure a bench wrote (six significant digits) agrees with `expected`, worked
/// out here from other figures it wrote: within the rounding of a quotient of two of them.
fn agrees(written: f64, expected: f64) -> bool {
    written.is_finite() && (written - expected).abs() <= 1e-4 * expected.abs()
}

/// One row of a bench CSV, its cells by column name.
struct CsvRow<'a> {
    header: &'a [&'a str],
    cells: Vec<&'a str>,
}

impl CsvRow<'_> {
    fn cell(&self, column: &str) -> &str {
        let i = (self.header.iter().position(|h| *h == column))
            .unwrap_or_else(|| panic!("no column {column} in {:?}", self.header));
        self.cells[i]
    }

    fn num(&self, column: &str) -> f64 {
        let cell = self.cell(column);
        cell.parse()
            .unwrap_or_else(|_| panic!("{column}: {cell:?} is not a number"))
    }
}
