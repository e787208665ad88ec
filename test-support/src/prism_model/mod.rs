//! Independent CPU model of the prism geometry shader (Hong & Oh 2018, §4.1) and a
//! reference rasterizer for it.
//!
//! GPU integration tests use this to predict, per shadow-map pixel, which (depth, time)
//! fragments the collection sub-pass should have stored. It is written from the
//! algorithm description, not from the shader source, so that a shared misreading
//! of the paper is the only way both can agree on a wrong answer.
//!
//! Conventions (mirroring the Vulkan pipeline):
//! * clip space z in [0, w]; framebuffer x = (ndc.x * 0.5 + 0.5) * W and
//!   y = (ndc.y * 0.5 + 0.5) * H (no y flip here: the projection matrix owns that);
//! * `depth` is linear light-view depth `-v.z`, `time` is 0 / 0.5 / 1 at the vertices.
//!
//! The prism construction uses f32 like the shader; the rasterizer uses f64 so that
//! its own rounding is negligible next to the GPU's fixed-point snapping (tests avoid
//! the GPU's tie rules by probing pixels with `edge_margin_at_pixel` > 0.01 px).

mod prism;
mod raster;
#[cfg(test)]
mod tests;

use glam::{Mat4, Vec4};

pub use prism::{edge_cases, prism_triangles};
pub use raster::{edge_margin_at_pixel, fragments_at_pixel};

/// One vertex emitted by the geometry shader.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrismVertex {
    pub clip: Vec4,
    /// Linear light-view depth (`-view.z`), interpolated perspective-correctly.
    pub depth: f32,
    /// Normalised shutter time in [0, 1].
    pub time: f32,
}

/// The light's camera and the shadow-map resolution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSetup {
    pub view: Mat4,
    pub proj: Mat4,
    pub orthographic: bool,
    pub width: u32,
    pub height: u32,
}

/// Which emission case each edge took (for tests that want to make sure both cases are
/// exercised).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EdgeCase {
    /// Side surface split into four triangles around the centre vertex H.
    Centre,
    /// The t=0 and t=1 edges cross on screen; two triangles meet at the crossing X.
    Crossing,
}

/// A fragment the rasterizer produced at one pixel centre.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CpuFragment {
    pub depth: f32,
    pub time: f32,
    /// How fast depth and time change across the screen here (per pixel): a rasterizer that
    /// snaps vertices to its sub-pixel grid may shift them by that much per pixel of snap.
    pub depth_per_pixel: f32,
    pub time_per_pixel: f32,
}
