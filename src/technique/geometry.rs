//! The scene's moving triangles on the GPU: every vertex with its t = 0 and t = 1 positions,
//! three vertices per triangle, and each triangle's albedo and closed flag.

use super::gpu_types::{SceneVertex, TriangleInfo};
use crate::error::{Error, Result};
use crate::gpu::{Buffer, BufferUsage, Context};

pub struct SceneGeometry {
    pub vertices: Buffer,
    pub triangles: Buffer,
    triangle_count: u32,
}

impl SceneGeometry {
    /// `vertices` holds 3 per triangle, in triangle order; triangle i has global id i.
    pub fn new(
        ctx: &Context,
        vertices: &[SceneVertex],
        triangles: &[TriangleInfo],
    ) -> Result<Self> {
        if vertices.len() != 3 * triangles.len() {
            return Err(Error::InvalidArgument(format!(
                "{} vertices for {} triangles (need 3 per triangle)",
                vertices.len(),
                triangles.len()
            )));
        }
        let limit = ctx.max_buffer_bytes();
        let bytes = std::mem::size_of_val(vertices) as u64;
        if bytes > limit {
            return Err(Error::DeviceLimit {
                what: "the vertex buffer",
                count: vertices.len() as u64,
                element_bytes: std::mem::size_of::<SceneVertex>() as u64,
                needed_bytes: bytes,
                limit_bytes: limit,
            });
        }
        let triangle_count = u32::try_from(triangles.len())
            .ok()
            .filter(|&n| n < u32::MAX)
            .ok_or_else(|| Error::InvalidArgument("too many triangles for 32-bit ids".into()))?;
        Ok(Self {
            vertices: Buffer::with_data(
                ctx,
                "scene vertices",
                BufferUsage::HostToDevice,
                vertices,
            )?,
            triangles: Buffer::with_data(
                ctx,
                "scene triangles",
                BufferUsage::HostToDevice,
                triangles,
            )?,
            triangle_count,
        })
    }

    pub fn triangle_count(&self) -> u32 {
        self.triangle_count
    }
}

/// What every pass of a frame reads: the frame parameters ([`super::FrameParams`] in a
/// uniform buffer) and the scene's triangles.
#[derive(Clone, Copy)]
pub struct FrameInputs<'a> {
    pub frame: &'a Buffer,
    pub geometry: &'a SceneGeometry,
}
