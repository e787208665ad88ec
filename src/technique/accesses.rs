//! The passes' accesses as data, the one source of their barriers: what each record
//! function reads and writes, in which stages, with which accesses, and (for images) in
//! which layouts. Each pass records its own entry and exit barriers from these
//! declarations ([`super::Barrier::between`]; `own_barriers.rs` says what each orders
//! against); a host with its own barrier system (a render graph) turns them off
//! (`with_host_barriers` on [`CollectionPass`], [`GenerationPass`], [`super::DrawList`],
//! [`TemporalShadowMap`] for its counter readback, [`super::VisibilityMaskPass`],
//! [`super::GBufferPass`], and the research feature's `EngineTsmPass` and `LightingPass`)
//! and records [`super::Barrier::between`] the declarations of every two passes it runs in
//! turn (with the layout transitions of the library's own images, [`Resource::Image`]). The
//! barriers inside a pass (between its own steps) stay its own.
//!
//! The rule between frames: one frame's lookups of the map (a host shader,
//! [`TemporalShadowMap::lookup_accesses`]; the mask, [`super::VisibilityMaskPass::accesses`])
//! read what the next frame's collection clears and rewrites, so that collection must be
//! ordered after them: its own entry barrier waits for every use the map can have had since
//! (the generation, lookups from any shader stage, the counter readback, an earlier
//! collection); a host recording it itself issues the barrier between what it ran on the
//! map since the last collection (or that same join) and [`CollectionPass::accesses`]. With
//! frames in flight each frame has its own maps (the record functions' contracts: a map is
//! not in use by a command buffer running at the same time), so the rule holds within one
//! map's frames: barriers order work submitted earlier on the same queue; on another queue,
//! a semaphore (and a queue-family transfer) are the host's.
//!
//! The temporal shadow map's buffers are reached by device address in the shaders, which
//! synchronization validation cannot see: [`crate::gpu::AccessCheck`] (a debug check,
//! off unless enabled) follows these declarations instead and reports a barrier a host
//! left out. A host that tracks buffers by handle gets the handles here
//! ([`Resource::Buffer`]), and the host's own vertex and index buffers, read by address
//! through the draw list, as [`Resource::DrawStreams`].

use super::collection::CollectionPass;
use super::coverage::CoverageMap;
use super::generation::GenerationPass;
use super::shadow_map::TemporalShadowMap;
use super::view::LightView;
use crate::gpu::Access;
use ash::vk;

/// What a use is of.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Resource {
    /// A buffer of the library (named as its allocation is, e.g. `"nodes"`).
    Buffer {
        /// The handle.
        buffer: vk::Buffer,
        /// Its name.
        name: &'static str,
    },
    /// The draw list's position and index streams: the host's buffers, read by address.
    DrawStreams,
    /// An image of the library's own (a G-buffer's), all its layers, in `layout` during the
    /// pass: [`super::Barrier::between`] gives its layout transitions.
    Image {
        /// The handle.
        image: vk::Image,
        /// Its name (as its allocation's).
        name: &'static str,
        /// Its aspect (depth or colour).
        aspect: vk::ImageAspectFlags,
        /// Its layers (all of them, of its only mip level).
        layers: u32,
        /// Its layout while the pass uses it.
        layout: vk::ImageLayout,
        /// Whether the pass overwrites it whole (what it held before, and its layout, need
        /// not be kept: the transition into the pass starts from `UNDEFINED`).
        discards: bool,
    },
    /// An image of the host's, through the view the host gave, in `layout` during the pass
    /// (the host's barriers move it there before and on after: a view names no image for a
    /// layout transition).
    ImageView {
        /// The view.
        view: vk::ImageView,
        /// Its layout while the pass uses it.
        layout: vk::ImageLayout,
    },
}

/// How one pass uses one resource: its first access (what must wait for earlier uses) and
/// its last (what later uses wait for).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ResourceUse {
    /// What is used.
    pub resource: Resource,
    /// The pass's first access of it.
    pub first: AccessData,
    /// The pass's last access of it.
    pub last: AccessData,
    /// Whether the pass writes it.
    pub writes: bool,
}

/// [`Access`] as plain data (stages and accesses), comparable.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AccessData {
    /// Pipeline stages.
    pub stages: vk::PipelineStageFlags2,
    /// Memory accesses in those stages.
    pub access: vk::AccessFlags2,
}

impl From<Access> for AccessData {
    fn from(a: Access) -> Self {
        Self {
            stages: a.stages,
            access: a.access,
        }
    }
}

impl From<AccessData> for Access {
    fn from(a: AccessData) -> Self {
        Self {
            stages: a.stages,
            access: a.access,
        }
    }
}

