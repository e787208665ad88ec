//! The lighting pass: against an ordinary shadow map where nothing moves, reproducibility,
//! and independence from the starting buffer capacities.

use crate::support::gpu::{
    assert_no_validation_messages, context, mesh, overhead_spot, render, scene,
};
use glam::{Vec2, Vec3};
use motion_shadows_app::output::write_exr;
use motion_shadows_app::render::{Method, RenderSettings};
use motion_shadows_app::scene::{BuiltinOptions, RigidTransform, box_mesh, builtin, plane_mesh};

fn static_scene() -> motion_shadows_app::scene::Scene {
    let ground = plane_mesh(Vec2::splat(12.0), 4);
    let block = RigidTransform {
        translation: Vec3::new(0.5, 1.5, 0.0),
        rotation_axis: Vec3::Y,
        rotation_deg: 30.0,
        scale: Vec3::ONE,
    }
    .apply(&box_mesh(Vec3::new(1.5, 1.0, 2.0), 2));
    scene(
        "static-occluder",
        overhead_spot(8.0, 50.0),
        vec![
            mesh("ground", ground.clone(), ground, false),
            mesh("block", block.clone(), block, true),
        ],
    )
}

fn settings(method: Method) -> RenderSettings {
    RenderSettings {
        width: 160,
        height: 120,
        spp: 4,
        seed: 7,
        method,
        ..RenderSettings::default()
    }
}

/// Where nothing moves, the temporal shadow map must shadow exactly what an ordinary shadow
/// map (nearest depth and triangle id per texel) shadows. Both see the same samples and the
/// same receivers; they can only differ where a texel holds two triangles at nearly the same
/// depth (the ordinary map keeps one of them), which happens along the block's silhouette
/// edges on the ground: a fraction of a percent of the pixels.
#[test]
fn static_occluder_matches_plain_shadow_map() {
    let ctx = context();
    let s = static_scene();
    let temporal = render(&ctx, &s, &settings(Method::Temporal)).image;
    let plain = render(&ctx, &s, &settings(Method::Plain { time: 0.5 })).image;
    let pixels = (temporal.width * temporal.height) as usize;
    let differ = (0..pixels)
        .filter(|&i| {
            (0..3).any(|c| {
                let (a, b) = (temporal.rgb[3 * i + c], plain.rgb[3 * i + c]);
                (a - b).abs() > 1e-5 * a.abs().max(b.abs()).max(1e-3)
            })
        })
        .count();
    let dark = (0..pixels).filter(|&i| plain.rgb[3 * i] == 0.0).count();
    eprintln!("temporal vs plain: {differ} of {pixels} pixels differ; {dark} dark");
    assert!(
        dark > pixels / 50,
        "the scene must have a shadow: {dark} dark pixels"
    );
    assert!(
        differ * 200 < pixels,
        "{differ} of {pixels} pixels differ between temporal and plain"
    );
    assert_no_validation_messages(&ctx);
}

