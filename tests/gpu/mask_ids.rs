//! The visibility mask refuses, by name and before recording anything, a dispatch whose
//! receivers move on a depth-line map without the host's triangle-id image (issue 37, item
//! 4): a turning surface's own triangle, a depth line per texel, would shadow it (measured on
//! a tumbling box against the ray tracer, docs/src/deferred-frame.md#triangle-ids). Which
//! other settings need the ids is the rule's unit test (`src/technique/mask.rs`).

use crate::support::gpu::{assert_no_validation_messages, context};
use motion_shadows::Error;
use motion_shadows::ash::vk;
use motion_shadows::glam::Mat4;
use motion_shadows::gpu::{Image, OneShot};
use motion_shadows::technique::{MaskInputs, MotionImage, TemporalShadowMap, VisibilityMaskPass};

const SIZE: u32 = 8;

#[test]
fn a_moving_mask_without_triangle_ids_is_refused_by_name() {
    let ctx = context();
    let map = TemporalShadowMap::new(&ctx, SIZE, SIZE, 1, 64).expect("map");
    let pass = VisibilityMaskPass::new(&ctx).expect("mask pass");
    let mut bindings = pass.bindings(&ctx, (SIZE, SIZE)).expect("bindings");
    let image = |name, format, usage| {
        Image::new(&ctx, name, (SIZE, SIZE, 1), format, usage).expect("image")
    };
    let sampled = vk::ImageUsageFlags::SAMPLED;
    let depth = image("depth", vk::Format::D32_SFLOAT, sampled);
    let motion = image("motion", vk::Format::R16G16B16A16_SFLOAT, sampled);
    let output = image("mask", vk::Format::R32_SFLOAT, vk::ImageUsageFlags::STORAGE);
    let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
    let inputs = MaskInputs::new(
        depth.layer_view(0),
        read,
        output.layer_view(0),
        (SIZE, SIZE),
        Mat4::IDENTITY,
    )
    .with_motion(
        MotionImage {
            view: motion.layer_view(0),
            layout: read,
        },
        1.0,
    );
    let mut refusal = None;
    let submitted = OneShot::new(&ctx).expect("command buffer").run(|cmd| {
        // SAFETY: a OneShot command buffer of the context, recording, outside rendering; the
        // bindings are fresh. The images were never written: a mask recorded here would read
        // them (the refusal is what is tested; the validation check below catches a record).
        refusal = unsafe { pass.record(ctx.device(), cmd, &mut bindings, &inputs, &map) }.err();
        Err(Error::InvalidArgument("not submitted".into()))
    });
    assert!(submitted.is_err());
    let refusal = refusal
        .expect("a moving mask without ids must be refused")
        .to_string();
    for named in ["triangle-id image", "MaskInputs::ids", "MaskInputs::motion"] {
        assert!(refusal.contains(named), "{named} not in: {refusal}");
    }
    assert_no_validation_messages(&ctx);
}
