//! What every GPU test needs: a validated context on a real Vulkan device (lavapipe in CI)
//! (`test-support`'s `gpu`, here `support::device`), and small scenes built by
//! hand, rendered with the app's standalone renderer.

use glam::Vec3;
use motion_shadows::gpu::Context;
use motion_shadows::technique::{PrismConstruction, ShadowMapContents};
use motion_shadows_app::render::{Method, RenderResult, RenderSettings, Renderer};
use motion_shadows_app::scene::{Camera, DirectionalLight, Light, Mesh, Scene, SpotLight};

pub use super::device::{assert_no_validation_messages, context};

/// `scene` on a renderer of its own (its pipelines made for this frame alone).
pub fn render(ctx: &Context, scene: &Scene, settings: &RenderSettings) -> RenderResult {
    render_with(&mut renderer(ctx), scene, settings)
}

/// A renderer for a test's frames. Made once per test and passed to [`render_with`]: making
/// the passes' pipelines and the first frame's variants takes lavapipe about 1.5 s, three to
/// six times a small frame (a fresh renderer renders what a reused one does:
/// `lighting::a_reused_renderer_renders_like_a_fresh_one`).
pub fn renderer(ctx: &Context) -> Renderer<'_> {
    Renderer::new(ctx).expect("renderer")
}

/// `scene` on `renderer`, whose pipelines earlier frames made.
pub fn render_with(
    renderer: &mut Renderer,
    scene: &Scene,
    settings: &RenderSettings,
) -> RenderResult {
    motion_shadows_app::frame::render(Some(renderer), scene, settings, &mut |_| {}).expect("render")
}

/// The temporal shadow map of `scene` at `shadow_size` (the camera image is a token 8x8),
/// built with the default (exact) prisms.
pub fn temporal_map(ctx: &Context, scene: &Scene, shadow_size: (u32, u32)) -> ShadowMapContents {
    temporal_map_with(ctx, scene, shadow_size, PrismConstruction::default(), true)
}

/// [`temporal_map`] with the prisms built as `prisms` says, and static draws in the static
/// layer or (`static_layer` false) in the lists.
pub fn temporal_map_with(
    ctx: &Context,
    scene: &Scene,
    shadow_size: (u32, u32),
    prisms: PrismConstruction,
    static_layer: bool,
) -> ShadowMapContents {
    let settings = RenderSettings {
        width: 8,
        height: 8,
        spp: 1,
        shadow_size: Some(shadow_size),
        method: Method::Temporal,
        prisms,
        static_layer,
        ..RenderSettings::default()
    };
    let result = render(ctx, scene, &settings);
    result
        .shadow_map
        .expect("temporal method keeps its map")
        .download(ctx)
        .expect("download")
}

pub fn mesh(name: &str, t0: Vec<Vec3>, t1: Vec<Vec3>, closed: bool) -> Mesh {
    Mesh {
        name: name.into(),
        albedo: Vec3::splat(0.8),
        closed,
        t0,
        t1,
    }
}

pub fn camera() -> Camera {
    Camera {
        position: Vec3::new(0.0, 6.0, 8.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y_deg: 50.0,
        near: 0.1,
        far: 100.0,
        t1: None,
    }
}

/// Straight down onto the xz plane, an orthographic box of half-width `half_extent`.
pub fn overhead_directional(half_extent: f32) -> Light {
    Light::Directional(DirectionalLight {
        direction: Vec3::NEG_Y,
        irradiance: 3.0,
        center: Vec3::ZERO,
        half_extent,
        distance: 10.0,
        near: 0.5,
        far: 20.0,
        t1: None,
    })
}

pub fn overhead_spot(height: f32, cone_deg: f32) -> Light {
    Light::Spot(SpotLight {
        position: Vec3::new(0.0, height, 0.0),
        direction: Vec3::NEG_Y,
        cone_angle_deg: cone_deg,
        intensity: 40.0,
        near: 0.5,
        far: 50.0,
        t1: None,
    })
}

pub fn scene(name: &str, light: Light, meshes: Vec<Mesh>) -> Scene {
    Scene {
        name: name.into(),
        camera: camera(),
        light,
        ambient: 0.0,
        meshes,
    }
}

/// Two triangles of a square in the xz plane at height y, corner (x, z), side s, facing +y.
pub fn square(x: f32, z: f32, s: f32, y: f32) -> Vec<Vec3> {
    let a = Vec3::new(x, y, z);
    let b = Vec3::new(x, y, z + s);
    let c = Vec3::new(x + s, y, z + s);
    let d = Vec3::new(x + s, y, z);
    vec![a, b, c, a, c, d]
}

pub fn translated(points: &[Vec3], by: Vec3) -> Vec<Vec3> {
    points.iter().map(|p| *p + by).collect()
}