/// The same seed renders byte-identical EXR files.
#[test]
fn same_seed_gives_identical_exr() {
    let ctx = context();
    let s = builtin("cubes-toward-light", &BuiltinOptions::default()).unwrap();
    let settings = RenderSettings {
        width: 128,
        height: 96,
        spp: 4,
        seed: 3,
        ..RenderSettings::default()
    };
    let dir =
        std::env::temp_dir().join(format!("motion-shadows-determinism-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut files = Vec::new();
    for run in 0..2 {
        let image = render(&ctx, &s, &settings).image;
        let path = dir.join(format!("run{run}.exr"));
        write_exr(&path, &image).unwrap();
        files.push(std::fs::read(&path).unwrap());
    }
    let other_seed = render(
        &ctx,
        &s,
        &RenderSettings {
            seed: 4,
            ..settings.clone()
        },
    )
    .image;
    std::fs::remove_dir_all(&dir).ok();
    assert!(
        files[0] == files[1],
        "two renders with the same seed differ"
    );
    let first = render(&ctx, &s, &settings).image;
    assert_ne!(
        first.rgb, other_seed.rgb,
        "the seed must change the samples"
    );
    assert_no_validation_messages(&ctx);
}

/// Buffers that start far too small are grown and the frame re-run: the image is the same as
/// with ample room, bit for bit.
#[test]
fn tiny_starting_capacity_gives_the_same_image() {
    let ctx = context();
    let s = builtin("cubes-toward-light", &BuiltinOptions::default()).unwrap();
    let ample = RenderSettings {
        width: 128,
        height: 96,
        spp: 2,
        initial_node_capacity: Some(4_000_000),
        initial_range_capacity: Some(4_000_000),
        ..RenderSettings::default()
    };
    let tiny = RenderSettings {
        initial_node_capacity: Some(1),
        initial_range_capacity: Some(1),
        ..ample.clone()
    };
    let big = render(&ctx, &s, &ample);
    let small = render(&ctx, &s, &tiny);
    assert_eq!(big.stats.shadow_pass_attempts, 1);
    assert!(small.stats.shadow_pass_attempts > 1);
    assert_eq!(small.stats.fragments, big.stats.fragments);
    assert_eq!(small.stats.ranges, big.stats.ranges);
    assert!(small.image.rgb == big.image.rgb, "images differ");
    assert_no_validation_messages(&ctx);
}

/// Ranges that only exist in part of the frame must matter: under a moving block the temporal
/// method's ground is partly lit (the shadow blurred along the path) over many pixels, where
/// an ordinary shadow map taken at one time (mid-shutter) leaves a hard shadow with partly lit
/// pixels only along its edges' antialiasing: at least four times as many.
#[test]
fn moving_occluder_blurs_its_shadow() {
    let ctx = context();
    let ground = plane_mesh(Vec2::splat(12.0), 4);
    let block0 = box_mesh(Vec3::new(1.0, 0.5, 1.0), 1)
        .iter()
        .map(|p| *p + Vec3::new(-2.0, 2.0, 0.0))
        .collect::<Vec<_>>();
    let block1 = block0.iter().map(|p| *p + Vec3::X * 4.0).collect();
    let s = scene(
        "moving-block",
        overhead_spot(8.0, 50.0),
        vec![
            mesh("ground", ground.clone(), ground, false),
            mesh("block", block0, block1, true),
        ],
    );
    let settings = RenderSettings {
        width: 160,
        height: 120,
        spp: 16,
        seed: 1,
        ..RenderSettings::default()
    };
    let blurred = render(&ctx, &s, &settings);
    let image = &blurred.image;
    // Under the path of the block the ground is partly lit: neither fully dark nor fully lit.
    let (w, h) = (image.width as usize, image.height as usize);
    let unshadowed = render(
        &ctx,
        &scene("lit", overhead_spot(8.0, 50.0), vec![s.meshes[0].clone()]),
        &settings,
    )
    .image;
    // Ground pixels only: no sample of the pixel sees the (motion-blurred) block itself.
    let partly_lit = |rgb: &[f32], moving: &[f32]| {
        (0..w * h)
            .filter(|&i| {
                let (v, lit) = (rgb[3 * i], unshadowed.rgb[3 * i]);
                moving[i] == 0.0 && lit > 0.0 && v > 0.2 * lit && v < 0.8 * lit
            })
            .count()
    };
    let partial = partly_lit(&image.rgb, &blurred.moving_coverage);
    let one_time = RenderSettings {
        method: Method::Plain { time: 0.5 },
        ..settings.clone()
    };
    let hard = render(&ctx, &s, &one_time);
    let hard = partly_lit(&hard.image.rgb, &hard.moving_coverage);
    eprintln!("partly lit pixels: temporal {partial}, one map at mid-shutter {hard}");
    assert!(partial > 200, "only {partial} partly shadowed pixels");
    assert!(
        partial > 4 * hard,
        "temporal {partial}, one map at mid-shutter {hard}"
    );
    assert_no_validation_messages(&ctx);
}

/// One renderer serving many frames of different sizes (as `bench` uses it) renders each like
/// a fresh one. Buffers are freed and made anew every frame, and a driver may hand a new buffer
/// the handle of a freed one: descriptors must follow the buffers, not the handle values.
#[test]
fn a_reused_renderer_renders_like_a_fresh_one() {
    let ctx = context();
    let s = builtin("cubes-toward-light", &BuiltinOptions::default()).unwrap();
    let mut renderer = motion_shadows_app::render::Renderer::new(&ctx).unwrap();
    let sizes = [(64, 48), (96, 72), (64, 48), (80, 60), (96, 72), (64, 48)];
    for (i, &(width, height)) in sizes.iter().enumerate() {
        let settings = RenderSettings {
            width,
            height,
            spp: 2,
            seed: i as u32,
            ..RenderSettings::default()
        };
        let reused = renderer.render(&s, &settings, &mut |_| {}).unwrap().image;
        let fresh = render(&ctx, &s, &settings).image;
        assert!(
            reused.rgb == fresh.rgb,
            "frame {i} ({width}x{height}) differs"
        );
    }
    assert_no_validation_messages(&ctx);
}
