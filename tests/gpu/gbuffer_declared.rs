//! The G-buffer pass declares its accesses, its images' layouts included (issue 37, item 2):
//! its entry and exit barriers are the layout transitions `Barrier::between` derives from
//! them, the same as the barriers the pass recorded by hand before (read off here one by
//! one), and a host that records the pass without them (`with_host_barriers`) and issues the
//! declared ones gets the same G-buffer with validation (synchronization validation on)
//! silent; leaving out the exit transition is reported by the validation layer.

use crate::pass_accesses::triangles;
use crate::support::gpu::{assert_no_validation_messages, context};
use motion_shadows::ash::vk;
use motion_shadows::glam::Vec3;
use motion_shadows::gpu::{Access, Context, OneShot};
use motion_shadows::technique::{
    Barrier, CameraView, DrawList, GBuffer, GBufferCamera, GBufferContents, GBufferPass,
    PassAccesses,
};

const SIZE: (u32, u32) = (24, 16);

/// Two frames of the G-buffer pass, the second read back; with `host` the host issues the
/// declared barriers (all of them, or all but the exit ones when `skip_exit`).
fn two_frames(ctx: &Context, host: bool, skip_exit: bool) -> GBufferContents {
    let (vertices, draws) = triangles(ctx);
    let mut list = DrawList::new(ctx, 2).expect("draw list");
    let pass = GBufferPass::new(ctx).expect("G-buffer pass");
    let pass = if host {
        pass.with_host_barriers()
    } else {
        pass
    };
    let gbuffer = GBuffer::new(ctx, SIZE.0, SIZE.1).expect("G-buffer");
    let view = CameraView::perspective(
        Vec3::new(0.5, 6.0, 3.0),
        Vec3::ZERO,
        Vec3::Y,
        60.0,
        SIZE.0 as f32 / SIZE.1 as f32,
        0.1,
        50.0,
    );
    let camera = GBufferCamera {
        view_proj: view.proj * view.view,
        eye: view.position,
    };
    let declared = pass.accesses(&list, &gbuffer);
    let device = ctx.device();
    let check = ctx.access_check();
    OneShot::new(ctx)
        .expect("one shot")
        .run(|cmd| {
            let barrier = |from: &PassAccesses, to: &PassAccesses| {
                let b: Barrier = Barrier::between(from, to).expect("the images change layout");
                // SAFETY: a OneShot command buffer of `ctx`, recording outside rendering on
                // its graphics queue; the G-buffer outlives the run and is in the earlier
                // declared use's layouts (the frames below run in that order).
                unsafe { b.record(device, cmd, check, "host") };
            };
            // SAFETY: as above; the draws' vertex buffer outlives the run, which waits.
            unsafe { list.record_update(device, cmd, &draws)? };
            for time in [0.0, 1.0] {
                if host {
                    barrier(&gbuffer.earlier_accesses(), &declared);
                }
                // SAFETY: as above; the list was updated before.
                unsafe { pass.record(device, cmd, &list, &camera, time, &gbuffer) };
                if host && !skip_exit {
                    barrier(&declared, &gbuffer.read_accesses());
                }
            }
            // SAFETY: as above, after the passes (once: the readback orders no earlier copy
            // into its buffer).
            unsafe { gbuffer.record_readback(device, cmd) };
            Ok(())
        })
        .expect("frames");
    drop(vertices);
    gbuffer.read().expect("read back")
}

/// The barriers the pass recorded by hand before its declarations drove them: per image,
/// from UNDEFINED (after compute sampled reads and transfer reads) to its attachment layout,
/// and after the drawing to its read layout for compute sampled reads.
#[test]
fn the_gbuffer_pass_declares_the_transitions_it_recorded_by_hand() {
    let ctx = context();
    let (_vertices, _) = triangles(&ctx);
    let list = DrawList::new(&ctx, 2).expect("draw list");
    let pass = GBufferPass::new(&ctx).expect("G-buffer pass");
    let gbuffer = GBuffer::new(&ctx, SIZE.0, SIZE.1).expect("G-buffer");
    let declared = pass.accesses(&list, &gbuffer);
    use vk::ImageLayout as L;
    let entry = Barrier::between(&gbuffer.earlier_accesses(), &declared).expect("entry");
    let exit = Barrier::between(&declared, &gbuffer.read_accesses()).expect("exit");
    assert_eq!(Access::from(entry.before), Access::NONE, "images only");
    assert_eq!(Access::from(exit.before), Access::NONE, "images only");
    let names = [
        "G-buffer depth",
        "G-buffer normals",
        "G-buffer albedo",
        "G-buffer motion",
        "G-buffer triangle ids",
        "G-buffer positions",
    ];
    assert_eq!(entry.images.len(), names.len());
    assert_eq!(exit.images.len(), names.len());
    for ((name, e), x) in names.iter().zip(&entry.images).zip(&exit.images) {
        let depth = *name == "G-buffer depth";
        let (attachment, written, read) = if depth {
            (
                L::DEPTH_ATTACHMENT_OPTIMAL,
                Access::DEPTH_ATTACHMENT,
                L::DEPTH_STENCIL_READ_ONLY_OPTIMAL,
            )
        } else {
            (
                L::COLOR_ATTACHMENT_OPTIMAL,
                Access::COLOR_ATTACHMENT_WRITE,
                L::SHADER_READ_ONLY_OPTIMAL,
            )
        };
        assert_eq!((e.name, x.name), (*name, *name));
        assert_eq!((e.old, e.new), (L::UNDEFINED, attachment), "{name} entry");
        assert_eq!(
            (Access::from(e.before), Access::from(e.after)),
            (
                Access::COMPUTE_SAMPLED_READ.and(Access::TRANSFER_READ),
                written
            ),
            "{name} entry"
        );
        assert_eq!((x.old, x.new), (attachment, read), "{name} exit");
        assert_eq!(
            (Access::from(x.before), Access::from(x.after)),
            (written, Access::COMPUTE_SAMPLED_READ),
            "{name} exit"
        );
        assert_eq!((e.layers, x.layers), (1, 1));
    }
    assert_no_validation_messages(&ctx);
}

#[test]
fn a_host_issuing_the_gbuffer_pass_declared_barriers_gets_the_same_gbuffer() {
    let ctx = context();
    let own = two_frames(&ctx, false, false);
    assert_no_validation_messages(&ctx);
    let host = two_frames(&ctx, true, false);
    assert_no_validation_messages(&ctx);
    let drawn = own.ids.iter().filter(|&&id| id != u32::MAX).count();
    assert!(drawn > 20, "the triangles cover {drawn} pixels");
    assert!(own == host, "the host's barriers changed the G-buffer");
}

#[test]
fn a_host_leaving_out_the_gbuffer_exit_transition_is_reported_by_validation() {
    let ctx = context();
    two_frames(&ctx, true, true);
    let messages = ctx.validation_messages();
    assert!(
        messages.iter().any(|m| m.contains("Layout")),
        "the images were left in their attachment layouts: {messages:?}"
    );
}
