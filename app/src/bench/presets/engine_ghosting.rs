//! The engine preset's ghosting picture: where TSM-8's mask is farthest from the truth, its
//! crop beside the temporal mask's and the truth's.

use super::Bench;
use super::engine::{GHOSTING_MAPS, ghosting_picture};
use crate::compare::{Rgb8Image, side_by_side};
use crate::error::Result;
use crate::render::deferred::DeferredResult;

/// The masks of TSM-8, the temporal map and the truth side by side, cropped to the window
/// (a third of the image each way) where TSM-8 is farthest from the truth: its ghosts.
pub(super) fn write_ghosting(
    b: &mut Bench,
    name: &str,
    truth: &DeferredResult,
    tsm: &DeferredResult,
    temporal: &DeferredResult,
) -> Result<()> {
    let (w, h) = (truth.image.width as usize, truth.image.height as usize);
    let (cw, ch) = (w / 3, h / 3);
    // The error summed over each window, by a summed-area table.
    let mut sat = vec![0.0f64; (w + 1) * (h + 1)];
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            let e = if truth.facing[i] {
                (f64::from(tsm.lit[i]) - f64::from(truth.lit[i])).abs()
            } else {
                0.0
            };
            sat[(y + 1) * (w + 1) + x + 1] =
                e + sat[y * (w + 1) + x + 1] + sat[(y + 1) * (w + 1) + x] - sat[y * (w + 1) + x];
        }
    }
    let window = |x: usize, y: usize| {
        sat[(y + ch) * (w + 1) + x + cw] - sat[y * (w + 1) + x + cw] - sat[(y + ch) * (w + 1) + x]
            + sat[y * (w + 1) + x]
    };
    let step = (cw / 8).max(1);
    let (mut best, mut at) = (-1.0, (0, 0));
    for y in (0..=h - ch).step_by(step) {
        for x in (0..=w - cw).step_by(step) {
            if window(x, y) > best {
                best = window(x, y);
                at = (x, y);
            }
        }
    }
    // Scaled up so that the crop reads at the chart's size.
    let zoom = (800 / (3 * cw)).max(1);
    let crop = |lit: &[f32]| {
        let mut img = Rgb8Image::new((cw * zoom) as u32, (ch * zoom) as u32);
        for y in 0..ch * zoom {
            for x in 0..cw * zoom {
                let v = lit[(at.1 + y / zoom) * w + at.0 + x / zoom];
                let g = (v.clamp(0.0, 1.0) * 255.0).round() as u8;
                img.put(x as u32, y as u32, [g, g, g]);
            }
        }
        img
    };
    let panels = [
        (format!("TSM-{GHOSTING_MAPS}"), crop(&tsm.lit)),
        ("temporal".to_owned(), crop(&temporal.lit)),
        ("truth".to_owned(), crop(&truth.lit)),
    ];
    let refs: Vec<(&str, &Rgb8Image)> = panels.iter().map(|(l, i)| (l.as_str(), i)).collect();
    let picture = side_by_side(&refs, [32, 32, 32]);
    b.write_picture(
        &ghosting_picture(name),
        picture.width,
        picture.height,
        &picture.data,
    )
}
