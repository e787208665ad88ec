//! Every pass's own entry and exit barriers are the ones its published declarations give
//! (issue 37, item 2): one frame of the draw list's update, the collection, the generation,
//! the visibility mask and the counter readback, each recording its own barriers, with the
//! access check on (which logs every barrier the passes report as they record it). Each
//! logged barrier must equal (a) what this file's own reading of the rule derives from the
//! published `accesses` (the source joins the earlier use's last accesses, the destination
//! the later use's first, over the buffers both use where either writes) and (b) the
//! barrier these passes recorded by hand before the declarations drove them, where one was
//! written out. A declaration changed on purpose moves a barrier away from (b); a pass that
//! records a barrier of its own making moves it away from (a).

use crate::pass_accesses::{light, triangles};
use crate::support::gpu::{assert_no_validation_messages, context};
use motion_shadows::ash::vk;
use motion_shadows::glam::Mat4;
use motion_shadows::gpu::{Access, Image, OneShot, ReportedBarrier, image_barrier};
use motion_shadows::technique::{
    CollectionPass, DrawList, GenerationPass, MaskInputs, PassAccesses, PrismConstruction,
    Resource, TemporalShadowMap, VisibilityMaskPass,
};

const SIZE: u32 = 48;
const MASK: u32 = 8;

/// The rule, read independently of the library's `Barrier::between`.
fn derive(earlier: &[&PassAccesses], later: &PassAccesses) -> Option<(Access, Access)> {
    let key = |r: &Resource| match r {
        Resource::Buffer { buffer, .. } => format!("{buffer:?}"),
        other => format!("{other:?}"),
    };
    let mut pair: Option<(Access, Access)> = None;
    for e in earlier.iter().flat_map(|p| p.uses.iter()) {
        for l in &later.uses {
            if key(&e.resource) == key(&l.resource) && (e.writes || l.writes) {
                let (b, a) = pair.unwrap_or((Access::NONE, Access::NONE));
                pair = Some((b.and(e.last.into()), a.and(l.first.into())));
            }
        }
    }
    pair
}

fn logged(log: &[ReportedBarrier], by: &str) -> Option<(Access, Access)> {
    let found: Vec<_> = log.iter().filter(|b| b.by == by).collect();
    assert!(found.len() <= 1, "{by} logged {} times", found.len());
    found.first().map(|b| (b.before, b.after))
}

const fn access(stages: vk::PipelineStageFlags2, access: vk::AccessFlags2) -> Access {
    Access { stages, access }
}

