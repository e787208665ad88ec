//! Filtered shadow lookups (`ShadowFilter::Bilinear`) against closed forms.
//!
//! A rectangle one unit above the ground, unbounded along z and crossing x in [A, B] (+V t
//! over the shutter), under a directional light slanted along x (so that the camera sees
//! both edges of the shadow beside the rectangle): whether the rectangle covers a
//! shadow-map texel's centre at time t, and for how much of the shutter, are closed forms in
//! where the centre's ray crosses the rectangle's height. The filtered lookup's definition is the mean of those answers over the
//! 2x2 texels around the receiver's projection, weighted by their overlap with a one-texel
//! box centred on it. Every 1-spp sample that lands on the ground is checked against that,
//! computed here from the sample's ray (the CPU mirror of the pass's sampling), the light's
//! matrices and the rectangle's edges: no shadow map involved. Plain (percentage-closer
//! filtering of an ordinary map), the temporal map at each sample's time, and the temporal
//! map's exact lit fraction of the shutter all follow the same definition.

use crate::support::gpu::{assert_no_validation_messages, context, mesh};
use crate::support::sampling::CameraRays;
use glam::{DVec2, DVec3, Vec2, Vec3};
use motion_shadows::technique::sampling::{pixel_key, pixel_sample};
use motion_shadows::technique::{ShadowEstimator, ShadowFilter};
use motion_shadows_app::render::upload::{camera_view, light_view};
use motion_shadows_app::render::{Method, RenderSettings};
use motion_shadows_app::scene::{DirectionalLight, Light, Scene, plane_mesh};

const IMAGE: (u32, u32) = (160, 120);
const SHADOW: (u32, u32) = (64, 64);
const SEED: u32 = 11;
/// The blocker's x extent at t = 0 (not on texel boundaries) and its travel over the shutter.
const A: f64 = -1.03;
const B: f64 = 0.61;
const HEIGHT: f32 = 1.0;
/// The light travels along (SLANT, -1, 0): a shadow falls SLANT units along x per unit of
/// height.
const SLANT: f32 = 2.0;
const IRRADIANCE: f32 = 3.0;

/// Radiance of lit ground: albedo 0.8 / pi * irradiance * cos, no ambient.
fn lit_radiance() -> f64 {
    let cos = 1.0 / (1.0 + f64::from(SLANT).powi(2)).sqrt();
    0.8 / std::f64::consts::PI * f64::from(IRRADIANCE) * cos
}

fn slanted_light() -> Light {
    Light::Directional(DirectionalLight {
        direction: Vec3::new(SLANT, -1.0, 0.0).normalize(),
        irradiance: IRRADIANCE,
        center: Vec3::ZERO,
        half_extent: 6.0,
        distance: 10.0,
        near: 0.5,
        far: 20.0,
        t1: None,
    })
}

fn blocker_scene(travel: f32) -> Scene {
    let strip = |x0: f32| {
        let (x1, y) = (x0 + (B - A) as f32, HEIGHT);
        let (a, b, c, d) = (
            Vec3::new(x0, y, -20.0),
            Vec3::new(x0, y, 20.0),
            Vec3::new(x1, y, 20.0),
            Vec3::new(x1, y, -20.0),
        );
        vec![a, b, c, a, c, d]
    };
    let ground = plane_mesh(Vec2::splat(16.0), 8);
    let mut s = crate::support::gpu::scene(
        "filtered-lookup",
        slanted_light(),
        vec![
            mesh("ground", ground.clone(), ground, false),
            mesh("blocker", strip(A as f32), strip(A as f32 + travel), false),
        ],
    );
    s.ambient = 0.0;
    s
}

/// What the filtered lookup must return at a ground point at time t.
enum Expect {
    /// Whether the blocker covers each texel centre at the sample's time.
    AtTime,
    /// The covered share of the shutter at each texel centre.
    Shutter,
}

struct Geometry {
    rays: CameraRays,
    to_light: glam::DMat4,
    from_light: glam::DMat4,
}

