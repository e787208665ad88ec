//! Drawing primitives clipped to a rectangle: pixels, 2-pixel lines and square markers.

use crate::compare::Rgb8Image;

/// A rectangle in image pixels, edges included: the plot area, or a clip region.
#[derive(Clone, Copy)]
pub(super) struct Rect {
    pub(super) left: i64,
    pub(super) top: i64,
    pub(super) right: i64,
    pub(super) bottom: i64,
}

impl Rect {
    fn contains(&self, x: i64, y: i64) -> bool {
        (self.left..=self.right).contains(&x) && (self.top..=self.bottom).contains(&y)
    }
}

/// Sets pixel (`x`, `y`) when it lies inside `clip`.
fn put_clipped(img: &mut Rgb8Image, clip: Rect, x: i64, y: i64, color: [u8; 3]) {
    if clip.contains(x, y) {
        // Inside the clip rectangle, which lies inside the image, so both fit in u32.
        if let (Ok(x), Ok(y)) = (u32::try_from(x), u32::try_from(y)) {
            img.put(x, y, color);
        }
    }
}

/// Clips the segment from `a` to `b` to `clip` (Liang-Barsky), so that far-off endpoints
/// never make the rasteriser walk millions of pixels outside the picture.
fn clip_segment(a: (f64, f64), b: (f64, f64), clip: Rect) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, a.0 - clip.left as f64),
        (dx, clip.right as f64 - a.0),
        (-dy, a.1 - clip.top as f64),
        (dy, clip.bottom as f64 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    let clipped = (
        (a.0 + t0 * dx, a.1 + t0 * dy),
        (a.0 + t1 * dx, a.1 + t1 * dy),
    );
    (t0 <= t1 && t0.is_finite() && t1.is_finite()).then_some(clipped)
}

/// A 2-pixel-thick line from `a` to `b`, clipped to `clip` (Bresenham, each step a 2x2
/// block).
pub(super) fn draw_line(
    img: &mut Rgb8Image,
    a: (f64, f64),
    b: (f64, f64),
    clip: Rect,
    color: [u8; 3],
) {
    let Some((a, b)) = clip_segment(a, b, clip) else {
        return;
    };
    // Clipped into the picture, so the rounded coordinates are small.
    let (mut x, mut y) = (a.0.round() as i64, a.1.round() as i64);
    let (x1, y1) = (b.0.round() as i64, b.1.round() as i64);
    let (dx, dy) = ((x1 - x).abs(), -(y1 - y).abs());
    let (sx, sy) = ((x1 - x).signum(), (y1 - y).signum());
    let mut err = dx + dy;
    loop {
        for (ox, oy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            put_clipped(img, clip, x + ox, y + oy, color);
        }
        if x == x1 && y == y1 {
            break;
        }
        let e2 = 2 * err;
        if e2 >= dy {
            err += dy;
            x += sx;
        }
        if e2 <= dx {
            err += dx;
            y += sy;
        }
    }
}

/// A filled square marker of side `2 * half + 1` centred on `p`, clipped to `clip`.
pub(super) fn draw_marker(
    img: &mut Rgb8Image,
    p: (f64, f64),
    half: i64,
    clip: Rect,
    color: [u8; 3],
) {
    let (cx, cy) = (p.0.round() as i64, p.1.round() as i64);
    for y in cy - half..=cy + half {
        for x in cx - half..=cx + half {
            put_clipped(img, clip, x, y, color);
        }
    }
}

/// `v` as a pixel coordinate (u32), clamped into the picture.
pub(super) fn px(v: i64) -> u32 {
    u32::try_from(v.max(0)).unwrap_or(u32::MAX)
}
