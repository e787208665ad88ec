//! A minimal CSV table writer (RFC 4180 quoting) and consistent number formatting, so that
//! published measurements diff cleanly between runs and load in any spreadsheet.

use std::path::Path;

use super::ChartError;

/// A table of text cells with a header row. Every row has exactly one field per column
/// ([`Table::push`] checks), so the CSV is rectangular.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Table {
    pub columns: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

impl Table {
    /// An empty table with these column names.
    pub fn new<S: Into<String>>(columns: impl IntoIterator<Item = S>) -> Self {
        Self {
            columns: columns.into_iter().map(Into::into).collect(),
            rows: Vec::new(),
        }
    }

    /// Appends `row`, which must have one field per column.
    pub fn push(&mut self, row: Vec<String>) -> Result<(), ChartError> {
        if row.len() != self.columns.len() {
            return Err(ChartError::RowLength {
                expected: self.columns.len(),
                actual: row.len(),
            });
        }
        self.rows.push(row);
        Ok(())
    }

    /// The table as CSV: the header first, then the rows, each line ended by "\n". Fields
    /// containing a comma, a double quote or a line break are quoted, with quotes doubled
    /// (RFC 4180). Rows are written as stored: the fields are public, so a row pushed
    /// around [`Table::push`] is not padded or cut.
    pub fn to_csv(&self) -> String {
        let mut out = String::new();
        for row in std::iter::once(&self.columns).chain(&self.rows) {
            for (i, field) in row.iter().enumerate() {
                if i > 0 {
                    out.push(',');
                }
                push_field(&mut out, field);
            }
            out.push('\n');
        }
        out
    }

    /// Writes [`Table::to_csv`] to `path`, replacing any existing file.
    pub fn write(&self, path: impl AsRef<Path>) -> Result<(), ChartError> {
        let path = path.as_ref();
        std::fs::write(path, self.to_csv()).map_err(|source| ChartError::Io {
            path: path.to_path_buf(),
            source,
        })
    }
}

/// Appends `field`, quoted when it holds a character that would otherwise end it early.
fn push_field(out: &mut String, field: &str) {
    if field.contains([',', '"', '\n', '\r']) {
        out.push('"');
        out.push_str(&field.replace('"', "\"\""));
        out.push('"');
    } else {
        out.push_str(field);
    }
}

/// The decimal digits of `abs` (finite, positive) rounded to `significant` digits, and the
/// decimal exponent of the first one. Rounding through Rust's own scientific formatting
/// means the exponent is that of the rounded value (9.9999996 gives "100000", exponent 1).
pub(super) fn significant_digits(abs: f64, significant: usize) -> (String, i32) {
    let formatted = format!("{:.*e}", significant.saturating_sub(1), abs);
    let (mantissa, exponent) = formatted.split_once('e').unwrap_or((&formatted, "0"));
    // Rust always writes a plain integer exponent here; 0 is only a fallback.
    let exponent = exponent.parse().unwrap_or(0);
    (mantissa.replace('.', ""), exponent)
}

/// `digits` with a decimal point after the first `point` of them (zeros padded on either
/// side as needed) and without trailing fractional zeros.
pub(super) fn place_point(digits: &str, point: i32) -> String {
    let len = i32::try_from(digits.len()).unwrap_or(i32::MAX);
    let mut s = if point <= 0 {
        format!("0.{}{digits}", "0".repeat(point.unsigned_abs() as usize))
    } else if point >= len {
        format!("{digits}{}", "0".repeat((point - len) as usize))
    } else {
        // 0 < point < len, so the cast is lossless and the split is inside the string.
        let (int, frac) = digits.split_at(point as usize);
        format!("{int}.{frac}")
    };
    if s.contains('.') {
        let trimmed = s.trim_end_matches('0').trim_end_matches('.').len();
        s.truncate(trimmed);
    }
    s
}

/// `v` with up to 6 significant digits and no trailing zeros, like C's `%g`: fixed point
/// for magnitudes from 1e-4 to below 1e6 ("0.25", "1234.57"), scientific otherwise
/// ("1.5e-7", "2.5e9"). Zero (also -0) is "0"; non-finite values are "nan", "inf", "-inf",
/// so a failed measurement is visible in the table rather than a parse error downstream.
pub fn fmt_num(v: f64) -> String {
    if v.is_nan() {
        return "nan".into();
    }
    if v.is_infinite() {
        return if v > 0.0 { "inf" } else { "-inf" }.into();
    }
    if v == 0.0 {
        return "0".into();
    }
    let (digits, exponent) = significant_digits(v.abs(), 6);
    let sign = if v < 0.0 { "-" } else { "" };
    if (-4..6).contains(&exponent) {
        format!("{sign}{}", place_point(&digits, exponent + 1))
    } else {
        format!("{sign}{}e{exponent}", place_point(&digits, 1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn strings(fields: &[&str]) -> Vec<String> {
        fields.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn csv_quotes_only_what_needs_it() {
        let mut table = Table::new(["scene", "ms"]);
        table.push(strings(&["plain", "1.5"])).unwrap();
        table.push(strings(&["a,b", "say \"hi\""])).unwrap();
        table.push(strings(&["two\nlines", ""])).unwrap();
        assert_eq!(
            table.to_csv(),
            "scene,ms\nplain,1.5\n\"a,b\",\"say \"\"hi\"\"\"\n\"two\nlines\",\n"
        );
    }

    #[test]
    fn row_length_is_checked() {
        let mut table = Table::new(["a", "b"]);
        let err = table.push(strings(&["1"])).unwrap_err();
        assert!(matches!(
            err,
            ChartError::RowLength {
                expected: 2,
                actual: 1
            }
        ));
        assert!(table.push(strings(&["1", "2", "3"])).is_err());
        assert!(table.rows.is_empty());
    }

    #[test]
    fn write_round_trips_and_names_path_on_error() {
        let path = std::env::temp_dir().join(format!(
            "motion-shadows-chart-{}-table.csv",
            std::process::id()
        ));
        let mut table = Table::new(["x"]);
        table.push(strings(&["1"])).unwrap();
        table.write(&path).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        std::fs::remove_file(&path).unwrap();
        assert_eq!(text, "x\n1\n");

        let bad = path.join("not-a-dir").join("t.csv");
        let err = table.write(&bad).unwrap_err();
        assert!(matches!(err, ChartError::Io { .. }));
        assert!(err.to_string().contains(&*bad.to_string_lossy()));
    }

    #[test]
    fn numbers_are_formatted_consistently() {
        let cases = [
            (0.0, "0"),
            (-0.0, "0"),
            (1.0, "1"),
            (0.25, "0.25"),
            (-2.5, "-2.5"),
            (1234.5678, "1234.57"),
            (123456.0, "123456"),
            (1234567.0, "1.23457e6"),
            (9.9999996, "10"),
            (999999.6, "1e6"),
            (0.0001, "0.0001"),
            (0.00001234, "1.234e-5"),
            (0.1 + 0.2, "0.3"),
            (f64::NAN, "nan"),
            (f64::INFINITY, "inf"),
            (f64::NEG_INFINITY, "-inf"),
            (f64::MAX, "1.79769e308"),
        ];
        for (v, expected) in cases {
            assert_eq!(fmt_num(v), expected, "for {v:e}");
        }
    }
}