impl Geometry {
    fn new(scene: &Scene) -> Self {
        let light = light_view(scene, SHADOW);
        let to_light = (light.proj * light.view).as_dmat4();
        Self {
            rays: CameraRays::of(&camera_view(scene, IMAGE), IMAGE),
            to_light,
            from_light: to_light.inverse(),
        }
    }

    /// The position of world point p among the texel centres (integers: centres).
    fn texel_coords(&self, p: DVec3) -> DVec2 {
        let c = self.to_light * p.extend(1.0);
        let ndc = DVec2::new(c.x / c.w, c.y / c.w);
        (ndc * 0.5 + DVec2::splat(0.5)) * DVec2::new(f64::from(SHADOW.0), f64::from(SHADOW.1))
            - DVec2::splat(0.5)
    }

    /// World x where the ray of the centre of texel c crosses the blocker's height.
    fn centre_x(&self, c: glam::IVec2) -> f64 {
        let size = DVec2::new(f64::from(SHADOW.0), f64::from(SHADOW.1));
        let ndc = (c.as_dvec2() + DVec2::splat(0.5)) / size * 2.0 - DVec2::ONE;
        let world = |z: f64| {
            let w = self.from_light * ndc.extend(z).extend(1.0);
            w.truncate() / w.w
        };
        let (p0, p1) = (world(0.0), world(1.0));
        let s = (f64::from(HEIGHT) - p0.y) / (p1.y - p0.y);
        p0.x + s * (p1.x - p0.x)
    }
}

/// The lit answer of one texel centre at world x: `None` within rounding of an edge.
fn centre_lit(x: f64, t: f64, travel: f64, expect: &Expect) -> Option<f64> {
    match expect {
        Expect::AtTime => {
            let (a, b) = (A + travel * t, B + travel * t);
            if (x - a).abs() < 1e-3 || (x - b).abs() < 1e-3 {
                return None;
            }
            Some(if a < x && x < b { 0.0 } else { 1.0 })
        }
        Expect::Shutter => {
            // Covered while A + V t <= x <= B + V t.
            let (from, to) = (((x - B) / travel).max(0.0), ((x - A) / travel).min(1.0));
            Some(1.0 - (to - from).max(0.0))
        }
    }
}

