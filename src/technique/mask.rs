//! The visibility-mask pass, for deferred engines: from the host's depth image (and normal
//! image, if it has one) and its camera, the fraction of the shutter each pixel sees the
//! light, written into a host-owned single-channel image that the host's own lighting
//! multiplies in. The fraction is exact for receivers that stay put during the shutter
//! (`ms_lit_fraction` in `glsl/motion_shadows.glsl`), so the mask has no time noise.
//!
//! Host images cannot be reached by device address, so this pass, unlike the others, binds a
//! descriptor set: one [`MaskBindings`] per use in flight (per frame in flight and light).

use super::image_pass::ImagePass;
use super::mask_ids::ids_required_by;
use super::mask_queue::{DEFAULT_MASK_FOLLOW_UP_ROUNDS, MaskQueue};
use super::push_constants::{MaskPush, PushBlock};
use super::shaders;
use super::shadow_map::TemporalShadowMap;
use crate::error::{Error, Result};
use crate::gpu::{
    Access, Buffer, BufferUsage, Context, Image, ImageBindings, image_barrier, memory_barrier,
};
use ash::vk;
use glam::Mat4;

/// Whether the device has the subgroup vote the mask's shader needs.
mod subgroup;
/// The walks' loop budget and follow-up rounds on a loop-limited device.
mod walks;

/// What one mask dispatch binds and reports: the descriptor set of the host's depth, normal
/// and output views, the overflow queues of walks that did not finish in one invocation, and
/// the count of pixels whose lookups may have been cut short. One per dispatch that may be
/// pending at the same time (per frame in flight and light), used once per command buffer.
/// Made by [`VisibilityMaskPass::bindings`].
pub struct MaskBindings {
    images: ImageBindings,
    /// One u32: pixels past the device's loop budget (written by the shader, read by the host).
    over_budget: Buffer,
    /// Where moving receivers' walks that stopped go on (a device with a loop limit only).
    queue: MaskQueue,
    /// A 1x1 R32_UINT image bound in place of the host's id image when it has none: the
    /// shader never reads it then, but the binding is an unsigned-integer sampler, and a view
    /// of another numeric format there is invalid.
    no_ids: Image,
}

impl MaskBindings {
    /// The bindings' allocations, by name, with their bytes (see
    /// [`super::TemporalShadowMap::allocations`]); the descriptor pool is not memory of the
    /// allocator.
    pub fn allocations(&self) -> Vec<(&str, u64)> {
        vec![
            (self.over_budget.name(), self.over_budget.allocated_bytes()),
            (MaskQueue::NAME, self.queue.buffer().allocated_bytes()),
            (
                "visibility-mask stand-in id image",
                self.no_ids.allocated_bytes(),
            ),
        ]
    }

    /// Pixels of the last dispatch recorded with these bindings whose lookups ran so many
    /// loop iterations that a device with a loop limit
    /// ([`crate::gpu::DeviceInfo::shader_loop_limit`], lavapipe) may have cut them short:
    /// their mask values may be wrong. Read after that command buffer completed. Always 0 on
    /// devices without such a limit. A moving receiver's walk along its path goes on over
    /// follow-up rounds ([`VisibilityMaskPass::with_follow_up_rounds`]), so a long path alone
    /// is not counted; where it is not 0, one texel's list is too long for this device at
    /// those pixels (its shadow comes and goes more than 32 times in the shutter over
    /// hundreds of ranges), a path needed more rounds than recorded, or the mask had more
    /// pixels than the bindings were made for, and the host should not trust the mask.
    pub fn read_over_budget_pixels(&self) -> Result<u32> {
        Ok(self.over_budget.read::<u32>(1)?[0])
    }
}

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
/// ([`MaskInputs::motion`]): [`VisibilityMaskPass::record`] refuses those dispatches without
/// it; recommended everywhere (the plane test, `LightView::receiver_plane`, was written to
/// rely on it).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TriangleIdImage {
    /// A view of a sampled R32_UINT image, the size of the depth image: the triangle's
    /// global id in the [`DrawList`](super::DrawList) the map was built from (the draw's
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
    /// `DEPTH_READ_ONLY_OPTIMAL` or `SHADER_READ_ONLY_OPTIMAL`).
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
    /// Required on a depth-line map with `motion` (see [`VisibilityMaskPass::record`]).
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