/// Every resource one recorded pass uses: the pass's declaration, from which both its own
/// entry and exit barriers and a host's ([`super::Barrier::between`]) are derived.
///
/// The rule between frames: one frame's lookups of the map (a host shader,
/// [`TemporalShadowMap::lookup_accesses`]; the mask) read what the next frame's collection
/// clears and rewrites, so that collection is ordered after them. Its own entry barrier
/// waits for every use the map can have had (the generation, lookups from any shader
/// stage, the counter readback, an earlier collection); a host recording the barriers
/// itself records `Barrier::between(earlier, collection)` with `earlier` the join
/// ([`Self::and`]) of what it ran on the map since the last collection. With frames in
/// flight each frame has its own maps (a map is not used by two command buffers running at
/// the same time), so the rule holds within one map's frames: a barrier orders work
/// submitted earlier on the same queue; across queues a semaphore is the host's. The map is
/// read by device address, which synchronization validation cannot see:
/// [`crate::gpu::AccessCheck`] checks a host's barriers against these declarations.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct PassAccesses {
    /// One entry per resource.
    pub uses: Vec<ResourceUse>,
}

impl PassAccesses {
    pub(crate) fn add(&mut self, resource: Resource, first: Access, last: Access, writes: bool) {
        self.uses.push(ResourceUse {
            resource,
            first: first.into(),
            last: last.into(),
            writes,
        });
    }

    pub(crate) fn buffer(
        &mut self,
        map_buffer: (&crate::gpu::Buffer, &'static str),
        first: Access,
        last: Access,
        writes: bool,
    ) {
        let (buffer, name) = map_buffer;
        self.add(
            Resource::Buffer {
                buffer: buffer.raw(),
                name,
            },
            first,
            last,
            writes,
        );
    }

    /// `image` (a library image, all its layers) in `layout` during the pass, overwritten
    /// whole if `discards`.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn image(
        &mut self,
        (image, name): (&crate::gpu::Image, &'static str),
        layout: vk::ImageLayout,
        discards: bool,
        first: Access,
        last: Access,
        writes: bool,
    ) {
        self.add(
            Resource::Image {
                image: image.raw(),
                name,
                aspect: image.aspect(),
                layers: image.size().2,
                layout,
                discards,
            },
            first,
            last,
            writes,
        );
    }

    /// Every first access together: the destination of one global barrier before the pass.
    pub fn first(&self) -> AccessData {
        self.uses
            .iter()
            .fold(Access::NONE, |a, u| a.and(u.first.into()))
            .into()
    }

    /// Every last access together: the source of one global barrier after the pass.
    pub fn last(&self) -> AccessData {
        self.uses
            .iter()
            .fold(Access::NONE, |a, u| a.and(u.last.into()))
            .into()
    }
}

/// Shader reads and writes of storage in the stages of the collection's draws.
const DRAW_STAGES_RW: Access = Access::FRAGMENT_RW.and(Access::GEOMETRY_RW);
/// Storage reads by the collection's vertex, geometry and fragment shaders.
const DRAW_STAGES_READ: Access = Access {
    stages: vk::PipelineStageFlags2::from_raw(
        vk::PipelineStageFlags2::VERTEX_SHADER.as_raw()
            | vk::PipelineStageFlags2::GEOMETRY_SHADER.as_raw()
            | vk::PipelineStageFlags2::FRAGMENT_SHADER.as_raw(),
    ),
    access: vk::AccessFlags2::SHADER_STORAGE_READ,
};
/// Storage reads by compute shaders.
const COMPUTE_READ: Access = Access {
    stages: vk::PipelineStageFlags2::COMPUTE_SHADER,
    access: vk::AccessFlags2::SHADER_STORAGE_READ,
};

impl CollectionPass {
    /// The same pass without its entry and exit barriers: the host issues them from
    /// [`Self::accesses`] (a render graph). The barriers between its own steps stay.
    pub fn with_host_barriers(mut self) -> Self {
        self.outer_barriers = false;
        self
    }

