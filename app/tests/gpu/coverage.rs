//! The coverage map (2017 paper's extension): fewer ranges, the same image, and never a pixel
//! marked covered unless one triangle is its nearest occluder all frame long.

use crate::support::gpu::{
    assert_no_validation_messages, context, mesh, overhead_directional, overhead_spot, render_with,
    renderer, scene, square, translated,
};
use glam::{Quat, Vec2, Vec3};
use motion_shadows_app::render::{Method, RenderResult, RenderSettings};
use motion_shadows_app::scene::{Light, Scene, box_mesh, plane_mesh};

/// The temporal method keeps static triangles in its lists here, as the coverage map's
/// passes do, so that the two store the same fragments.
fn settings(method: Method) -> RenderSettings {
    RenderSettings {
        width: 128,
        height: 96,
        spp: 4,
        seed: 5,
        shadow_size: Some((64, 64)),
        method,
        static_layer: false,
        ..RenderSettings::default()
    }
}

fn both(ctx: &motion_shadows::gpu::Context, s: &Scene) -> (RenderResult, RenderResult) {
    let mut renderer = renderer(ctx);
    (
        render_with(&mut renderer, s, &settings(Method::Temporal)),
        render_with(&mut renderer, s, &settings(Method::Coverage)),
    )
}

/// A static block over a static ground: under the block only the block's range is stored.
#[test]
fn covered_pixels_keep_one_range_and_the_image_is_the_same() {
    let ctx = context();
    let ground = plane_mesh(Vec2::splat(12.0), 8);
    let block: Vec<Vec3> = box_mesh(Vec3::new(3.0, 1.0, 3.0), 2)
        .iter()
        .map(|p| *p + Vec3::Y * 2.0)
        .collect();
    let s = scene(
        "static-block",
        overhead_spot(8.0, 50.0),
        vec![
            mesh("ground", ground.clone(), ground, false),
            mesh("block", block.clone(), block, true),
        ],
    );
    let (temporal, coverage) = both(&ctx, &s);
    let c = &coverage.stats;
    eprintln!(
        "static block: ranges {} with coverage, {} without ({} temporal)",
        c.ranges, c.ranges_without_coverage, temporal.stats.ranges
    );
    assert_eq!(c.ranges_without_coverage, temporal.stats.ranges);
    assert!(c.ranges < c.ranges_without_coverage, "nothing was covered");
    assert!(coverage.image.rgb == temporal.image.rgb, "images differ");
    assert_no_validation_messages(&ctx);
}

/// Both methods at a size where every shadow texel is small, same samples: the images must
/// be identical, and the coverage method must not store more ranges.
fn assert_same_image(
    ctx: &motion_shadows::gpu::Context,
    s: &Scene,
) -> (RenderResult, RenderResult) {
    let (temporal, coverage) = both(ctx, s);
    assert_same_results(ctx, &temporal, &coverage);
    (temporal, coverage)
}

fn assert_same_results(
    ctx: &motion_shadows::gpu::Context,
    temporal: &RenderResult,
    coverage: &RenderResult,
) {
    assert_eq!(
        coverage.stats.ranges_without_coverage,
        temporal.stats.ranges
    );
    assert!(coverage.stats.ranges <= temporal.stats.ranges);
    let pixels = temporal.image.rgb.len() / 3;
    let differ: Vec<usize> = (0..pixels)
        .filter(|&i| (0..3).any(|c| temporal.image.rgb[3 * i + c] != coverage.image.rgb[3 * i + c]))
        .collect();
    let width = temporal.image.width as usize;
    let first: Vec<_> = differ
        .iter()
        .take(8)
        .map(|i| (i % width, i / width))
        .collect();
    assert_eq!(
        differ.len(),
        0,
        "{} of {pixels} pixels differ, first at {first:?}",
        differ.len()
    );
    assert_no_validation_messages(ctx);
}

fn ground() -> motion_shadows_app::scene::Mesh {
    let g = plane_mesh(Vec2::splat(14.0), 4);
    mesh("ground", g.clone(), g, false)
}

