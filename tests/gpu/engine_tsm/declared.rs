//! The engine TSM pass declares its accesses (issue 37, item 2): a host with its own barrier
//! system records the pass and the draw list's update without their entry barriers
//! (`with_host_barriers`) and issues, between them, the barriers the published declarations
//! give (`Barrier::between`, reported to the access check as it records them). Two records of
//! one map in one command buffer: with every barrier the check passes and validation stays
//! silent; leaving out either barrier is reported, naming the buffer and both passes. The
//! pass with its own barriers passes the check too, its entry barrier the one the
//! declarations give.

use super::SIZE;
use super::rig::{Mesh, camera, light, rect};
use crate::support::gpu::{assert_no_validation_messages, context};
use glam::Vec3;
use motion_shadows::Error;
use motion_shadows::ash::vk;
use motion_shadows::gpu::{Access, Context, Image, OneShot, image_barrier};
use motion_shadows::technique::{
    Barrier, DrawList, EngineTsmMap, EngineTsmPass, GBuffer, GBufferCamera, GBufferPass,
    PassAccesses, TsmStart,
};

/// The maps' texels on a side (small: the check is about barriers, not pixels).
const TEXELS: u32 = 32;

/// The host's barriers, by what they order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Step {
    /// The casters' draw-list update before the first record.
    AfterUpdate,
    /// The first record before the second (its header rewritten).
    BetweenRecords,
}

/// Two records of the pass into one map; `host` records with the host's barriers (leaving
/// out `skip`), else with the pass's own. What the check says at the end, and the barriers
/// logged.
fn two_records(
    ctx: &Context,
    host: bool,
    skip: Option<Step>,
) -> (
    motion_shadows::Result<()>,
    PassAccesses,
    Vec<(String, Access, Access)>,
) {
    let check = ctx.access_check();
    check.enable();
    let ground = Mesh::new(ctx, &rect(-6.0, 6.0, -6.0, 6.0, 0.0), None);
    let caster = Mesh::new(ctx, &rect(-0.5, 0.5, -0.5, 0.5, 1.0), None);
    let light = light(Vec3::new(0.3, -1.0, 0.2).normalize(), false);
    let mut receivers = DrawList::new(ctx, 2).expect("draw list");
    let casters = DrawList::new(ctx, 2).expect("draw list");
    let (casters, pass) = if host {
        (
            casters.with_host_barriers(),
            EngineTsmPass::new(ctx).expect("pass").with_host_barriers(),
        )
    } else {
        (casters, EngineTsmPass::new(ctx).expect("pass"))
    };
    let mut casters = casters;
    // One set per record: a set bound in a command buffer is not rewritten in it.
    let mut bindings = [
        pass.bindings().expect("bindings"),
        pass.bindings().expect("bindings"),
    ];
    let gbuffer_pass = GBufferPass::new(ctx).expect("G-buffer pass");
    let gbuffer = GBuffer::new(ctx, SIZE.0, SIZE.1).expect("G-buffer");
    let map = EngineTsmMap::new(ctx, TEXELS, TEXELS, 1, TsmStart::Copy).expect("map");
    let output = Image::new(
        ctx,
        "TSM mask",
        (SIZE.0, SIZE.1, 1),
        vk::Format::R32_SFLOAT,
        vk::ImageUsageFlags::STORAGE,
    )
    .expect("mask image");
    let (view_proj, eye) = camera();
    let inputs = gbuffer.mask_inputs(output.layer_view(0), view_proj.inverse(), 1.0, false);
    let declared = pass.accesses(&inputs, &casters, &map);
    let device = ctx.device();
    let run = OneShot::new(ctx).expect("one shot").run(|cmd| {
        let barrier = |step: Step, from: &PassAccesses, to: &PassAccesses| {
            if !host || skip == Some(step) {
                return;
            }
            let b = Barrier::between(from, to).expect("the declarations order these");
            // SAFETY: a OneShot command buffer of `ctx`, recording, outside rendering, on its
            // graphics and compute queue.
            unsafe { b.record(device, cmd, check, &format!("host {step:?}")) };
        };
        // SAFETY: as above; the meshes' buffers, the G-buffer and the output image outlive
        // the run, which waits; each draw list is updated before the pass that reads it, and
        // the output image is moved to GENERAL before the pass writes it.
        unsafe {
            receivers.record_update(device, cmd, &[ground.draw(0)])?;
            let camera = GBufferCamera { view_proj, eye };
            gbuffer_pass.record(device, cmd, &receivers, &camera, 1.0, &gbuffer);
            casters.record_update(device, cmd, &[ground.draw(0), caster.draw(2)])?;
            image_barrier(
                device,
                cmd,
                output.raw(),
                output.layers_range(0, 1),
                (vk::ImageLayout::UNDEFINED, vk::ImageLayout::GENERAL),
                Access::NONE,
                Access::COMPUTE_RW,
            );
        }
        barrier(Step::AfterUpdate, &casters.update_accesses(), &declared);
        // SAFETY: as above.
        unsafe {
            pass.record(
                device,
                cmd,
                &mut bindings[0],
                &inputs,
                &casters,
                &light,
                &map,
                2,
            )?
        };
        barrier(Step::BetweenRecords, &declared, &declared);
        // SAFETY: as above.
        unsafe {
            pass.record(
                device,
                cmd,
                &mut bindings[1],
                &inputs,
                &casters,
                &light,
                &map,
                2,
            )?
        };
        Ok(())
    });
    let log = check
        .take_barrier_log()
        .into_iter()
        .map(|b| (b.by, b.before, b.after))
        .collect();
    let result = run.and_then(|()| check.end_frame());
    (result, declared, log)
}

