//! What a host hands the mask passes: its images (depth, normals, motion, ids, positions)
//! and camera, with the documented defaults for what it leaves out.

use ash::vk;
use glam::Mat4;

/// How the host's normal image stores a world-space normal in its rgb channels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NormalEncoding {
    /// Signed components in [-1, 1] (float or snorm formats).
    Signed,
    /// `n * 0.5 + 0.5` in [0, 1] (unorm formats).
    Unorm,
}

/// The host's normal image.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NormalImage {
    /// A view of a sampled image (world-space normal in rgb), the size of the depth image.
    pub view: vk::ImageView,
    /// Its layout while the pass runs (e.g. `SHADER_READ_ONLY_OPTIMAL`).
    pub layout: vk::ImageLayout,
    /// How its values encode the normal.
    pub encoding: NormalEncoding,
}

/// The host's motion image: how far each G-buffer point moves during the shutter, so that
/// the mask follows moving receivers (a character's own faces, a moving floor) instead of
/// testing them where they are at one time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MotionImage {
    /// A view of a sampled float image (R16G16B16A16_SFLOAT or R32G32B32A32_SFLOAT; any
    /// format the shader reads as floats), the size of the depth image: rgb = the surface
    /// point's world-space displacement over the whole shutter, `p(1) - p(0)` (a = unused).
    /// An engine whose shutter runs from the previous frame to this one writes
    /// `position_now - position_previous`, its motion vectors in world space.
    pub view: vk::ImageView,
    /// Its layout while the pass runs (e.g. `SHADER_READ_ONLY_OPTIMAL`).
    pub layout: vk::ImageLayout,
}

/// The host's world-position image: where each G-buffer point is at the mask's time, in
/// full float. Optional, and the precise choice: a receiver rebuilt from a standard 32-bit
/// float depth buffer is off its own surface by about `z^2 / near * 6e-8` along the view
/// ray, enough, at grazing light, for its coplanar neighbours to shadow it (acne), whatever
/// the receiver test. Reversed Z shrinks that error; a position image removes it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PositionImage {
    /// A view of a sampled float image (R32G32B32A32_SFLOAT: half floats are too coarse
    /// for the same reason), the size of the depth image: rgb = the world position (a =
    /// unused).
    pub view: vk::ImageView,
    /// Its layout while the pass runs (e.g. `SHADER_READ_ONLY_OPTIMAL`).
    pub layout: vk::ImageLayout,
}

/// The host's triangle-id image: which triangle each pixel shows, so that a receiver's own
/// triangle never shadows it. Required on a depth-line map with moving receivers
/// ([`MaskInputs::motion`]): [`VisibilityMaskPass::record`](crate::technique::VisibilityMaskPass::record) refuses those dispatches without
/// it; recommended everywhere (the plane test, `LightView::receiver_plane`, was written to
/// rely on it).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TriangleIdImage {
    /// A view of a sampled R32_UINT image, the size of the depth image: the triangle's
    /// global id in the [`DrawList`](crate::technique::DrawList) the map was built from (the draw's
    /// first id plus the primitive's index), `u32::MAX` for none.
    pub view: vk::ImageView,
    /// Its layout while the pass runs (e.g. `SHADER_READ_ONLY_OPTIMAL`).
    pub layout: vk::ImageLayout,
}