    /// What [`Self::record`] with these arguments reads and writes. The draw list itself
    /// is updated, with its own barriers, by [`super::DrawList::record_update`].
    pub fn accesses(
        &self,
        draws: &super::DrawList,
        light: &LightView,
        map: &TemporalShadowMap,
        coverage: Option<&CoverageMap>,
    ) -> PassAccesses {
        collection_uses(draws, light, map, coverage)
    }
}

/// [`CollectionPass::accesses`]: the collection's declarations, the one source of its own
/// barriers and of the host's.
pub(crate) fn collection_uses(
    draws: &super::DrawList,
    light: &LightView,
    map: &TemporalShadowMap,
    coverage: Option<&CoverageMap>,
) -> PassAccesses {
    let mut a = PassAccesses::default();
    let transfer_then_draws = |last: Access| (Access::TRANSFER_WRITE, last);
    a.add(
        Resource::DrawStreams,
        DRAW_STAGES_READ,
        DRAW_STAGES_READ,
        false,
    );
    a.buffer(
        (draws.buffer(), "draw list"),
        DRAW_STAGES_READ,
        DRAW_STAGES_READ,
        false,
    );
    let (first, last) = transfer_then_draws(DRAW_STAGES_READ);
    a.buffer((&map.header, "shadow map header"), first, last, true);
    for (buffer, name) in [
        (&map.heads, "node heads"),
        (&map.range_heads, "range heads"),
    ] {
        let (first, last) = transfer_then_draws(DRAW_STAGES_RW);
        a.buffer((buffer, name), first, last, true);
    }
    // Counters: written by transfer, counted by the geometry and fragment shaders, and
    // (when the collection stores the ranges) copied within the buffer at the end.
    a.buffer(
        (&map.counters, "counters"),
        Access::TRANSFER_WRITE,
        DRAW_STAGES_RW.and(Access::TRANSFER_WRITE),
        true,
    );
    // The generation's dispatch arguments, and the sort's tile list the fragment shader
    // writes (collection_append.glsl's list_sort_tile).
    let (first, last) = transfer_then_draws(Access::FRAGMENT_RW);
    a.buffer((&map.tiles, "generation dispatch"), first, last, true);
    a.buffer(
        (&map.nodes, "nodes"),
        Access::FRAGMENT_RW,
        Access::FRAGMENT_RW,
        true,
    );
    a.buffer(
        (&map.ranges, "ranges"),
        Access::FRAGMENT_RW,
        Access::FRAGMENT_RW,
        true,
    );
    // With sorted storage the collection links its ranges here; the generation sorts
    // them into `ranges`.
    a.buffer(
        (&map.range_lists, "range lists"),
        Access::FRAGMENT_RW,
        Access::FRAGMENT_RW,
        true,
    );
    if light.lookup == super::Lookup::Exact {
        // Written once per drawn triangle by the geometry shader.
        if let Some(records) = &map.triangle_records {
            a.buffer(
                (records, "triangle records"),
                DRAW_STAGES_RW,
                DRAW_STAGES_RW,
                true,
            );
        }
    }
    if let Some(names) = map
        .static_names
        .as_ref()
        .filter(|_| map.uses_static_names(light, coverage))
    {
        // Cleared by transfer when redrawn, linked by the fragment shader, its count
        // copied into the counters at the end.
        a.buffer(
            (names, "static names"),
            Access::TRANSFER_WRITE.and(DRAW_STAGES_RW),
            DRAW_STAGES_RW.and(Access::TRANSFER_READ),
            true,
        );
    } else if map.uses_static_layer(light, coverage) {
        a.buffer(
            (&map.static_nearest, "static layer"),
            Access::TRANSFER_WRITE.and(DRAW_STAGES_RW),
            DRAW_STAGES_RW,
            true,
        );
    }
    if let Some(c) = coverage {
        a.buffer(
            (&c.nearest, "coverage nearest"),
            Access::TRANSFER_WRITE,
            DRAW_STAGES_RW,
            true,
        );
    }
    a
}

impl GenerationPass {
    /// The same pass without its entry and exit barriers: the host issues them from
    /// [`Self::accesses`]. The barriers between its two dispatches stay.
    pub fn with_host_barriers(mut self) -> Self {
        self.outer_barriers = false;
        self
    }

