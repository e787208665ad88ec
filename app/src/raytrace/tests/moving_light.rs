//! The truth under a moving light against closed forms: a still square caster under a spot
//! light translating over the shutter, and under a turning directional light, on the ground
//! plane y = 0. Where the shadow ray of a ground point meets the caster's plane y = h is
//! linear in t (over a ratio of linear terms for the directional light), so its shadowed
//! times are an interval solved by hand here.

use crate::raytrace::bvh::Bvh;
use crate::raytrace::shade::ShadingLight;
use crate::raytrace::shutter::lit_fraction;
use crate::raytrace::triangles::Triangle;
use glam::{DVec3, Vec3};
use motion_shadows::technique::LightView;

/// Closed forms hold to this (the roots are bracketed to 1e-14).
const EXACT: f64 = 1e-9;
/// The square x in [X0, X0 + 1], z in [-0.5, 0.5] at height H_CASTER.
const X0: f32 = 0.25;
const H_CASTER: f32 = 2.0;
/// The spot light starts at (LX0, H_LIGHT, 0) and moves by (DX, 0, 0).
const LX0: f32 = -1.0;
const H_LIGHT: f32 = 4.0;
const DX: f32 = 3.0;

/// The square at height `H_CASTER` moved by `by` over the shutter (two triangles).
fn square(by: Vec3) -> Bvh {
    let c = [(0.0, -0.5), (1.0, -0.5), (1.0, 0.5), (0.0, 0.5)]
        .map(|(x, z)| Vec3::new(X0 + x, H_CASTER, z));
    let tri = |i: [usize; 3], id| Triangle::new(i.map(|i| c[i]), i.map(|i| c[i] + by), id, 0);
    Bvh::new(&[tri([0, 1, 2], 0), tri([0, 2, 3], 1)])
}

fn spot(position: Vec3) -> ShadingLight {
    let view = LightView::spot(position, Vec3::NEG_Y, 80.0, 1.0, 0.1, 20.0, (64, 64));
    ShadingLight::new(&view, 10.0)
}

fn translating_spot() -> ShadingLight {
    let l0 = Vec3::new(LX0, H_LIGHT, 0.0);
    spot(l0).moving_to((l0 + Vec3::X * DX).as_dvec3(), DVec3::NEG_Y)
}

/// The measure of the t in [0, 1] where `a + b t` lies in [lo, hi].
fn measure_inside(a: f64, b: f64, lo: f64, hi: f64) -> f64 {
    let (t_lo, t_hi) = if b == 0.0 {
        if (lo..=hi).contains(&a) {
            (0.0, 1.0)
        } else {
            return 0.0;
        }
    } else {
        let (t1, t2) = ((lo - a) / b, (hi - a) / b);
        (t1.min(t2), t1.max(t2))
    };
    (t_hi.min(1.0) - t_lo.max(0.0)).max(0.0)
}

/// Ground points with the caster's shadow somewhere near: x across it, z inside its width
/// (the shadow ray meets y = h at z (1 - h / H), inside [-0.5, 0.5] for |z| <= 1).
fn ground_points() -> impl Iterator<Item = DVec3> {
    (0..41).map(|i| DVec3::new(-3.0 + 0.2 * f64::from(i), 0.0, 0.3))
}

/// The x where the segment from ground point x (moving by `dp` over the shutter) to the
/// light (at `LX0 + t DX`) crosses the caster's plane, as `a + b t`.
fn crossing(px: f64, dp: f64) -> (f64, f64) {
    let k = f64::from(H_CASTER) / f64::from(H_LIGHT);
    let (lx, dx) = (f64::from(LX0), f64::from(DX));
    (px * (1.0 - k) + k * lx, dp * (1.0 - k) + k * dx)
}

#[test]
fn a_still_caster_under_a_translating_spot_light() {
    let (bvh, light) = (square(Vec3::ZERO), translating_spot());
    let (lo, hi) = (f64::from(X0), f64::from(X0) + 1.0);
    let mut partly = 0;
    for p in ground_points() {
        let (a, b) = crossing(p.x, 0.0);
        let expected = 1.0 - measure_inside(a, b, lo, hi);
        let got = lit_fraction(&bvh, &light, p, p, u32::MAX);
        assert!((got - expected).abs() < EXACT, "{p}: {got} vs {expected}");
        partly += usize::from(expected > 0.01 && expected < 0.99);
        // The per-sample tracer's shadow ray, to the light where it is at t.
        for t in [0.1, 0.35, 0.6, 0.85] {
            let (ray, s_min, s_max) = light.at(t).shadow_ray(p);
            let x = a + b * t;
            // Away from the shadow's edge (the sampled test is not bracketed to 1e-14).
            if (x - lo).abs() > 1e-6 && (x - hi).abs() > 1e-6 {
                let shadowed = (lo..=hi).contains(&x);
                assert_eq!(
                    bvh.occluded(&ray, t, s_min, s_max, u32::MAX),
                    shadowed,
                    "{p} {t}"
                );
            }
        }
    }
    assert!(partly >= 10, "only {partly} points in the blurred part");
}