#[test]
fn every_pass_records_the_barriers_its_declarations_give() {
    let ctx = context();
    ctx.access_check().enable();
    let light = light(PrismConstruction::Exact);
    let (vertices, draws) = triangles(&ctx);
    let mut list = DrawList::new(&ctx, 2).expect("draw list");
    let collection = CollectionPass::new(&ctx).expect("collection");
    let generation = GenerationPass::new(&ctx).expect("generation");
    let mask = VisibilityMaskPass::new(&ctx).expect("mask pass");
    let mut bindings = mask.bindings(&ctx, (MASK, MASK)).expect("bindings");
    let mut map = TemporalShadowMap::new(&ctx, SIZE, SIZE, 1 << 14, 1 << 14).expect("map");
    map.prepare_for(&ctx, &light, None).expect("buffers");
    let image = |name, format, usage| {
        Image::new(&ctx, name, (MASK, MASK, 1), format, usage).expect("image")
    };
    let depth = image(
        "depth",
        vk::Format::D32_SFLOAT,
        vk::ImageUsageFlags::SAMPLED,
    );
    let output = image("mask", vk::Format::R32_SFLOAT, vk::ImageUsageFlags::STORAGE);
    let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
    let inputs = MaskInputs::new(
        depth.layer_view(0),
        read,
        output.layer_view(0),
        (MASK, MASK),
        Mat4::IDENTITY,
    );
    let device = ctx.device();
    OneShot::new(&ctx)
        .expect("command buffer")
        .run(|cmd| unsafe {
            // SAFETY: a OneShot command buffer of `ctx`, recording, outside rendering; every
            // object outlives the submission, which `run` waits for; the images are moved
            // into the layouts the mask's inputs state before it reads or writes them.
            list.record_update(device, cmd, &draws)?;
            collection.record(device, cmd, &list, &light, &map, None)?;
            generation.record(device, cmd, &map);
            let sampled = Access::COMPUTE_SAMPLED_READ;
            for (img, layout, after) in [
                (&depth, read, sampled),
                (&output, vk::ImageLayout::GENERAL, Access::COMPUTE_RW),
            ] {
                let range = img.layers_range(0, 1);
                let change = (vk::ImageLayout::UNDEFINED, layout);
                image_barrier(device, cmd, img.raw(), range, change, Access::NONE, after);
            }
            mask.record(device, cmd, &mut bindings, &inputs, &map)?;
            map.record_counter_readback(device, cmd);
            Ok(())
        })
        .expect("frame");
    let log = ctx.access_check().take_barrier_log();
    drop(vertices);

    let c = collection.accesses(&list, &light, &map, None);
    let g = generation.accesses(&map);
    let any_stage = Access::ANY_SHADER_READ.stages;
    let lookups = map.lookup_accesses(any_stage);
    let readback = map.counter_readback_accesses();
    let (update, readers) = (list.update_accesses(), list.read_accesses());
    let expected = [
        ("draw list update entry", derive(&[&readers], &update)),
        ("draw list update exit", derive(&[&update], &readers)),
        (
            "collection entry",
            derive(&[&g, &lookups, &readback, &c], &c),
        ),
        ("collection exit", derive(&[&c], &g)),
        ("generation entry", derive(&[&g], &g)),
        ("generation exit", derive(&[&g], &lookups)),
        (
            "visibility mask exit",
            derive(&[&bindings.accesses()], &bindings.read_accesses()),
        ),
        ("counter readback entry", derive(&[&g], &readback)),
        (
            "counter readback exit",
            derive(&[&readback], &map.counter_read_accesses()),
        ),
    ];
    for (by, derived) in expected {
        assert!(derived.is_some(), "{by}: the declarations order something");
        assert_eq!(logged(&log, by), derived, "{by}: recorded vs declared");
    }
    assert_eq!(
        log.len(),
        expected.len(),
        "no barrier beyond these: {log:?}"
    );

    // The barriers the passes recorded by hand before (the same numbers, written out).
    let storage_read = vk::AccessFlags2::SHADER_STORAGE_READ;
    let by_hand = [
        (
            "draw list update entry",
            (Access::ANY_SHADER_READ, Access::TRANSFER_WRITE),
        ),
        (
            "draw list update exit",
            (Access::TRANSFER_WRITE, Access::ANY_SHADER_READ),
        ),
        (
            "generation exit",
            (Access::COMPUTE_RW, access(any_stage, storage_read)),
        ),
        (
            "visibility mask exit",
            (Access::COMPUTE_RW, Access::HOST_READ),
        ),
        (
            "counter readback entry",
            (Access::COMPUTE_RW, Access::TRANSFER_READ),
        ),
        (
            "counter readback exit",
            (Access::TRANSFER_WRITE, Access::HOST_READ),
        ),
    ];
    for (by, barrier) in by_hand {
        assert_eq!(
            logged(&log, by),
            Some(barrier),
            "{by}: the hand-written barrier"
        );
    }
    // The collection's entry waits for every earlier use the old one did, before its
    // transfers and draws; its exit makes the draws' and transfers' writes visible to the
    // generation's compute shaders and indirect reads.
    let (before, after) = logged(&log, "collection entry").expect("collection entry");
    let old_source = Access::ANY_SHADER_READ
        .and(Access::COMPUTE_RW)
        .and(Access::FRAGMENT_RW)
        .and(Access::TRANSFER_READ)
        .and(Access::INDIRECT_READ);
    assert!(before.stages.contains(old_source.stages), "{before:?}");
    assert!(
        after
            .stages
            .contains(vk::PipelineStageFlags2::TRANSFER | vk::PipelineStageFlags2::FRAGMENT_SHADER)
    );
    let (before, after) = logged(&log, "collection exit").expect("collection exit");
    let written = Access::FRAGMENT_RW
        .and(Access::GEOMETRY_RW)
        .and(Access::TRANSFER_WRITE);
    assert!(before.stages.contains(written.stages) && before.access.contains(written.access));
    assert!(after.stages.contains(
        vk::PipelineStageFlags2::COMPUTE_SHADER | vk::PipelineStageFlags2::DRAW_INDIRECT
    ));
    ctx.access_check()
        .end_frame()
        .expect("a frame of the passes' own barriers misses none");
    drop((depth, output, bindings, map, list));
    assert_no_validation_messages(&ctx);
}