use super::gpu_constants::{
    MASK_HAS_IDS as HAS_IDS, MASK_HAS_NORMALS as HAS_NORMALS, MASK_HAS_POSITIONS as HAS_POSITIONS,
    MASK_NORMALS_UNORM as NORMALS_UNORM, MASK_STILL_PIXELS_PLANE as STILL_PIXELS_PLANE,
};

/// `MASK_HAS_POSITIONS` where the host gives a position image (both mask passes).
pub(super) fn mask_position_flag(inputs: &MaskInputs) -> u32 {
    if inputs.positions.is_some() {
        HAS_POSITIONS
    } else {
        0
    }
}

/// Where the follow-up rounds' pipelines start among the pass's variants.
const FOLLOW_UP_VARIANTS: usize = 4;

/// The visibility-mask pass. Immutable after creation.
///
/// For each pixel of the host's depth image: the fraction of the shutter during which that
/// surface point sees the map's light, in [0, 1], written into the host's output image.
/// What it assumes and what it writes where nothing shadows (normals may face either way;
/// background and points outside the light's view get 1; visibility only, no spot cone or
/// `dot(n, l)`) is listed under [`MaskInputs`].
pub struct VisibilityMaskPass {
    pass: ImagePass,
    loop_budget: u32,
    follow_up_rounds: u32,
}

impl VisibilityMaskPass {
    /// Creates the pass. Errors when the device lacks the subgroup vote operations in compute
    /// shaders, or does not have `shaderStorageImageWriteWithout
    /// Format` enabled (a headless context enables it where supported; a host says so in
    /// `Context::from_raw`), which lets one pipeline write any of the output formats.
    pub fn new(ctx: &Context) -> Result<Self> {
        subgroup::check_subgroup_vote(ctx.info().subgroup_vote_in_compute)?;
        let sampled = vk::DescriptorType::COMBINED_IMAGE_SAMPLER;
        let pass = ImagePass::new(
            ctx,
            "the visibility-mask pass",
            &[
                sampled,
                sampled,
                vk::DescriptorType::STORAGE_IMAGE,
                sampled,
                sampled,
                sampled,
            ],
            MaskPush::BYTES,
            ("visibility_mask.comp", shaders::VISIBILITY_MASK_COMP),
            // (MOVING, EXACT, FOLLOW_UP): receivers standing still or moving, against a map
            // built for the depth-line test or for the exact lookup; the first dispatch, then
            // the follow-up rounds' (variant + FOLLOW_UP_VARIANTS).
            &[
                &[0, 0, 0],
                &[1, 0, 0],
                &[0, 1, 0],
                &[1, 1, 0],
                &[0, 0, 1],
                &[1, 0, 1],
                &[0, 1, 1],
                &[1, 1, 1],
            ],
        )?;
        Ok(Self {
            pass,
            loop_budget: ctx.info().shader_loop_budget(),
            follow_up_rounds: DEFAULT_MASK_FOLLOW_UP_ROUNDS,
        })
    }

    /// The bindings for one dispatch in flight, of a mask of up to `size` pixels. On a device
    /// with a loop limit (lavapipe) they hold the overflow queues: two entries of 28 bytes per
    /// pixel and two pools of unions carried by exact walks stopped within a texel's list, 64
    /// bytes per eight pixels: 72 bytes a pixel (elsewhere nothing, as no walk stops there).
    pub fn bindings(&self, ctx: &Context, size: (u32, u32)) -> Result<MaskBindings> {
        let rounds = self.rounds();
        let pixels = if rounds > 0 {
            size.0.saturating_mul(size.1)
        } else {
            0
        };
        Ok(MaskBindings {
            images: self.pass.layout.allocate()?,
            queue: MaskQueue::new(ctx, pixels, rounds)?,
            over_budget: Buffer::new(
                ctx,
                "visibility-mask over-budget pixels",
                4,
                BufferUsage::DeviceToHost,
            )?,
            no_ids: Image::new(
                ctx,
                "visibility-mask stand-in id image",
                (1, 1, 1),
                vk::Format::R32_UINT,
                vk::ImageUsageFlags::SAMPLED,
            )?,
        })
    }

