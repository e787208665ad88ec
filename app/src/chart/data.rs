//! What a line chart shows: its series, titles and axis scales, and which of its points can
//! be drawn.

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

/// A line chart; see [`super::render`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LineChart {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
    pub log_x: bool,
    pub log_y: bool,
}

impl LineChart {
    /// Whether [`super::render`] can place the point: both coordinates finite, and > 0 on a log
    /// axis.
    pub(super) fn drawable(&self, &(x, y): &(f64, f64)) -> bool {
        x.is_finite() && y.is_finite() && (!self.log_x || x > 0.0) && (!self.log_y || y > 0.0)
    }

    /// Every series' drawable points.
    pub(super) fn drawable_points(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.series
            .iter()
            .flat_map(|s| s.points.iter().copied().filter(|p| self.drawable(p)))
    }
}
