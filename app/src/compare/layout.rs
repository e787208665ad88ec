//! Labelled side-by-side layouts of comparison pictures (reference, methods, error maps).

use super::Rgb8Image;
use super::font::{GLYPH_HEIGHT, draw_text, text_width};

/// Horizontal gap in pixels between neighbouring panels.
const PANEL_GAP: u32 = 4;
/// Scale of the title font.
const TITLE_SCALE: u32 = 2;
/// Space in pixels around the title text inside its bar.
const TITLE_PADDING: u32 = 4;
/// Height in pixels of the title bar above every panel.
pub const TITLE_BAR_HEIGHT: u32 = GLYPH_HEIGHT * TITLE_SCALE + 2 * TITLE_PADDING;
const TITLE_BACKGROUND: [u8; 3] = [48, 48, 48];
const TITLE_COLOR: [u8; 3] = [255, 255, 255];

/// The panels left to right, 4 px apart, top-aligned below a title bar that shows each
/// panel's label (white on dark grey, centred, clipped to the panel's width).
///
/// The result is `sum of widths + 4 * (panels - 1)` wide and `TITLE_BAR_HEIGHT + tallest
/// panel` high; the gaps and the space below shorter panels are `background`. No panels give
/// an empty 0x0 picture.
pub fn side_by_side(panels: &[(&str, &Rgb8Image)], background: [u8; 3]) -> Rgb8Image {
    if panels.is_empty() {
        return Rgb8Image::new(0, 0);
    }
    let gaps = PANEL_GAP.saturating_mul(u32::try_from(panels.len() - 1).unwrap_or(u32::MAX));
    let width = panels
        .iter()
        .fold(gaps, |sum, (_, panel)| sum.saturating_add(panel.width));
    let tallest = panels.iter().map(|(_, p)| p.height).max().unwrap_or(0);
    let height = TITLE_BAR_HEIGHT.saturating_add(tallest);

    let mut out = Rgb8Image::new(width, height);
    out.fill_rect(0, 0, width, height, background);
    let mut x = 0u32;
    for (label, panel) in panels {
        // The title is drawn on its own canvas of the panel's width, so a long label is cut
        // at the panel's edge instead of running into the neighbour's title.
        let mut title = Rgb8Image::new(panel.width, TITLE_BAR_HEIGHT);
        title.fill_rect(0, 0, panel.width, TITLE_BAR_HEIGHT, TITLE_BACKGROUND);
        let text_x = panel
            .width
            .saturating_sub(text_width(label, TITLE_SCALE))
            .max(2 * TITLE_PADDING)
            / 2;
        draw_text(
            &mut title,
            text_x,
            TITLE_PADDING,
            label,
            TITLE_SCALE,
            TITLE_COLOR,
        );
        out.blit(&title, x, 0);
        out.blit(panel, x, TITLE_BAR_HEIGHT);
        x = x.saturating_add(panel.width).saturating_add(PANEL_GAP);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn solid(width: u32, height: u32, color: [u8; 3]) -> Rgb8Image {
        let mut img = Rgb8Image::new(width, height);
        img.fill_rect(0, 0, width, height, color);
        img
    }

    #[test]
    fn size_is_widths_plus_gaps_by_title_plus_tallest() {
        let a = solid(30, 20, [200, 0, 0]);
        let b = solid(50, 40, [0, 200, 0]);
        let c = solid(10, 5, [0, 0, 200]);
        let bg = [1, 2, 3];
        let out = side_by_side(&[("reference", &a), ("temporal", &b), ("TSM", &c)], bg);
        assert_eq!(out.width, 30 + 50 + 10 + 2 * 4);
        assert_eq!(out.height, TITLE_BAR_HEIGHT + 40);
        assert_eq!(out.data.len(), (out.width * out.height * 3) as usize);

        // Panels top-aligned below the title bar, gaps and space below in the background.
        assert_eq!(out.get(0, TITLE_BAR_HEIGHT), Some([200, 0, 0]));
        assert_eq!(out.get(29, TITLE_BAR_HEIGHT + 19), Some([200, 0, 0]));
        assert_eq!(out.get(0, TITLE_BAR_HEIGHT + 20), Some(bg));
        assert_eq!(out.get(31, TITLE_BAR_HEIGHT), Some(bg));
        assert_eq!(out.get(34, TITLE_BAR_HEIGHT + 39), Some([0, 200, 0]));
        assert_eq!(out.get(88, TITLE_BAR_HEIGHT), Some([0, 0, 200]));
        assert_eq!(out.get(31, 0), Some(bg));

        // Each title bar holds some title text and stays within its panel's columns.
        for (x0, w) in [(0u32, 30u32), (34, 50), (88, 10)] {
            let has_text = (0..TITLE_BAR_HEIGHT)
                .flat_map(|y| (x0..x0 + w).map(move |x| (x, y)))
                .any(|(x, y)| out.get(x, y) == Some(TITLE_COLOR));
            assert!(has_text, "no title over the panel at {x0}");
            assert_eq!(out.get(x0, 0), Some(TITLE_BACKGROUND));
        }
    }

    #[test]
    fn no_panels_give_an_empty_picture() {
        let out = side_by_side(&[], [0; 3]);
        assert_eq!((out.width, out.height, out.data.len()), (0, 0, 0));
    }
}