/// A triangle turning half a turn about its centre (vertices move straight through it) covers
/// pixels near the centre at t = 0 and t = 1, but not in between: the caps pass marks them, and
/// only the reset of a pixel that the triangle's own edges sweep over unmarks them. A marked
/// pixel stores no ranges, so every pixel the triangle touches must keep all its ranges.
#[test]
fn covering_at_both_ends_but_not_between_is_not_covered() {
    let centre = Vec3::new(0.5, 2.0, 0.3);
    let t0: Vec<Vec3> = [
        Vec3::new(-2.0, 0.0, -1.5),
        Vec3::new(-0.5, 0.0, 2.5),
        Vec3::new(2.5, 0.0, -1.0),
    ]
    .iter()
    .map(|v| centre + *v)
    .collect();
    let half_turn = Quat::from_rotation_y(std::f32::consts::PI);
    let t1: Vec<Vec3> = t0
        .iter()
        .map(|p| centre + half_turn * (*p - centre))
        .collect();
    let s = scene(
        "half-turn",
        overhead_directional(8.0),
        vec![ground(), mesh("turning", t0, t1, false)],
    );
    let ctx = context();
    let (temporal, coverage) = both(&ctx, &s);
    let download = |r: &RenderResult| r.shadow_map.as_ref().unwrap().download(&ctx).unwrap();
    let (t_map, c_map) = (download(&temporal), download(&coverage));
    let turning = s.meshes[0].triangle_count() as u32; // the ground's triangles come first
    let key = |r: &motion_shadows::technique::Range| (r.id, r.t_s.to_bits(), r.t_e.to_bits());
    let mut touched = 0;
    for y in 0..t_map.height {
        for x in 0..t_map.width {
            let mut want: Vec<_> = t_map.ranges_at(x, y).iter().map(key).collect();
            if !want.iter().any(|k| k.0 == turning) {
                continue;
            }
            touched += 1;
            let mut got: Vec<_> = c_map.ranges_at(x, y).iter().map(key).collect();
            want.sort();
            got.sort();
            assert_eq!(
                got, want,
                "pixel ({x},{y}), swept by the turning triangle, lost ranges"
            );
        }
    }
    assert!(touched > 100, "{touched} pixels touched");
    assert_same_results(&ctx, &temporal, &coverage);
}

/// A static square (the covering triangle pair) with a small square crossing in front of it
/// mid-frame: the crossed pixels must be reset, or the small square's shadow on the big one
/// would vanish from the image. Elsewhere under the big square only its own range is kept.
#[test]
fn a_blocker_crossing_in_front_mid_frame_resets_the_pixel() {
    let big = square(-3.0, -3.0, 6.0, 1.0);
    let small0 = square(-6.0, -0.5, 1.0, 2.5);
    let small1 = translated(&small0, Vec3::X * 10.0);
    let s = scene(
        "crossing-blocker",
        overhead_directional(8.0),
        vec![
            ground(),
            mesh("big", big.clone(), big, false),
            mesh("small", small0, small1, false),
        ],
    );
    let (temporal, coverage) = assert_same_image(&context(), &s);
    assert!(
        coverage.stats.ranges < temporal.stats.ranges,
        "the big square's uncrossed pixels should keep one range"
    );
}

/// The covering triangle moves in depth: a square rises through a static smaller square, so the
/// small one is nearer to the light for the first half of the frame and farther for the second.
/// At t = 1 the rising square is the nearest, and both its caps cover the pixels; only comparing
/// each fragment with the covering square's depth at that fragment's time resets them. A mark
/// would drop the small square's range and light the rising square where the small one shadows
/// it early in the frame.
#[test]
fn a_covering_triangle_moving_in_depth_is_reset_by_what_it_passes() {
    let rising0 = square(-3.0, -3.0, 6.0, 1.0);
    let rising1 = translated(&rising0, Vec3::Y * 2.0);
    let middle = square(-1.0, -1.0, 2.0, 2.0);
    let s = scene(
        "rising-square",
        overhead_directional(8.0),
        vec![
            ground(),
            mesh("rising", rising0, rising1, false),
            mesh("middle", middle.clone(), middle, false),
        ],
    );
    assert_same_image(&context(), &s);
}