    /// Records the mask of `map` (after its generation pass) for the host's images.
    ///
    /// Errors, recording nothing, without `inputs.ids` where a receiver's own triangle would
    /// shadow it: on a map whose last collection was for depth lines
    /// ([`super::Lookup::DepthLine`]) with `inputs.motion` (moving receivers, and so
    /// `plane_test_where_still`). Measured on a tumbling box against the ray tracer
    /// (docs/src/deferred-frame.md#triangle-ids): there no normal offset clears a turning
    /// face of its own triangle's depth lines. Still receivers (plane test or offset) and
    /// maps built for [`super::Lookup::Exact`] came out the same without ids.
    ///
    /// # Safety
    /// - `cmd` was allocated from the device the pass was made on, is recording, outside any
    ///   render pass or dynamic rendering, on a queue with compute.
    /// - `bindings` was made by this pass and no command buffer using it is pending or has
    ///   it bound in `cmd` (its set is rewritten here).
    /// - The views are valid, of the device, with the usages, sizes, formats and layouts
    ///   [`MaskInputs`] states, and stay alive until `cmd` completes.
    /// - The host has made its writes to the depth and normal images visible to
    ///   `COMPUTE_SHADER` sampled reads, and ordered earlier accesses of the output image
    ///   before `COMPUTE_SHADER` storage writes, with its own barriers (image layout
    ///   transitions included).
    /// - The map's collection and generation passes were recorded earlier in `cmd` or in a
    ///   command buffer submitted before it (their closing barrier makes the ranges visible).
    ///
    /// Synchronization: leaves the output written by `COMPUTE_SHADER` with
    /// `SHADER_STORAGE_WRITE`, in `GENERAL` layout; the host's barrier makes it visible to
    /// its lighting. Records its own barriers around the bindings' counter and queues (a
    /// transfer fill before the first dispatch, a compute-to-compute-and-indirect barrier
    /// before each follow-up round, a compute-to-host barrier after the last: after `cmd`
    /// completes, [`MaskBindings::read_over_budget_pixels`] reads the counter). State
    /// changed: the bound compute pipeline, descriptor set 0 of the compute bind point, push
    /// constants.
    pub unsafe fn record(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        bindings: &mut MaskBindings,
        inputs: &MaskInputs,
        map: &TemporalShadowMap,
    ) -> Result<()> {
        if map.recorded_for_moving_light() && inputs.motion.is_none() {
            // Under a moving light no receiver stands still in the light's frame: only the
            // moving receivers' walk follows one.
            return Err(Error::InvalidArgument(
                "a map built for a moving light (LightView::end) needs the moving receivers' \
                 mask (MaskInputs::motion; zero motion for still pixels)"
                    .to_owned(),
            ));
        }
        if inputs.ids.is_none() {
            if let Some(why) = ids_required_by(inputs, map.recorded_lookup()) {
                return Err(Error::InvalidArgument(format!(
                    "the visibility mask needs the host's triangle-id image (MaskInputs::ids, a TriangleIdImage) {why}"
                )));
            }
        }
        let depth = (inputs.depth, inputs.depth_layout);
        // Without a normal or motion image the depth view stands in (never read: the flag
        // and the variant say so).
        let normals = inputs.normals.map_or(depth, |n| (n.view, n.layout));
        let motion = inputs.motion.map_or(depth, |m| (m.view, m.layout));
        let read_only = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        let ids = inputs
            .ids
            .map_or((bindings.no_ids.layer_view(0), read_only), |i| {
                (i.view, i.layout)
            });
        let positions = inputs.positions.map_or(depth, |p| (p.view, p.layout));
        let output = (inputs.output, vk::ImageLayout::GENERAL);
        // SAFETY: the caller's contract (the set is not in use; the views are valid).
        unsafe {
            bindings
                .images
                .write(&[depth, normals, output, motion, ids, positions])
        };
        let flags = match inputs.normals {
            Some(NormalImage {
                encoding: NormalEncoding::Unorm,
                ..
            }) => HAS_NORMALS | NORMALS_UNORM,
            Some(_) => HAS_NORMALS,
            None => 0,
        } | if inputs.ids.is_some() { HAS_IDS } else { 0 }
            | mask_position_flag(inputs)
            | if inputs.plane_test_where_still {
                STILL_PIXELS_PLANE
            } else {
                0
            };
        let constants = MaskPush {
            inv_view_proj: inputs.inv_view_proj,
            map: map.header_address(),
            size: [inputs.size.0, inputs.size.1],
            background_depth: inputs.background_depth,
            flags,
            over_budget: bindings.over_budget.device_address(),
            loop_budget: self.loop_budget,
            time: inputs.time,
            queue: bindings.queue.buffer().device_address(),
            round: 0,
            rounds: 0,
            capacity: bindings.queue.capacity(),
            probe: if self.loop_budget > 0 { 2 } else { 0 },
        };
        let exact = map.recorded_lookup() == super::view::Lookup::Exact;
        let variant = usize::from(inputs.motion.is_some()) + 2 * usize::from(exact);
        // Only walks along a path stop and go on (moving receivers, the exact lookup).
        let walks = inputs.motion.is_some() || exact;
        let rounds = if walks { bindings.queue.rounds() } else { 0 };
        let constants = MaskPush {
            rounds,
            ..constants
        };
        let counter = bindings.over_budget.raw();
        // SAFETY: the caller's contract; the set was just written; the counter is the
        // bindings' own, not in use by a pending command buffer (the caller's contract).
        unsafe {
            device.cmd_fill_buffer(cmd, counter, 0, vk::WHOLE_SIZE, 0);
            if rounds > 0 {
                bindings.queue.record_reset(device, cmd);
            }
            if inputs.ids.is_none() {
                // Its contents are never read: a transition from UNDEFINED each time keeps it
                // in the bound layout without a setup submission.
                image_barrier(
                    device,
                    cmd,
                    bindings.no_ids.raw(),
                    bindings.no_ids.layers_range(0, 1),
                    (vk::ImageLayout::UNDEFINED, read_only),
                    Access::COMPUTE_SAMPLED_READ,
                    Access::COMPUTE_SAMPLED_READ,
                );
            }
            // The rounds' group counts are read as indirect arguments too.
            memory_barrier(
                device,
                cmd,
                Access::TRANSFER_WRITE,
                Access::COMPUTE_RW.and(Access::INDIRECT_READ),
            );
            self.pass.record(
                device,
                cmd,
                variant,
                &bindings.images,
                &constants,
                inputs.size,
            );
            let queue = bindings.queue.buffer().raw();
            for round in 1..=rounds {
                // The queue this round reads, its group count and the mask's earlier writes.
                memory_barrier(
                    device,
                    cmd,
                    Access::COMPUTE_RW,
                    Access::COMPUTE_RW.and(Access::INDIRECT_READ),
                );
                self.pass
                    .bind(device, cmd, variant + FOLLOW_UP_VARIANTS, &bindings.images);
                self.pass.record_indirect(
                    device,
                    cmd,
                    variant + FOLLOW_UP_VARIANTS,
                    &MaskPush { round, ..constants },
                    (queue, MaskQueue::groups_offset(round)),
                );
            }
            memory_barrier(device, cmd, Access::COMPUTE_RW, Access::HOST_READ);
        }
        Ok(())
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
}
