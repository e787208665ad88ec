//! The visibility-mask pass, for deferred engines: from the host's depth image (and normal
//! image, if it has one) and its camera, the fraction of the shutter each pixel sees the
//! light, written into a host-owned single-channel image that the host's own lighting
//! multiplies in. The fraction is exact for receivers that stay put during the shutter
//! (`ms_lit_fraction` in `glsl/motion_shadows.glsl`), so the mask has no time noise.
//!
//! Host images cannot be reached by device address, so this pass, unlike the others, binds a
//! descriptor set: one [`MaskBindings`] per use in flight (per frame in flight and light).

use super::declared_barriers::record_own;
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

/// The host's images and camera (the pass's inputs).
mod inputs;
pub use inputs::{
    MaskInputs, MotionImage, NormalEncoding, NormalImage, PositionImage, TriangleIdImage,
};
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
    /// The over-budget counter.
    pub(crate) fn over_budget_buffer(&self) -> &Buffer {
        &self.over_budget
    }

    /// The follow-up rounds' queues.
    pub(crate) fn queue_buffer(&self) -> &Buffer {
        self.queue.buffer()
    }

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
        self.read_accesses()
            .declare_run(self.over_budget.access_check(), "read_over_budget_pixels");
        Ok(self.over_budget.read::<u32>(1)?[0])
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
/// The STILL_FIRST first rounds: exact masks (receivers standing, then moving), then the
/// depth-line mask with moving receivers, then the exact masks over maps with static name
/// lists (STATIC_NAMES_FIRST).
const STILL_FIRST_EXACT: usize = 8;
const STILL_FIRST_DEPTH_LINE_MOVING: usize = 10;
const STILL_FIRST_EXACT_STATIC_NAMES: usize = 11;

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
    /// Records its exit barrier (off: the host's, [`Self::with_host_barriers`]).
    pub(crate) outer_barriers: bool,
}

impl VisibilityMaskPass {
    /// Creates the pass. Errors when the device lacks the subgroup vote operations in compute
    /// shaders, or does not have `shaderStorageImageWriteWithoutFormat` enabled (a headless
    /// context enables it where supported; a host says so in `Context::from_raw`), which lets
    /// one pipeline write any of the output formats. Makes no pipeline: each of the shader's
    /// variants (still or moving receivers, depth line or exact, the follow-up rounds') is
    /// made by the first record that needs it, so that first record takes longer (on
    /// lavapipe up to about a second per variant; the eleven made up front cost a process
    /// about 2 CPU seconds).
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
            // (MOVING, EXACT, FOLLOW_UP, STILL_FIRST, STATIC_NAMES_FIRST): receivers standing
            // still or moving, against a map built for the depth-line test or for the exact
            // lookup; the first dispatch, then the follow-up rounds' (variant +
            // FOLLOW_UP_VARIANTS); first dispatches that leave moving receivers to the
            // follow-up rounds (STILL_FIRST_EXACT + MOVING, STILL_FIRST_DEPTH_LINE_MOVING),
            // and with them the still ones whose texel names moving triangles, over a map with
            // static name lists (STILL_FIRST_EXACT_STATIC_NAMES + MOVING).
            &[
                &[0, 0, 0, 0],
                &[1, 0, 0, 0],
                &[0, 1, 0, 0],
                &[1, 1, 0, 0],
                &[0, 0, 1, 0],
                &[1, 0, 1, 0],
                &[0, 1, 1, 0],
                &[1, 1, 1, 0],
                &[0, 1, 0, 1],
                &[1, 1, 0, 1],
                &[1, 0, 0, 1],
                &[0, 1, 0, 1, 1],
                &[1, 1, 0, 1, 1],
            ],
        )?;
        Ok(Self {
            pass,
            loop_budget: ctx.info().shader_loop_budget(),
            follow_up_rounds: DEFAULT_MASK_FOLLOW_UP_ROUNDS,
            outer_barriers: true,
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
    /// completes, [`MaskBindings::read_over_budget_pixels`] reads the counter; that last one
    /// comes from [`MaskBindings::accesses`] and is the caller's on a pass made
    /// [`Self::with_host_barriers`]). State changed: the bound compute pipeline, descriptor
    /// set 0 of the compute bind point, push constants.
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
        // A first round without the moving receivers where follow-up rounds take them (a
        // device with a loop limit; rounds only where paths are walked), under a still light
        // (under a moving one nothing stands still relative to it).
        let first = if rounds > 0 && !map.recorded_for_moving_light() {
            if exact && map.recorded_static_names() {
                STILL_FIRST_EXACT_STATIC_NAMES + usize::from(inputs.motion.is_some())
            } else if exact {
                STILL_FIRST_EXACT + usize::from(inputs.motion.is_some())
            } else {
                STILL_FIRST_DEPTH_LINE_MOVING
            }
        } else {
            variant
        };
        let constants = MaskPush {
            rounds,
            ..constants
        };
        // Made now where no record made them before (ImagePass: each at first use).
        let first = self.pass.pipeline(first)?;
        let follow_up = if rounds > 0 {
            Some(self.pass.pipeline(variant + FOLLOW_UP_VARIANTS)?)
        } else {
            None
        };
        let counter = bindings.over_budget.raw();
        let check = bindings.over_budget.access_check();
        // No pending command buffer uses the bindings (the contract): whatever used them
        // before was waited for.
        check.forget(counter);
        check.forget(bindings.queue.buffer().raw());
        self.accesses(inputs, map)
            .and(&bindings.accesses())
            .declare_run(check, "visibility mask");
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
                first,
                &bindings.images,
                &constants,
                inputs.size,
            );
            let queue = bindings.queue.buffer().raw();
            if let Some(follow_up) = follow_up {
                for round in 1..=rounds {
                    // The queue this round reads, its group count and the mask's earlier writes.
                    memory_barrier(
                        device,
                        cmd,
                        Access::COMPUTE_RW,
                        Access::COMPUTE_RW.and(Access::INDIRECT_READ),
                    );
                    self.pass.bind(device, cmd, follow_up, &bindings.images);
                    self.pass.record_indirect(
                        device,
                        cmd,
                        follow_up,
                        &MaskPush { round, ..constants },
                        (queue, MaskQueue::groups_offset(round)),
                    );
                }
            }
            if self.outer_barriers {
                let exit = super::own_barriers::mask(bindings).exit;
                record_own(device, cmd, check, "visibility mask exit", exit.as_ref());
            }
        }
        Ok(())
    }
}