/// What one mask dispatch reads and writes: the host's images and camera.
///
/// Build it with [`MaskInputs::new`] (the five inputs every dispatch needs) and the `with_*`
/// methods for the optional ones, or field by field (every field is public; there is no
/// `Default`: a depth and an output view have none):
///
/// ```no_run
/// # use motion_shadows::ash::vk;
/// # use motion_shadows::glam::Mat4;
/// # use motion_shadows::technique::{MaskInputs, MotionImage, NormalEncoding, NormalImage};
/// # let (depth, output, normals, motion) = (vk::ImageView::null(), vk::ImageView::null(),
/// #     vk::ImageView::null(), vk::ImageView::null());
/// # let inv_view_proj = Mat4::IDENTITY;
/// let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
/// let inputs = MaskInputs::new(depth, read, output, (1280, 720), inv_view_proj)
///     .with_normals(NormalImage { view: normals, layout: read, encoding: NormalEncoding::Unorm })
///     .with_motion(MotionImage { view: motion, layout: read }, 1.0);
/// ```
///
/// Conventions (what the pass does with them):
/// - **Normals** may face either way: the pass turns each normal (read from `normals`, or
///   rebuilt from the depth neighbours without them) to the light's side before it offsets
///   the receiver along it. (`ms_visibility` and `ms_lit_fraction`, called in a host's own
///   shader, take the normal as given: there it must face the light.)
/// - **1 means lit**: pixels holding `background_depth` (no surface), and points outside the
///   light's view (behind a spot light, or outside the square its projection covers; the
///   depth is not clipped to the near and far planes), get 1.
/// - **Visibility only**: the mask is the share of the shutter the point sees the light,
///   nothing else. Inside the map's square but outside a spot light's cone it is still that
///   share (the square's corners); the cone, distance falloff and `dot(n, l)` are the host's
///   lighting, multiplied in with the mask.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaskInputs {
    /// A view of the host's depth image (depth aspect, sampled usage), `size` texels.
    pub depth: vk::ImageView,
    /// Its layout while the pass runs (`DEPTH_STENCIL_READ_ONLY_OPTIMAL`,
    /// `DEPTH_READ_ONLY_OPTIMAL`, `SHADER_READ_ONLY_OPTIMAL` or synchronization2's
    /// `READ_ONLY_OPTIMAL`, which the deferred example uses for every G-buffer image).
    pub depth_layout: vk::ImageLayout,
    /// The host's normal image, or `None` to rebuild normals from the depth neighbours.
    pub normals: Option<NormalImage>,
    /// A view of the output image: single channel (R8_UNORM, R16_UNORM, R16_SFLOAT or
    /// R32_SFLOAT), storage usage, `size` texels, in `GENERAL` layout.
    pub output: vk::ImageView,
    /// Pixels.
    pub size: (u32, u32),
    /// The inverse of the host's view-projection matrix (Vulkan clip space: x, y in [-1, 1]
    /// with y down, depth as stored in the depth image).
    pub inv_view_proj: Mat4,
    /// The depth image's clear value (1 for a standard depth buffer, 0 for reversed Z):
    /// pixels holding it have no surface and get 1 (lit).
    pub background_depth: f32,
    /// The host's motion image, or `None`: every receiver stands still for the whole
    /// shutter (the static mask, cheaper).
    pub motion: Option<MotionImage>,
    /// The shutter time in [0, 1] the depth (and normal) image shows: the point of pixel p
    /// is at `position(p) + (t - time) * motion(p)` at time t. Engines draw their current
    /// frame at shutter close: 1. Read only with `motion`.
    pub time: f32,
    /// The host's triangle-id image, or `None`: no receiver is known to lie on a triangle.
    /// Required on a depth-line map with `motion` (see [`VisibilityMaskPass::record`](crate::technique::VisibilityMaskPass::record)).
    pub ids: Option<TriangleIdImage>,
    /// The host's world-position image, or `None`: positions rebuilt from the depth.
    pub positions: Option<PositionImage>,
    /// With `motion`: whether a pixel whose motion is exactly zero is tested as a standing
    /// receiver is, at its plane's depth at the texel centre without the normal offset (the
    /// receiver-plane test), instead of as the map's light says. Why: the light's normal
    /// offset suits receivers that move (a surface that turns during the shutter leaves
    /// its G-buffer plane) but costs still ones their contact shadows. Wants `ids` (the
    /// plane test relies on the own-triangle skip). Visibility mask only.
    pub plane_test_where_still: bool,
}

impl MaskInputs {
    /// The inputs every dispatch needs (see the fields), with the optional ones at their
    /// defaults: no normal image (normals rebuilt from the depth neighbours),
    /// `background_depth` 1 (a standard depth buffer; [`Self::with_background_depth`] for
    /// reversed Z), no motion (every receiver stands still; `time` 1), no triangle ids, no
    /// position image, the map light's receiver test for every moving-mask pixel.
    pub fn new(
        depth: vk::ImageView,
        depth_layout: vk::ImageLayout,
        output: vk::ImageView,
        size: (u32, u32),
        inv_view_proj: Mat4,
    ) -> Self {
        Self {
            depth,
            depth_layout,
            normals: None,
            output,
            size,
            inv_view_proj,
            background_depth: 1.0,
            motion: None,
            time: 1.0,
            ids: None,
            positions: None,
            plane_test_where_still: false,
        }
    }

    /// With the host's normal image ([`Self::normals`]).
    pub fn with_normals(self, normals: NormalImage) -> Self {
        Self {
            normals: Some(normals),
            ..self
        }
    }

    /// With the depth image's clear value ([`Self::background_depth`]: 0 for reversed Z).
    pub fn with_background_depth(self, background_depth: f32) -> Self {
        Self {
            background_depth,
            ..self
        }
    }

