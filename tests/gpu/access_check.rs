//! The debug check of declared accesses catches a host that skips a barrier it was told to
//! issue (issue 37, item 2): the map is read by device address, so neither the validation
//! layer nor (on lavapipe) the pixels say anything. A host with its own barrier system
//! records the draw list's update, the collection, the generation and the counter readback
//! without their own barriers and issues, between each pair of passes, the barrier their
//! published declarations give (`Barrier::between`, reported to the check as it records it);
//! its lighting, which reads the map, is declared to the check like a pass. Two frames in one
//! command buffer. With every barrier the frame passes the check (and validation stays
//! silent); leaving out any one of them is reported, naming the buffer and both uses.

use crate::pass_accesses::{light, triangles};
use crate::support::gpu::{assert_no_validation_messages, context};
use motion_shadows::Error;
use motion_shadows::ash::vk;
use motion_shadows::gpu::{Context, OneShot};
use motion_shadows::technique::{
    Barrier, CollectionPass, DrawList, GenerationPass, PassAccesses, PrismConstruction,
    TemporalShadowMap,
};

const SIZE: u32 = 32;

/// The host's barriers, by what they order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Step {
    BeforeUpdate,
    AfterUpdate,
    BeforeCollection,
    CollectionToGeneration,
    GenerationToLighting,
    BeforeReadback,
    AfterReadback,
}

const STEPS: [Step; 7] = [
    Step::BeforeUpdate,
    Step::AfterUpdate,
    Step::BeforeCollection,
    Step::CollectionToGeneration,
    Step::GenerationToLighting,
    Step::BeforeReadback,
    Step::AfterReadback,
];

/// Two host frames; `skip` leaves out that barrier in the second frame. What the check
/// says at the end of the frames. (The barrier before the second draw-list update can be left
/// out without a hazard: the first frame's barriers after its collection, whose sources
/// hold the stages that read the list, already chain those reads to every later transfer,
/// and the check follows such chains.)
fn two_frames(ctx: &Context, skip: Option<Step>) -> motion_shadows::Result<()> {
    let check = ctx.access_check();
    check.enable();
    let light = light(PrismConstruction::Paper);
    let (vertices, draws) = triangles(ctx);
    let mut list = DrawList::new(ctx, 2)?.with_host_barriers();
    let collection = CollectionPass::new(ctx)?.with_host_barriers();
    let generation = GenerationPass::new(ctx)?.with_host_barriers();
    let mut map = TemporalShadowMap::new(ctx, SIZE, SIZE, 1 << 12, 1 << 12)?.with_host_barriers();
    map.prepare_for(ctx, &light, None)?;
    let device = ctx.device();
    OneShot::new(ctx)?.run(|cmd| {
        let lighting = map.lookup_accesses(vk::PipelineStageFlags2::FRAGMENT_SHADER);
        let g = generation.accesses(&map);
        let readback = map.counter_readback_accesses();
        // What may have used the map before a frame: the last frame's lighting and
        // readback (and, through them, its generation).
        let mut earlier: PassAccesses = g.clone().and(&lighting).and(&readback);
        for frame in 0..2 {
            let barrier = |step: Step, from: &PassAccesses, to: &PassAccesses| {
                if frame == 1 && skip == Some(step) {
                    return;
                }
                let b = Barrier::between(from, to).expect("the declarations order these");
                // SAFETY: a OneShot command buffer of `ctx`, recording, outside rendering,
                // on its graphics and compute queue.
                unsafe { b.record(device, cmd, check, &format!("host {step:?}")) };
            };
            let (update, readers) = (list.update_accesses(), list.read_accesses());
            barrier(Step::BeforeUpdate, &readers, &update);
            // SAFETY: as above; the draws' vertex buffer outlives the submission.
            unsafe { list.record_update(device, cmd, &draws)? };
            barrier(Step::AfterUpdate, &update, &readers);
            let c = collection.accesses(&list, &light, &map, None);
            barrier(Step::BeforeCollection, &earlier, &c);
            // SAFETY: as above; the list was updated just before.
            unsafe { collection.record(device, cmd, &list, &light, &map, None)? };
            barrier(Step::CollectionToGeneration, &c, &g);
            // SAFETY: as above, after the collection of the same map.
            unsafe { generation.record(device, cmd, &map) };
            barrier(Step::GenerationToLighting, &g, &lighting);
            // The host's lighting would read the map here, in its fragment shaders.
            lighting.declare_run(check, "host lighting");
            barrier(Step::BeforeReadback, &g, &readback);
            // SAFETY: as above.
            unsafe { map.record_counter_readback(device, cmd) };
            barrier(Step::AfterReadback, &readback, &map.counter_read_accesses());
            earlier = g.clone().and(&lighting).and(&readback);
        }
        Ok(())
    })?;
    map.read_counters()?;
    drop(vertices);
    check.end_frame()
}

#[test]
fn a_host_frame_with_every_declared_barrier_passes_the_check() {
    let ctx = context();
    two_frames(&ctx, None).expect("every barrier issued and reported");
    assert_no_validation_messages(&ctx);
}

#[test]
fn a_host_frame_that_skips_a_declared_barrier_is_reported_by_name() {
    // The buffer each barrier is the first to order, the passes either side (None: a
    // chain of the other barriers orders it, see `two_frames`).
    let expected = |step: Step| match step {
        Step::BeforeUpdate => None,
        Step::AfterUpdate => Some(("draw list", "draw list update", "collection")),
        Step::BeforeCollection => Some(("counters", "counter readback", "collection")),
        Step::CollectionToGeneration => Some(("shadow map header", "collection", "generation")),
        Step::GenerationToLighting => Some(("range heads", "generation", "host lighting")),
        Step::BeforeReadback => Some(("counters", "generation", "counter readback")),
        Step::AfterReadback => Some(("counters readback", "counter readback", "read_counters")),
    };
    for step in STEPS {
        let ctx = context();
        let report = two_frames(&ctx, Some(step));
        let Some((want, before, after)) = expected(step) else {
            assert!(report.is_ok(), "{step:?}: a chain orders it: {report:?}");
            continue;
        };
        let (resource, previous, next) = match report {
            Err(Error::MissingBarrier {
                resource,
                previous,
                next,
            }) => (resource, previous, next),
            other => panic!("{step:?} skipped: the check said {other:?}"),
        };
        assert_eq!(resource, want, "{step:?}: the buffer named");
        assert!(previous.starts_with(before), "{step:?}: {previous}");
        assert!(next.starts_with(after), "{step:?}: {next}");
    }
}