/// The relative motion: a still caster under a light translating by `dL` is the caster
/// translating by `-dL` under a still light, for a receiver that moves with the light
/// (`P -> P + dL`) in the first and stands still in the second; both against the closed form.
#[test]
fn a_translating_light_is_the_caster_translating_the_other_way() {
    let moving_light = (square(Vec3::ZERO), translating_spot());
    let still_light = (square(Vec3::NEG_X * DX), spot(Vec3::new(LX0, H_LIGHT, 0.0)));
    let (lo, hi) = (f64::from(X0), f64::from(X0) + 1.0);
    let dl = DVec3::X * f64::from(DX);
    let mut partly = 0;
    for p in ground_points() {
        let (a, b) = crossing(p.x, f64::from(DX));
        let expected = 1.0 - measure_inside(a, b, lo, hi);
        let light_moves = lit_fraction(&moving_light.0, &moving_light.1, p, p + dl, u32::MAX);
        let caster_moves = lit_fraction(&still_light.0, &still_light.1, p, p, u32::MAX);
        assert!(
            (light_moves - expected).abs() < EXACT,
            "{p}: {light_moves} vs {expected}"
        );
        assert!(
            (caster_moves - expected).abs() < EXACT,
            "{p}: {caster_moves} vs {expected}"
        );
        partly += usize::from(expected > 0.01 && expected < 0.99);
    }
    assert!(partly >= 5, "only {partly} points in the blurred part");
}

/// A directional light turning from `d0` to `d1`: the shadow ray's direction is the blend
/// `-((1 - t) d0 + t d1)` (up to its length), so the crossing of y = h is a ratio of linear
/// terms and the shadowed times solve linear inequalities.
#[test]
fn a_still_caster_under_a_turning_directional_light() {
    let (d0, d1) = (
        Vec3::new(-0.6, -1.0, 0.0).normalize(),
        Vec3::new(0.5, -1.0, 0.0).normalize(),
    );
    let view = LightView::directional(d0, 1.0, Vec3::ZERO, 5.0, 10.0, 0.1, 20.0, (64, 64));
    let light = ShadingLight::new(&view, 10.0).moving_to(DVec3::ZERO, d1.as_dvec3());
    let bvh = square(Vec3::ZERO);
    // As the light holds them: t = 0 from the view (f32), t = 1 normalised in f64.
    let (u0, u1) = (-d0.as_dvec3(), -d1.as_dvec3().normalize());
    let h = f64::from(H_CASTER);
    let mut partly = 0;
    for p in (0..41).map(|i| DVec3::new(-2.0 + 0.125 * f64::from(i), 0.0, 0.3)) {
        // x(t) = px + h ux(t) / uy(t) in [X0, X0 + 1], uy > 0: with w = lo - px, e = hi - px,
        // w uy(t) <= h ux(t) <= e uy(t), each linear in t: g(t) = g0 + t (g1 - g0).
        let (w, e) = (f64::from(X0) - p.x, f64::from(X0) + 1.0 - p.x);
        let lower = |u: DVec3| h * u.x - w * u.y; // >= 0
        let upper = |u: DVec3| e * u.y - h * u.x; // >= 0
        // Both conditions are linear in t: their common interval by its ends.
        let interval = |g0: f64, g1: f64| -> (f64, f64) {
            let slope = g1 - g0;
            if slope == 0.0 {
                return if g0 >= 0.0 { (0.0, 1.0) } else { (1.0, 0.0) };
            }
            let root = -g0 / slope;
            if slope > 0.0 {
                (root, 1.0)
            } else {
                (0.0, root)
            }
        };
        let (a0, a1) = interval(lower(u0), lower(u1));
        let (b0, b1) = interval(upper(u0), upper(u1));
        let (t0, t1) = (a0.max(b0).max(0.0), a1.min(b1).min(1.0));
        let expected = 1.0 - (t1 - t0).max(0.0);
        let got = lit_fraction(&bvh, &light, p, p, u32::MAX);
        assert!((got - expected).abs() < EXACT, "{p}: {got} vs {expected}");
        partly += usize::from(expected > 0.01 && expected < 0.99);
    }
    assert!(partly >= 5, "only {partly} points in the blurred part");
}

/// A light whose pose at t = 1 is its pose at t = 0 shades and shadows as the still light,
/// to the bit (the moving light's arithmetic leaves a still pose as it is).
#[test]
fn a_light_that_does_not_move_is_the_still_light() {
    let l0 = Vec3::new(LX0, H_LIGHT, 0.0);
    let still = spot(l0);
    let same = still.moving_to(l0.as_dvec3(), DVec3::NEG_Y);
    let bvh = square(Vec3::X);
    for p in ground_points() {
        for t in [0.0, 0.3, 1.0] {
            let (a, b) = (still.at(t), same.at(t));
            assert_eq!(a.shadow_ray(p).0.dir, b.shadow_ray(p).0.dir, "{p} {t}");
        }
        let got = lit_fraction(&bvh, &same, p, p, u32::MAX);
        let expected = lit_fraction(&bvh, &still, p, p, u32::MAX);
        assert_eq!(got.to_bits(), expected.to_bits(), "{p}");
    }
}