    /// With the host's motion image and the shutter time its depth image shows
    /// ([`Self::motion`], [`Self::time`]: 1 for an engine that draws its current frame at
    /// shutter close).
    pub fn with_motion(self, motion: MotionImage, time: f32) -> Self {
        Self {
            motion: Some(motion),
            time,
            ..self
        }
    }

    /// With the host's triangle-id image ([`Self::ids`]).
    pub fn with_ids(self, ids: TriangleIdImage) -> Self {
        Self {
            ids: Some(ids),
            ..self
        }
    }

    /// With the host's world-position image ([`Self::positions`]).
    pub fn with_positions(self, positions: PositionImage) -> Self {
        Self {
            positions: Some(positions),
            ..self
        }
    }

    /// With still pixels of a moving mask given the receiver-plane test
    /// ([`Self::plane_test_where_still`]).
    pub fn with_plane_test_where_still(self) -> Self {
        Self {
            plane_test_where_still: true,
            ..self
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ash::vk::Handle;

    #[test]
    fn new_fills_the_optional_inputs_with_the_documented_defaults() {
        let view = |n| vk::ImageView::from_raw(n);
        let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        let m = Mat4::from_scale(glam::Vec3::splat(2.0));
        let base = MaskInputs::new(view(1), read, view(2), (64, 32), m);
        assert_eq!(
            base,
            MaskInputs {
                depth: view(1),
                depth_layout: read,
                normals: None,
                output: view(2),
                size: (64, 32),
                inv_view_proj: m,
                background_depth: 1.0,
                motion: None,
                time: 1.0,
                ids: None,
                positions: None,
                plane_test_where_still: false,
            }
        );
        let normals = NormalImage {
            view: view(3),
            layout: read,
            encoding: NormalEncoding::Unorm,
        };
        let motion = MotionImage {
            view: view(4),
            layout: read,
        };
        let ids = TriangleIdImage {
            view: view(5),
            layout: read,
        };
        let positions = PositionImage {
            view: view(6),
            layout: read,
        };
        let full = base
            .with_normals(normals)
            .with_background_depth(0.0)
            .with_motion(motion, 0.25)
            .with_ids(ids)
            .with_positions(positions)
            .with_plane_test_where_still();
        assert_eq!(
            full,
            MaskInputs {
                normals: Some(normals),
                background_depth: 0.0,
                motion: Some(motion),
                time: 0.25,
                ids: Some(ids),
                positions: Some(positions),
                plane_test_where_still: true,
                ..base
            }
        );
    }

    /// The host's images as the mask uses them, known before the frame is recorded (the
    /// host's barrier into those layouts comes first): every input view sampled by compute
    /// shaders in the layout the inputs give, the output written by compute shaders in
    /// `GENERAL`, and nothing else.
    #[test]
    fn image_accesses_declare_each_view_in_its_layout_and_the_output_written() {
        use crate::technique::{AccessData, Resource, ResourceUse};
        let view = |n| vk::ImageView::from_raw(n);
        let (read, depth_read) = (
            vk::ImageLayout::READ_ONLY_OPTIMAL,
            vk::ImageLayout::DEPTH_STENCIL_READ_ONLY_OPTIMAL,
        );
        let inputs = MaskInputs::new(view(1), depth_read, view(2), (8, 8), Mat4::IDENTITY)
            .with_motion(
                MotionImage {
                    view: view(4),
                    layout: read,
                },
                1.0,
            )
            .with_ids(TriangleIdImage {
                view: view(5),
                layout: read,
            });
        let compute = vk::PipelineStageFlags2::COMPUTE_SHADER;
        let uses = |view, layout, access, writes| {
            let at = AccessData {
                stages: compute,
                access,
            };
            ResourceUse {
                resource: Resource::ImageView { view, layout },
                first: at,
                last: at,
                writes,
            }
        };
        let sampled = vk::AccessFlags2::SHADER_SAMPLED_READ;
        let mut expected = vec![
            uses(view(1), depth_read, sampled, false),
            uses(view(4), read, sampled, false),
            uses(view(5), read, sampled, false),
            uses(
                view(2),
                vk::ImageLayout::GENERAL,
                vk::AccessFlags2::SHADER_STORAGE_WRITE,
                true,
            ),
        ];
        let key = |u: &ResourceUse| match u.resource {
            Resource::ImageView { view, .. } => view.as_raw(),
            _ => u64::MAX,
        };
        let mut got = inputs.image_accesses().uses;
        got.sort_by_key(key);
        expected.sort_by_key(key);
        assert_eq!(got, expected);
    }
}
