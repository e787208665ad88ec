//! The deferred mask on a device that leaves loops after a fixed count (lavapipe): a moving
//! receiver walks the ranges of every shadow texel its path crosses, and a long path over a
//! fine map is more than one shader invocation may run. The mask goes on with such walks in
//! follow-up rounds: it must answer as the exact truth does (the CPU's lit share of each
//! G-buffer point, `render_truth`), with both lookups, and say clearly when even its rounds
//! are not enough (lavapipe, validation on).
//!
//! The scene: a floor sliding 16 units along x under an overhead light, and a slab sliding 6
//! units the other way above it, shadowing each floor point for 2/22 of the shutter. The
//! depth-line lookup walks about 4 loop iterations per texel: its map is 8,192 texels along the
//! motion (64 across, over a strip 0.1 wide that the camera looks at), so that a floor point
//! crosses up to 5,000 texels. The exact lookup walks about 20 per texel (its conservative
//! lists name more triangles): a square map of 1024 x 1024 texels over 16 units does.

use glam::{Vec2, Vec3};
use motion_shadows::gpu::{Context, ContextOptions};
use motion_shadows::technique::Lookup;
use motion_shadows_app::raytrace::deferred::render_truth;
use motion_shadows_app::render::deferred::{DeferredMethod, DeferredResult, DeferredSettings};
use motion_shadows_app::render::{RenderSettings, Renderer};
use motion_shadows_app::scene::{
    Camera, DirectionalLight, Light, Mesh, Scene, box_mesh, plane_mesh,
};

/// What the map and the camera look at.
#[derive(Clone, Copy)]
struct Setup {
    map: (u32, u32),
    /// The map's half width across the motion; along it, that times the map's aspect.
    half_extent: f32,
    image: (u32, u32),
    fov_y_deg: f32,
}

/// A strip 0.1 wide, 12.8 long, 8,192 texels along it; the camera sees 0.08 of its width.
const STRIP: Setup = Setup {
    map: (8192, 64),
    half_extent: 0.05,
    image: (128, 8),
    fov_y_deg: 0.76,
};

/// 16 x 16 units, 1,024 texels a side; the camera sees 7.5 x 5.6 of it.
const SQUARE: Setup = Setup {
    map: (768, 768),
    half_extent: 8.0,
    image: (64, 48),
    fov_y_deg: 50.0,
};

fn mesh(name: &str, t0: Vec<Vec3>, t1: Vec<Vec3>) -> Mesh {
    Mesh {
        name: name.into(),
        albedo: Vec3::splat(0.7),
        closed: false,
        t0,
        t1,
    }
}

fn moved(points: &[Vec3], by: Vec3) -> Vec<Vec3> {
    points.iter().map(|&p| p + by).collect()
}

fn long_paths(setup: Setup) -> Scene {
    let floor = plane_mesh(Vec2::splat(40.0), 4);
    let slab = box_mesh(Vec3::new(2.0, 0.1, 6.0), 1);
    Scene {
        name: "long-paths".into(),
        camera: Camera {
            position: Vec3::new(0.0, 6.0, 0.01),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y_deg: setup.fov_y_deg,
            near: 0.1,
            far: 50.0,
            t1: None,
        },
        light: Light::Directional(DirectionalLight {
            direction: Vec3::new(0.0, -1.0, 0.0),
            irradiance: 3.0,
            center: Vec3::ZERO,
            half_extent: setup.half_extent,
            distance: 10.0,
            near: 0.1,
            far: 20.0,
            t1: None,
        }),
        ambient: 0.0,
        meshes: vec![
            mesh(
                "floor",
                moved(&floor, Vec3::new(-8.0, 0.0, 0.0)),
                moved(&floor, Vec3::new(8.0, 0.0, 0.0)),
            ),
            mesh(
                "slab",
                moved(&slab, Vec3::new(3.0, 1.0, 0.0)),
                moved(&slab, Vec3::new(-3.0, 1.0, 0.0)),
            ),
        ],
    }
}

fn settings(setup: Setup) -> RenderSettings {
    RenderSettings {
        width: setup.image.0,
        height: setup.image.1,
        shadow_size: Some(setup.map),
        ..RenderSettings::default()
    }
}

fn deferred(method: DeferredMethod, lookup: Lookup) -> DeferredSettings {
    DeferredSettings {
        method,
        lookup,
        ..DeferredSettings::default()
    }
}

fn context() -> Context {
    Context::headless(&ContextOptions { validation: true })
        .expect("GPU tests need a Vulkan device and the validation layer")
}

fn render(
    renderer: &mut Renderer<'_>,
    setup: Setup,
    lookup: Lookup,
) -> motion_shadows_app::Result<DeferredResult> {
    renderer.render_deferred(
        &long_paths(setup),
        &settings(setup),
        &deferred(DeferredMethod::Temporal, lookup),
        &mut |_| {},
    )
}

fn assert_silent(ctx: &Context) {
    let messages = ctx.validation_messages();
    assert!(messages.is_empty(), "validation: {}", messages.join("\n"));
}

