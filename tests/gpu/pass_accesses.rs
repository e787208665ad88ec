//! A host with its own barrier system: the collection and generation passes recorded without
//! their entry and exit barriers (`with_host_barriers`), the host issuing them from the
//! passes' published accesses (`accesses`: first and last stages and accesses), two frames of
//! one map in one command buffer, under synchronization validation. The result matches the
//! passes with their own barriers; leaving out one host barrier is reported as a hazard (the
//! check has teeth). Synchronization validation sees the accesses made through handles
//! (fills, updates, copies, indirect arguments), not those made through device addresses:
//! the missing barrier it reports is the one before the second frame's collection, whose
//! update of the generation's dispatch arguments would race the first generation's
//! indirect read of them.

use crate::support::gpu::{assert_no_validation_messages, context};
use motion_shadows::glam::Vec3;
use motion_shadows::gpu::{Access, Buffer, BufferUsage, Context, OneShot, memory_barrier};
use motion_shadows::technique::{
    CollectionPass, Counters, Draw, DrawList, GenerationPass, Indices, LightView, PositionStream,
    PrismConstruction, TemporalShadowMap,
};

const SIZE: u32 = 48;

/// A moving triangle and a static one under a spot light looking down.
pub(crate) fn triangles(ctx: &Context) -> (Buffer, Vec<Draw>) {
    let moving = [[-2.0f32, 2.0, -2.0], [1.0, 2.0, -2.0], [0.0, 2.0, 1.0]];
    let ground = [[-4.0f32, 0.0, -4.0], [4.0, 0.0, -4.0], [0.0, 0.0, 4.0]];
    let mut data: Vec<f32> = Vec::new();
    for p in moving {
        data.extend_from_slice(&[p[0], p[1], p[2], 1.0, p[0] + 1.5, p[1], p[2], 1.0]);
    }
    for p in ground {
        data.extend_from_slice(&[p[0], p[1], p[2], 1.0]);
    }
    let buffer =
        Buffer::with_data(ctx, "triangles", BufferUsage::HostToDevice, &data).expect("vertices");
    let moving = Draw::new(
        PositionStream::from_buffer(&buffer, 0, 32).expect("t0"),
        PositionStream::from_buffer(&buffer, 16, 32).expect("t1"),
        3,
        Indices::None,
        1,
        0,
    );
    let ground_stream = PositionStream::from_buffer(&buffer, 96, 16).expect("ground");
    let ground = Draw::new(ground_stream, ground_stream, 3, Indices::None, 1, 1);
    (buffer, vec![moving, ground])
}

pub(crate) fn light(prisms: PrismConstruction) -> LightView {
    LightView {
        prisms,
        ..LightView::spot(
            Vec3::new(0.0, 8.0, 0.0),
            Vec3::NEG_Y,
            40.0,
            50.0,
            0.5,
            50.0,
            (SIZE, SIZE),
        )
    }
}

/// Records two frames of collection and generation into one command buffer, then the
/// counters' readback; `host` says whether the passes' outer barriers are the host's (from
/// the published accesses), and `skip` leaves out the host barrier before the second frame's
/// collection.
fn run(ctx: &Context, host: bool, skip: bool, light: &LightView) -> Counters {
    let (vertices, draws) = triangles(ctx);
    let mut list = DrawList::new(ctx, 2).expect("draw list");
    let (mut collection, mut generation) = (
        CollectionPass::new(ctx).expect("collection"),
        GenerationPass::new(ctx).expect("generation"),
    );
    if host {
        collection = collection.with_host_barriers();
        generation = generation.with_host_barriers();
    }
    let mut map = TemporalShadowMap::new(ctx, SIZE, SIZE, 1 << 14, 1 << 14).expect("map");
    map.prepare_for(ctx, light, None)
        .expect("the light's buffers");
    let device = ctx.device();
    OneShot::new(ctx)
        .expect("command buffer")
        .run(|cmd| unsafe {
            // SAFETY: a OneShot command buffer of `ctx`, recording, outside rendering; every
            // object outlives the submission, which `run` waits for.
            list.record_update(device, cmd, &draws)?;
            let c = collection.accesses(&list, light, &map, None);
            let g = generation.accesses(&map);
            // Before the first frame, the draw list's upload (its own exit barrier).
            let mut earlier = Access::NONE;
            for frame in 0..2 {
                if host && !(skip && frame == 1) {
                    memory_barrier(device, cmd, earlier, c.first().into());
                }
                collection.record(device, cmd, &list, light, &map, None)?;
                if host {
                    memory_barrier(device, cmd, c.last().into(), g.first().into());
                }
                generation.record(device, cmd, &map);
                earlier = g.last().into();
            }
            if host {
                // The readback waits for compute writes itself; the host's exit barrier.
                memory_barrier(device, cmd, earlier, Access::COMPUTE_RW);
            }
            map.record_counter_readback(device, cmd);
            Ok(())
        })
        .expect("frames");
    drop(vertices);
    map.read_counters().expect("counters")
}

