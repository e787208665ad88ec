//! The on-screen overlay: a few lines of text (the method, time, frame rate, per-pass GPU ms,
//! the map's memory) in the app's bitmap font, rasterized on the host into a fixed-size
//! grid of codes the shading reads by address: 0 leaves the pixel, 1 darkens it (the
//! backdrop), 2 writes white (a glyph's pixel).

use crate::compare::{GLYPH_HEIGHT, Rgb8Image, draw_text, text_width};

/// The overlay's size in pixels: its buffer is made once at this size.
pub const OVERLAY_WIDTH: u32 = 600;
pub const OVERLAY_HEIGHT: u32 = 64;
/// Pixels between lines and around the text.
const LEADING: u32 = 3;
const MARGIN: u32 = 4;

pub const BACKDROP: u32 = 1;
pub const GLYPH: u32 = 2;

/// Lays out text lines; reuses its grids from frame to frame.
pub struct Overlay {
    canvas: Rgb8Image,
    codes: Vec<u32>,
}

impl Default for Overlay {
    fn default() -> Self {
        Self {
            canvas: Rgb8Image::new(OVERLAY_WIDTH, OVERLAY_HEIGHT),
            codes: vec![0; (OVERLAY_WIDTH * OVERLAY_HEIGHT) as usize],
        }
    }
}

impl Overlay {
    /// The codes of `lines` (row after row, `OVERLAY_WIDTH` a row): a backdrop behind the
    /// text's extent, glyph pixels on it. Lines past the overlay's height or width are cut.
    pub fn compose(&mut self, lines: &[String]) -> &[u32] {
        self.canvas.data.fill(0);
        self.codes.fill(0);
        let line_height = GLYPH_HEIGHT + LEADING;
        let mut widest = 0;
        let mut y = MARGIN;
        let mut shown = 0;
        for line in lines {
            if y + GLYPH_HEIGHT + MARGIN > OVERLAY_HEIGHT {
                break;
            }
            draw_text(&mut self.canvas, MARGIN, y, line, 1, [255, 255, 255]);
            widest = widest.max(text_width(line, 1));
            y += line_height;
            shown += 1;
        }
        if shown == 0 {
            return &self.codes;
        }
        let backdrop_width = (widest + 2 * MARGIN).min(OVERLAY_WIDTH);
        let backdrop_height = (shown * line_height - LEADING + 2 * MARGIN).min(OVERLAY_HEIGHT);
        for row in 0..backdrop_height {
            for col in 0..backdrop_width {
                let i = (row * OVERLAY_WIDTH + col) as usize;
                self.codes[i] = if self.canvas.data[3 * i] > 0 {
                    GLYPH
                } else {
                    BACKDROP
                };
            }
        }
        &self.codes
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_is_drawn_on_a_backdrop_that_fits_it() {
        let mut overlay = Overlay::default();
        let codes = overlay.compose(&["T".to_owned()]).to_vec();
        let at = |x: u32, y: u32| codes[(y * OVERLAY_WIDTH + x) as usize];
        // "T" is 5 pixels wide: the backdrop spans it and the margins, nothing further.
        assert_eq!(at(0, 0), BACKDROP);
        assert_eq!(at(5 + 2 * MARGIN - 1, MARGIN), BACKDROP);
        assert_eq!(at(5 + 2 * MARGIN, MARGIN), 0);
        assert_eq!(at(0, GLYPH_HEIGHT + 2 * MARGIN), 0);
        // The T's top bar covers its full width on the first glyph row.
        assert!((MARGIN..MARGIN + 5).all(|x| at(x, MARGIN) == GLYPH));
        // Nothing to show: nothing drawn.
        assert!(overlay.compose(&[]).iter().all(|&c| c == 0));
    }
}