/// Any one pixel's lit share off the truth's by at most this: the slab's edges cross a
/// texel in 1/22 of 16/1024 of the shutter (square map), f32 roots elsewhere.
const LARGEST_DIFFERENCE: f32 = 2e-3;

/// The mask's loop budget per invocation and its follow-up rounds, where a test sets them.
#[derive(Clone, Copy)]
struct Walks {
    budget: u32,
    rounds: u32,
}

fn answered_as_the_truth(setup: Setup, lookup: Lookup, walks: Option<Walks>) {
    let ctx = context();
    let scene = long_paths(setup);
    let truth = render_truth(
        &scene,
        &settings(setup),
        &deferred(DeferredMethod::Raytrace, Lookup::DepthLine),
        &mut |_| {},
    )
    .expect("truth");
    let mut renderer = Renderer::new(&ctx).expect("renderer");
    if let Some(walks) = walks {
        renderer.set_mask_loop_budget(walks.budget).expect("passes");
        renderer
            .set_mask_follow_up_rounds(walks.rounds)
            .expect("passes");
    }
    let r = render(&mut renderer, setup, lookup).expect("the mask answers every pixel");
    let compared: Vec<usize> = (0..truth.lit.len()).filter(|&i| truth.facing[i]).collect();
    let shadowed = compared.iter().filter(|&&i| truth.lit[i] < 0.99).count();
    let off: Vec<usize> = compared
        .iter()
        .copied()
        .filter(|&i| (r.lit[i] - truth.lit[i]).abs() > LARGEST_DIFFERENCE)
        .collect();
    let mean = compared
        .iter()
        .map(|&i| f64::from((r.lit[i] - truth.lit[i]).abs()))
        .sum::<f64>()
        / compared.len() as f64;
    println!(
        "{lookup:?}: {} pixels, {shadowed} shadowed, mean difference {mean}, {} off by more \
         than {LARGEST_DIFFERENCE}: {:?}",
        compared.len(),
        off.len(),
        off.iter()
            .map(|&i| (
                i % setup.image.0 as usize,
                i / setup.image.0 as usize,
                r.lit[i],
                truth.lit[i]
            ))
            .collect::<Vec<_>>()
    );
    assert!(
        shadowed * 2 > compared.len() && compared.len() * 2 > truth.lit.len(),
        "{shadowed} of {} pixels shadowed",
        compared.len()
    );
    assert!(off.is_empty(), "{} pixels off the truth", off.len());
    drop(renderer);
    assert_silent(&ctx);
}

#[test]
fn long_paths_with_depth_lines_are_answered_as_the_truth() {
    answered_as_the_truth(STRIP, Lookup::DepthLine, None);
}

#[test]
fn long_paths_with_the_exact_lookup_are_answered_as_the_truth() {
    answered_as_the_truth(SQUARE, Lookup::Exact, None);
}

/// With a budget of a few triangles' tests per invocation, the exact walks stop within texels'
/// lists too, carrying the texel's shadowed intervals so far to their next round: the answer
/// is the same. Over a fine map (each texel's window a sliver of the shutter) and a coarse
/// one (a texel's list alone decides a long window, the slab's edges inside it).
#[test]
fn exact_walks_stopped_within_texel_lists_are_answered_as_the_truth() {
    for setup in [SQUARE, COARSE] {
        answered_as_the_truth(
            setup,
            Lookup::Exact,
            Some(Walks {
                budget: EXACT_TEST_BUDGET,
                rounds: 400,
            }),
        );
    }
}

/// SQUARE's view over a map of 16 x 16 texels: a floor point crosses 16 of them.
const COARSE: Setup = Setup {
    map: (16, 16),
    ..SQUARE
};

/// A loop budget per invocation (per lane) of a handful of exact tests: the walks over SQUARE
/// stop within texels' lists and need many rounds.
const EXACT_TEST_BUDGET: u32 = 64;

/// With too few follow-up rounds the frame is refused, with the count of pixels left and what
/// the deferred frame can do about it; each round finishes some of them (the exact lookup's
/// paths here need several invocations each at a budget of 512; the first round starts over
/// what the first dispatch could not finish).
#[test]
fn long_paths_past_the_last_round_are_refused_with_the_count() {
    let ctx = context();
    let mut renderer = Renderer::new(&ctx).expect("renderer");
    let mut left = Vec::new();
    renderer.set_mask_loop_budget(512).expect("passes");
    for rounds in [8, 12, 16] {
        renderer.set_mask_follow_up_rounds(rounds).expect("passes");
        let Err(error) = render(&mut renderer, SQUARE, Lookup::Exact) else {
            panic!("{rounds} rounds: the frame must be refused");
        };
        let error = error.to_string();
        println!("{rounds} rounds: {error}");
        for option in ["follow-up rounds", "--static-receivers", "--shadow-size"] {
            assert!(error.contains(option), "{error}");
        }
        let count: u32 = error
            .split(' ')
            .next()
            .and_then(|n| n.parse().ok())
            .expect("the error starts with the count of pixels");
        left.push(count);
    }
    assert!(
        left[0] > 1000 && left[1] < left[0] && left[2] < left[1],
        "pixels left after 8, 12, 16 rounds: {left:?}"
    );
    drop(renderer);
    assert_silent(&ctx);
}