#[test]
fn a_host_issues_the_passes_barriers_from_their_published_accesses() {
    for prisms in [PrismConstruction::Exact, PrismConstruction::Paper] {
        let light = light(prisms);
        let ctx = context();
        let own = run(&ctx, false, false, &light);
        assert_no_validation_messages(&ctx);
        assert!(
            own.range_count > 0,
            "{prisms:?}: the triangles cast ranges: {own:?}"
        );
        let ctx = context();
        let hosts = run(&ctx, true, false, &light);
        assert_no_validation_messages(&ctx);
        assert_eq!(
            (hosts.node_count, hosts.range_count, hosts.ranges_direct),
            (own.node_count, own.range_count, own.ranges_direct),
            "{prisms:?}: the same map with the host's barriers"
        );
    }
}

#[test]
fn a_missing_host_barrier_is_a_reported_hazard() {
    let ctx = context();
    run(&ctx, true, true, &light(PrismConstruction::Paper));
    let messages = ctx.validation_messages();
    assert!(
        messages.iter().any(|m| m.contains("SYNC-HAZARD")),
        "synchronization validation did not report the missing barrier: {messages:?}"
    );
}

/// The mask pass publishes the host's images it reads and writes, each in the layout the
/// inputs give (the host's barriers move them there), and the map's buffers it reads.
#[test]
fn the_mask_pass_publishes_the_hosts_images_and_layouts() {
    use motion_shadows::ash::vk::{self, Handle};
    use motion_shadows::technique::{
        MaskInputs, MotionImage, PositionImage, Resource, VisibilityMaskPass,
    };
    let ctx = context();
    let mask = VisibilityMaskPass::new(&ctx).expect("mask pass");
    let map = TemporalShadowMap::new(&ctx, 16, 16, 16, 16).expect("map");
    let view = |n: u64| vk::ImageView::from_raw(n);
    let depth_layout = vk::ImageLayout::DEPTH_STENCIL_READ_ONLY_OPTIMAL;
    let motion = MotionImage {
        view: view(3),
        layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
    };
    let positions = PositionImage {
        view: view(4),
        layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
    };
    let inputs = MaskInputs::new(view(1), depth_layout, view(2), (16, 16), Default::default())
        .with_motion(motion, 1.0)
        .with_positions(positions);
    let accesses = mask.accesses(&inputs, &map);
    let images: Vec<(Resource, vk::AccessFlags2, bool)> = accesses
        .uses
        .iter()
        .filter(|u| matches!(u.resource, Resource::ImageView { .. }))
        .map(|u| (u.resource, u.first.access, u.writes))
        .collect();
    let sampled = vk::AccessFlags2::SHADER_SAMPLED_READ;
    let image = |view, layout| Resource::ImageView { view, layout };
    assert_eq!(
        images,
        [
            (image(view(1), depth_layout), sampled, false),
            (image(view(3), motion.layout), sampled, false),
            (image(view(4), positions.layout), sampled, false),
            (
                image(view(2), vk::ImageLayout::GENERAL),
                vk::AccessFlags2::SHADER_STORAGE_WRITE,
                true
            ),
        ]
    );
    // The ranges, read by the compute shader: what the generation's exit barrier must reach.
    assert!(accesses.uses.iter().any(|u| matches!(
        u.resource,
        Resource::Buffer { name: "ranges", .. }
    ) && u.first.stages
        == vk::PipelineStageFlags2::COMPUTE_SHADER));
    assert!(
        accesses
            .first()
            .stages
            .contains(vk::PipelineStageFlags2::COMPUTE_SHADER)
    );
    drop((mask, map));
    assert_no_validation_messages(&ctx);
}