/// Checks every ground sample of a 1-spp render; returns how many were on a ramp (strictly
/// between lit and shadowed) and how many were checked.
fn check(settings: &RenderSettings, travel: f32, expect: Expect, what: &str) -> (usize, usize) {
    let ctx = context();
    let scene = blocker_scene(travel);
    let result = crate::support::gpu::render(&ctx, &scene, settings);
    assert_eq!(result.stats.shadow_filter, "bilinear");
    let g = Geometry::new(&scene);
    let origin = g.rays.origin.as_dvec3();
    let travel = f64::from(travel);
    let (mut checked, mut ramp, mut worst) = (0, 0, 0.0f64);
    for y in 0..IMAGE.1 {
        for x in 0..IMAGE.0 {
            let (t, offset) = pixel_sample(pixel_key(x, y, SEED), 0, 1);
            let t = f64::from(t);
            let dir = g.rays.direction(x as f32 + offset.x, y as f32 + offset.y);
            if dir.y >= -1e-6 {
                continue;
            }
            // Samples that may see the blocker (or pass near its edges) are not ground.
            let at_blocker = origin + dir * ((f64::from(HEIGHT) - origin.y) / dir.y);
            let (a, b) = (A + travel * t, B + travel * t);
            if at_blocker.x > a - 0.05 && at_blocker.x < b + 0.05 {
                continue;
            }
            let ground = origin + dir * (-origin.y / dir.y);
            if ground.x.abs() > 7.5 || ground.z.abs() > 7.5 {
                continue;
            }
            let u = g.texel_coords(ground);
            let size = DVec2::new(f64::from(SHADOW.0), f64::from(SHADOW.1));
            if u.cmplt(DVec2::splat(-0.5)).any() || u.cmpge(size - 0.5).any() {
                // Outside the light's view: nothing shadows it (checked as such below).
                let got = f64::from(result.image.rgb[((y * IMAGE.0 + x) * 3 + 1) as usize]);
                assert!(
                    (got / lit_radiance() - 1.0).abs() < 2e-3,
                    "{what}: ({x},{y}) outside the map"
                );
                continue;
            }
            let base = u.floor();
            let f = u - base;
            let mut expected = 0.0;
            let mut sure = true;
            for k in 0..4 {
                let o = glam::IVec2::new(k & 1, k >> 1);
                let c = base.as_ivec2() + o;
                let w = (if o.x == 1 { f.x } else { 1.0 - f.x })
                    * (if o.y == 1 { f.y } else { 1.0 - f.y });
                let inside = c.x >= 0 && c.y >= 0 && c.x < SHADOW.0 as i32 && c.y < SHADOW.1 as i32;
                let lit = if inside {
                    centre_lit(g.centre_x(c), t, travel, &expect)
                } else {
                    Some(1.0)
                };
                match lit {
                    Some(v) => expected += w * v,
                    None => sure = false,
                }
            }
            if !sure {
                continue;
            }
            let got =
                f64::from(result.image.rgb[((y * IMAGE.0 + x) * 3 + 1) as usize]) / lit_radiance();
            worst = worst.max((got - expected).abs());
            assert!(
                (got - expected).abs() < 2e-3,
                "{what}: pixel ({x},{y}) at t = {t:.4}, ground ({:.4}, {:.4}): visibility {got:.5}, \
                 the filter's definition says {expected:.5}",
                ground.x,
                ground.z
            );
            checked += 1;
            ramp += usize::from(expected > 0.01 && expected < 0.99);
        }
    }
    eprintln!("{what}: {checked} ground samples, {ramp} on a ramp, worst difference {worst:.1e}");
    assert!(checked > 5000, "{what}: only {checked} samples checked");
    assert_no_validation_messages(&ctx);
    (ramp, checked)
}

fn settings(method: Method, estimator: ShadowEstimator) -> RenderSettings {
    RenderSettings {
        width: IMAGE.0,
        height: IMAGE.1,
        spp: 1,
        seed: SEED,
        shadow_size: Some(SHADOW),
        method,
        shadow_estimator: estimator,
        shadow_filter: ShadowFilter::Bilinear,
        ..RenderSettings::default()
    }
}

/// Percentage-closer filtering of an ordinary map: a static blocker's edges ramp over one
/// texel, as the bilinear weights of the texel centres say.
#[test]
fn plain_map_filtered_lookup_is_percentage_closer_filtering() {
    let (ramp, _) = check(
        &settings(Method::Plain { time: 0.5 }, ShadowEstimator::Sampled),
        0.0,
        Expect::AtTime,
        "plain, static blocker",
    );
    assert!(ramp > 50, "{ramp} samples on the edges' ramps");
}

/// The temporal map at each sample's time, filtered: the same definition with the blocker
/// where it is at that time.
#[test]
fn temporal_filtered_lookup_at_the_sample_time() {
    let (ramp, _) = check(
        &settings(Method::Temporal, ShadowEstimator::Sampled),
        2.0,
        Expect::AtTime,
        "temporal sampled, moving blocker",
    );
    assert!(ramp > 50, "{ramp} samples on the edges' ramps");
}

/// The analytic estimator, filtered: each texel's exact covered share of the shutter,
/// weighted. The blocker travels 16 texels, so most of the shadow is partial.
#[test]
fn temporal_filtered_lit_fraction_of_the_shutter() {
    let (ramp, checked) = check(
        &settings(Method::Temporal, ShadowEstimator::Analytic),
        2.0,
        Expect::Shutter,
        "temporal analytic, moving blocker",
    );
    assert!(
        ramp * 10 > checked,
        "{ramp} of {checked} samples partly lit"
    );
}