/// The 2017 paper's Fig. 8 setting, scaled down for CI: random cubes at the default speeds.
/// The coverage method stores fewer ranges and renders the same image, up to a tiny share of
/// pixels: the covering triangle's depth comes from the coverage pass (its caps drawn by the
/// depth-map vertex shader) rather than from the prism's cap fragments, which may differ in
/// the last bit and flip a comparison that is a tie to within rounding.
#[test]
fn random_cubes_store_fewer_ranges_and_render_the_same() {
    let ctx = context();
    let mut renderer = renderer(&ctx);
    let options = motion_shadows_app::scene::BuiltinOptions {
        cube_count: 1000,
        ..Default::default()
    };
    let s = motion_shadows_app::scene::builtin("random-cubes", &options).unwrap();
    let at = |method| RenderSettings {
        width: 160,
        height: 120,
        spp: 4,
        seed: 9,
        method,
        static_layer: false,
        ..RenderSettings::default()
    };
    let temporal = render_with(&mut renderer, &s, &at(Method::Temporal));
    let coverage = render_with(&mut renderer, &s, &at(Method::Coverage));
    let (with, without) = (
        coverage.stats.ranges,
        coverage.stats.ranges_without_coverage,
    );
    eprintln!(
        "random cubes (1000): {without} ranges without the coverage map, {with} with ({:.2}x fewer)",
        without as f64 / with.max(1) as f64
    );
    assert_eq!(without, temporal.stats.ranges);
    assert!(with < without);
    let pixels = temporal.image.rgb.len() / 3;
    let differ = (0..pixels)
        .filter(|&i| (0..3).any(|c| temporal.image.rgb[3 * i + c] != coverage.image.rgb[3 * i + c]))
        .count();
    eprintln!("random cubes: {differ} of {pixels} pixels differ");
    assert!(
        differ * 1000 <= pixels,
        "{differ} of {pixels} pixels differ"
    );
    assert_no_validation_messages(&ctx);
}

/// A triangulated ground sinking away from an overhead directional light, with nothing above
/// it: the coverage map marks its texels with its own triangles, and a sample on another of
/// its triangles in a marked texel (within a texel of the marked one's edges) is behind the
/// mark only by the mark's depth at the sample's own time. Every pixel whose samples all see
/// the ground must get the unshadowed Lambert radiance, albedo / pi times the irradiance (the
/// ground faces the light, no ambient). Fails when the covering triangle's depth is taken at
/// t = 0 instead of at the sample's time.
#[test]
fn a_surface_sinking_under_its_own_marks_stays_lit() {
    let ctx = context();
    let mut renderer = renderer(&ctx);
    let ground0: Vec<Vec3> = translated(&plane_mesh(Vec2::splat(12.0), 8), Vec3::Y * 2.0);
    let ground1 = translated(&ground0, Vec3::NEG_Y * 2.0);
    let s = scene(
        "sinking-ground",
        overhead_directional(8.0),
        vec![mesh("ground", ground0, ground1, false)],
    );
    let result = render_with(&mut renderer, &s, &settings(Method::Coverage));
    let stats = &result.stats;
    assert!(
        stats.ranges < stats.ranges_without_coverage,
        "nothing was covered"
    );
    let Light::Directional(light) = &s.light else {
        unreachable!("a directional light")
    };
    let unshadowed = 0.8 / std::f32::consts::PI * light.irradiance;
    let mut checked = 0;
    for (i, &share) in result.moving_coverage.iter().enumerate() {
        if share < 1.0 {
            continue;
        }
        checked += 1;
        for c in 0..3 {
            let v = result.image.rgb[3 * i + c];
            assert!(
                (v - unshadowed).abs() <= 1e-4 * unshadowed,
                "pixel {i}: radiance {v}, unshadowed {unshadowed}"
            );
        }
    }
    eprintln!("{checked} pixels on the ground, all unshadowed");
    assert!(checked > 5000, "{checked}");
    assert_no_validation_messages(&ctx);
}
