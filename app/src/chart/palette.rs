//! The chart's colours.

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

pub(super) const BACKGROUND: [u8; 3] = [255, 255, 255];
pub(super) const TEXT: [u8; 3] = [30, 30, 30];
pub(super) const AXIS: [u8; 3] = [70, 70, 70];
pub(super) const GRID: [u8; 3] = [230, 230, 230];
pub(super) const LEGEND_BORDER: [u8; 3] = [170, 170, 170];

/// The colour of series `index`.
pub(super) fn series_color(index: usize) -> [u8; 3] {
    PALETTE[index % PALETTE.len()]
}