#[test]
fn a_host_recording_the_engine_tsm_pass_with_every_declared_barrier_passes_the_check() {
    let ctx = context();
    let (result, _, _) = two_records(&ctx, true, None);
    result.expect("every barrier issued and reported");
    assert_no_validation_messages(&ctx);
}

#[test]
fn a_host_skipping_a_declared_engine_tsm_barrier_is_reported_by_name() {
    for (step, want, before) in [
        (Step::AfterUpdate, "draw list", "draw list update"),
        (
            Step::BetweenRecords,
            "time-dependent shadow maps' header",
            "time-dependent shadow maps",
        ),
    ] {
        let ctx = context();
        match two_records(&ctx, true, Some(step)).0 {
            Err(Error::MissingBarrier {
                resource,
                previous,
                next,
            }) => {
                assert_eq!(resource, want, "{step:?}: the buffer named");
                assert!(previous.starts_with(before), "{step:?}: {previous}");
                assert!(
                    next.starts_with("time-dependent shadow maps ("),
                    "{step:?}: {next}"
                );
            }
            other => panic!("{step:?} skipped: the check said {other:?}"),
        }
    }
}

/// With its own barriers the pass passes the check, and the entry barrier it logs is the
/// one its declarations give between one record of the map and the next, read here
/// independently: the header's last accesses (the depth draws' vertex reads and the mask's
/// compute reads) before its first (the transfer that rewrites it).
#[test]
fn the_engine_tsm_pass_records_the_entry_barrier_its_declarations_give() {
    let ctx = context();
    let (result, declared, log) = two_records(&ctx, false, None);
    result.expect("the pass's own barriers order its records");
    assert_no_validation_messages(&ctx);
    let header = declared
        .uses
        .iter()
        .find(|u| {
            matches!(u.resource, motion_shadows::technique::Resource::Buffer { name, .. }
                if name == "time-dependent shadow maps' header")
        })
        .expect("the header is declared");
    let reads = Access {
        stages: vk::PipelineStageFlags2::VERTEX_SHADER | vk::PipelineStageFlags2::COMPUTE_SHADER,
        access: vk::AccessFlags2::SHADER_STORAGE_READ,
    };
    assert_eq!(Access::from(header.first), Access::TRANSFER_WRITE);
    assert_eq!(Access::from(header.last), reads);
    let entries: Vec<_> = log
        .iter()
        .filter(|(by, _, _)| by == "time-dependent shadow maps entry")
        .collect();
    assert_eq!(entries.len(), 2, "one entry barrier per record: {log:?}");
    for (_, before, after) in entries {
        assert_eq!((*before, *after), (reads, Access::TRANSFER_WRITE));
    }
}