    /// What [`Self::record`] of `map` reads and writes.
    pub fn accesses(&self, map: &TemporalShadowMap) -> PassAccesses {
        generation_uses(map)
    }
}

/// [`GenerationPass::accesses`]: the generation's declarations.
pub(crate) fn generation_uses(map: &TemporalShadowMap) -> PassAccesses {
    let mut a = PassAccesses::default();
    let rw = Access::COMPUTE_RW;
    a.buffer(
        (&map.header, "shadow map header"),
        COMPUTE_READ,
        COMPUTE_READ,
        false,
    );
    a.buffer((&map.heads, "node heads"), rw, rw, true);
    a.buffer((&map.nodes, "nodes"), rw, rw, true);
    a.buffer((&map.range_heads, "range heads"), rw, rw, true);
    a.buffer((&map.ranges, "ranges"), rw, rw, true);
    a.buffer((&map.counters, "counters"), rw, rw, true);
    a.buffer(
        (&map.static_nearest, "static layer"),
        COMPUTE_READ,
        COMPUTE_READ,
        false,
    );
    a.buffer(
        (&map.range_lists, "range lists"),
        COMPUTE_READ,
        COMPUTE_READ,
        false,
    );
    // The dispatches' arguments: the sorting's short lists count the long ones' groups.
    a.buffer(
        (&map.tiles, "generation dispatch"),
        Access::INDIRECT_READ,
        rw.and(Access::INDIRECT_READ),
        true,
    );
    a.buffer(
        (&map.long_pixels, "long-list pixels"),
        Access::TRANSFER_WRITE,
        rw.and(Access::INDIRECT_READ),
        true,
    );
    a
}

impl super::VisibilityMaskPass {
    /// What [`Self::record`] with these inputs reads and writes of the host's images and of
    /// `map` (its own counter and overflow queues: [`super::MaskBindings::accesses`]). The
    /// images' barriers and layout transitions are always the host's (the record function's
    /// contract); the map's ranges must be visible to compute reads, which the generation
    /// pass's exit barrier (or the host's, from [`GenerationPass::accesses`]) does.
    pub fn accesses(&self, inputs: &super::MaskInputs, map: &TemporalShadowMap) -> PassAccesses {
        let mut a = map.lookup_accesses(vk::PipelineStageFlags2::COMPUTE_SHADER);
        let write = Access {
            stages: vk::PipelineStageFlags2::COMPUTE_SHADER,
            access: vk::AccessFlags2::SHADER_STORAGE_WRITE,
        };
        mask_image_uses(&mut a, inputs, write);
        a
    }
}

impl super::MaskInputs {
    /// What the visibility mask does with the host's images: each input view sampled by
    /// compute shaders in the layout these inputs give, the output written by compute shaders
    /// in `GENERAL` (the image uses of [`super::VisibilityMaskPass::accesses`] and
    /// `ShadowFrame::mask`). Known before the frame is recorded, when the host records the
    /// barrier that moves its G-buffer and mask images into those layouts (`ShadowFrame`
    /// arrives after `LightShadow::record_frame` has recorded the mask).
    pub fn image_accesses(&self) -> PassAccesses {
        let mut a = PassAccesses::default();
        let write = Access {
            stages: vk::PipelineStageFlags2::COMPUTE_SHADER,
            access: vk::AccessFlags2::SHADER_STORAGE_WRITE,
        };
        mask_image_uses(&mut a, self, write);
        a
    }
}

/// The host's images a mask over `inputs` uses: its G-buffer images sampled by the compute
/// shader, its output (in `GENERAL`) with `output` accesses.
pub(crate) fn mask_image_uses(a: &mut PassAccesses, inputs: &super::MaskInputs, output: Access) {
    let sampled = Access::COMPUTE_SAMPLED_READ;
    let image = |view, layout| Resource::ImageView { view, layout };
    a.add(
        image(inputs.depth, inputs.depth_layout),
        sampled,
        sampled,
        false,
    );
    let optional = [
        inputs.normals.map(|n| (n.view, n.layout)),
        inputs.motion.map(|m| (m.view, m.layout)),
        inputs.ids.map(|i| (i.view, i.layout)),
        inputs.positions.map(|p| (p.view, p.layout)),
    ];
    for (view, layout) in optional.into_iter().flatten() {
        a.add(image(view, layout), sampled, sampled, false);
    }
    a.add(
        image(inputs.output, vk::ImageLayout::GENERAL),
        output,
        output,
        true,
    );
}

impl TemporalShadowMap {
    /// What a shader of the host that tests visibility against this map reads (by address,
    /// from any stage it names): the map after [`GenerationPass::record`].
    pub fn lookup_accesses(&self, stages: vk::PipelineStageFlags2) -> PassAccesses {
        let read = Access {
            stages,
            access: vk::AccessFlags2::SHADER_STORAGE_READ,
        };
        let mut a = PassAccesses::default();
        for (buffer, name) in [
            (&self.header, "shadow map header"),
            (&self.range_heads, "range heads"),
            (&self.ranges, "ranges"),
            (&self.static_nearest, "static layer"),
        ] {
            a.buffer((buffer, name), read, read, false);
        }
        // The exact lookup's: the triangles it tests, and the static ones named per texel.
        if let Some(records) = &self.triangle_records {
            a.buffer((records, "triangle records"), read, read, false);
        }
        if let Some(names) = &self.static_names {
            a.buffer((names, "static names"), read, read, false);
        }
        a
    }
}
