//! The lighting pass declares its accesses (issue 37, item 2): a host records two frames of
//! the lighting pass into one target without the pass's entry barrier (`with_host_barriers`)
//! and issues the one the declarations give between them (`Barrier::between` the pass's
//! accesses and the target's readback, then the next frame's): the access check passes and
//! validation stays silent; leaving it out is reported, naming the target's header and the
//! lighting pass on both sides. The pass with its own entry barrier passes the check too.

use crate::pass_accesses::{light, triangles};
use crate::support::gpu::{assert_no_validation_messages, context};
use motion_shadows::Error;
use motion_shadows::glam::Vec3;
use motion_shadows::gpu::{Context, OneShot};
use motion_shadows::technique::{
    Barrier, CameraView, CollectionPass, DrawList, GenerationPass, LightingPass, LightingTarget,
    LightingView, PrismConstruction, ShadowSource, TemporalShadowMap,
};

const SIZE: (u32, u32) = (16, 12);

/// Two lighting frames into one target after one collection and generation; `host`: the
/// pass's entry barrier is the host's (left out when `skip`). What the check says.
fn two_frames(ctx: &Context, host: bool, skip: bool) -> motion_shadows::Result<()> {
    let check = ctx.access_check();
    check.enable();
    let light = light(PrismConstruction::Paper);
    let (vertices, draws) = triangles(ctx);
    let mut list = DrawList::new(ctx, 2)?;
    let collection = CollectionPass::new(ctx)?;
    let generation = GenerationPass::new(ctx)?;
    let lighting = LightingPass::new(ctx)?;
    let lighting = if host {
        lighting.with_host_barriers()
    } else {
        lighting
    };
    let mut map = TemporalShadowMap::new(ctx, 32, 32, 1 << 12, 1 << 12)?;
    map.prepare_for(ctx, &light, None)?;
    let target = LightingTarget::new(ctx, SIZE.0, SIZE.1, 2, 2)?;
    let view = LightingView {
        camera: CameraView::perspective(
            Vec3::new(0.0, 6.0, 4.0),
            Vec3::ZERO,
            Vec3::Y,
            60.0,
            SIZE.0 as f32 / SIZE.1 as f32,
            0.1,
            50.0,
        ),
        seed: 1,
        ambient: 0.1,
        estimator: Default::default(),
        filter: Default::default(),
    };
    let shadow = ShadowSource::Temporal(&map);
    let declared = lighting.accesses(&list, shadow, &target);
    let device = ctx.device();
    OneShot::new(ctx)?.run(|cmd| {
        // SAFETY: a OneShot command buffer of `ctx`, recording outside rendering on its
        // graphics and compute queue; every object outlives the run, which waits.
        unsafe {
            list.record_update(device, cmd, &draws)?;
            collection.record(device, cmd, &list, &light, &map, None)?;
            generation.record(device, cmd, &map);
        }
        for frame in 0..2 {
            if host && !(skip && frame == 1) {
                let earlier = declared.clone().and(&target.readback_accesses());
                let b = Barrier::between(&earlier, &declared).expect("the frames conflict");
                // SAFETY: as above.
                unsafe { b.record(device, cmd, check, "host") };
            }
            // SAFETY: as above; the list was updated and the map generated before.
            unsafe {
                lighting.record(device, cmd, &list, &view, shadow, &target, None)?;
                target.record_readback(device, cmd);
            }
        }
        Ok(())
    })?;
    drop(vertices);
    check.end_frame()
}

#[test]
fn a_host_issuing_the_lighting_pass_declared_entry_barrier_passes_the_check() {
    let ctx = context();
    two_frames(&ctx, true, false).expect("every barrier issued and reported");
    assert_no_validation_messages(&ctx);
    let ctx = context();
    two_frames(&ctx, false, false).expect("the pass's own entry barrier");
    assert_no_validation_messages(&ctx);
}

#[test]
fn a_host_skipping_the_lighting_pass_declared_entry_barrier_is_reported() {
    let ctx = context();
    match two_frames(&ctx, true, true) {
        Err(Error::MissingBarrier {
            resource,
            previous,
            next,
        }) => {
            assert_eq!(resource, "lighting target header");
            assert!(previous.starts_with("lighting ("), "{previous}");
            assert!(next.starts_with("lighting ("), "{next}");
        }
        other => panic!("the check said {other:?}"),
    }
}

/// The copy into a host image reads the radiance the lighting pass wrote: the barrier its
/// declarations give after the lighting pass is the shading's writes before compute storage
/// reads, which the lighting pass's own closing barrier (compute writes before compute and
/// transfer reads) holds; the host's image is its own, in `GENERAL`.
#[test]
fn the_lighting_image_output_declares_its_radiance_reads() {
    use motion_shadows::ash::vk;
    use motion_shadows::gpu::Access;
    use motion_shadows::technique::{LightingImageOutput, Resource};
    let ctx = context();
    let (_vertices, _) = triangles(&ctx);
    let list = DrawList::new(&ctx, 2).expect("draw list");
    let map = TemporalShadowMap::new(&ctx, 32, 32, 1 << 12, 1 << 12).expect("map");
    let target = LightingTarget::new(&ctx, SIZE.0, SIZE.1, 2, 2).expect("target");
    let lighting = LightingPass::new(&ctx).expect("lighting");
    let output = LightingImageOutput::new(&ctx).expect("output");
    let declared = output.accesses(&target, vk::ImageView::null());
    let image = declared
        .uses
        .iter()
        .find(|u| matches!(u.resource, Resource::ImageView { .. }))
        .expect("the host's image");
    assert_eq!(
        image.resource,
        Resource::ImageView {
            view: vk::ImageView::null(),
            layout: vk::ImageLayout::GENERAL
        }
    );
    assert!(image.writes);
    let lit = lighting.accesses(&list, ShadowSource::Temporal(&map), &target);
    let b = Barrier::between(&lit, &declared).expect("the radiance is read after its writes");
    let read = Access {
        stages: vk::PipelineStageFlags2::COMPUTE_SHADER,
        access: vk::AccessFlags2::SHADER_STORAGE_READ,
    };
    assert_eq!(
        (Access::from(b.before), Access::from(b.after)),
        (Access::COMPUTE_RW, read)
    );
    assert!(b.images.is_empty());
    assert_no_validation_messages(&ctx);
}
