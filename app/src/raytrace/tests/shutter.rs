//! The exact lit fraction of a moving point against closed forms (translating squares under
//! a light straight down or a spot) and against dense sampling of the tracer's own shadow
//! test on random moving triangles; the deferred truth on a scene with a closed form.

use super::point;
use crate::raytrace::bvh::Bvh;
use crate::raytrace::deferred::deferred_truth;
use crate::raytrace::shade::ShadingLight;
use crate::raytrace::shutter::{lit_fraction, shadowed_intervals};
use crate::raytrace::triangles::Triangle;
use crate::scene::rng::SplitMix64;
use crate::scene::{Camera, DirectionalLight, Light, Mesh, Scene, plane_mesh};
use glam::{DVec3, Quat, Vec2, Vec3};
use motion_shadows::technique::LightView;

/// Closed forms hold to this (the roots are bracketed to 1e-14).
const EXACT: f64 = 1e-9;

fn directional(direction: Vec3) -> ShadingLight {
    let view = LightView::directional(direction, 1.0, Vec3::ZERO, 5.0, 10.0, 0.1, 20.0, (64, 64));
    ShadingLight::new(&view, 10.0)
}

fn spot(position: Vec3) -> ShadingLight {
    let view = LightView::spot(position, Vec3::NEG_Y, 80.0, 1.0, 0.1, 20.0, (64, 64));
    ShadingLight::new(&view, 10.0)
}

/// The square x in [x0, x0 + 1], z in [-0.5, 0.5] at height y, moved by `by` over the
/// shutter: two triangles with ids `id` and `id + 1`.
fn square(x0: f32, y: f32, by: Vec3, id: u32) -> [Triangle; 2] {
    let c =
        [(0.0, -0.5), (1.0, -0.5), (1.0, 0.5), (0.0, 0.5)].map(|(x, z)| Vec3::new(x0 + x, y, z));
    let tri = |i: [usize; 3], id| Triangle::new(i.map(|i| c[i]), i.map(|i| c[i] + by), id, 0);
    [tri([0, 1, 2], id), tri([0, 2, 3], id + 1)]
}

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

fn assert_close(got: f64, expected: f64, what: &str) {
    assert!(
        (got - expected).abs() < EXACT,
        "{what}: {got} (expected {expected})"
    );
}

/// The unit square moves 3 to the right, over points on the ground, under a light straight
/// down: it covers a point for a third of the shutter, whenever it crosses it whole.
#[test]
fn a_caster_crossing_a_static_point() {
    let bvh = Bvh::new(&square(-2.0, 1.0, Vec3::new(3.0, 0.0, 0.0), 0));
    let light = directional(Vec3::NEG_Y);
    let lit = |x: f64, z: f64| lit_fraction(&bvh, &light, v(x, 0.0, z), v(x, 0.0, z), u32::MAX);
    // x in [-2 + 3t, -1 + 3t]: t in [(x + 1) / 3, (x + 2) / 3].
    assert_close(lit(0.0, 0.2), 2.0 / 3.0, "crossed whole");
    assert_close(lit(-0.7, -0.3), 2.0 / 3.0, "crossed whole, off centre");
    // Reached halfway through (t from 5/6 to the shutter's close), left early (to 1/6).
    assert_close(lit(1.5, 0.2), 5.0 / 6.0, "reached late");
    assert_close(lit(-1.5, 0.2), 5.0 / 6.0, "left early");
    assert_close(lit(0.0, 0.7), 1.0, "beside its path");
    let got = shadowed_intervals(&bvh, &light, v(0.0, 0.0, 0.2), v(0.0, 0.0, 0.2), u32::MAX);
    assert_eq!(got.len(), 1, "{got:?}");
    assert_close(got[0].0, 1.0 / 3.0, "shadow starts");
    assert_close(got[0].1, 2.0 / 3.0, "shadow ends");
    // Above the caster, or lit from below it, nothing is in the way.
    assert_close(lit(0.0, 0.2) + 1.0 / 3.0, 1.0, "sum");
    let up = directional(Vec3::Y);
    assert_close(
        lit_fraction(&bvh, &up, v(0.0, 0.0, 0.2), v(0.0, 0.0, 0.2), u32::MAX),
        1.0,
        "light from below",
    );
}

/// A finely tessellated plane sliding over a point covers it all shutter: one triangle after
/// another, whose intervals meet at roots of different polynomials of their shared edges.
/// The point is exactly unlit, with no slivers of light between them.
#[test]
fn a_tessellated_caster_leaves_no_gaps() {
    let plane = plane_mesh(Vec2::new(6.0, 6.0), 12);
    let by = Vec3::new(1.3, 0.0, 0.7);
    let tris: Vec<Triangle> = plane
        .chunks_exact(3)
        .enumerate()
        .map(|(i, c)| {
            let p0 = [c[0], c[1], c[2]].map(|p| p + Vec3::new(0.05, 1.0, -0.03));
            Triangle::new(p0, p0.map(|p| p + by), i as u32, 0)
        })
        .collect();
    let bvh = Bvh::new(&tris);
    for (light, what) in [
        (directional(Vec3::new(0.1, -1.0, 0.2)), "directional"),
        (spot(Vec3::new(0.3, 3.0, -0.2)), "spot"),
    ] {
        for p in [v(0.0, 0.0, 0.0), v(0.37, 0.0, -0.61)] {
            let got = shadowed_intervals(&bvh, &light, p, p, u32::MAX);
            assert_eq!(got, [(0.0, 1.0)], "{what} at {p}");
            assert_eq!(lit_fraction(&bvh, &light, p, p, u32::MAX), 0.0);
        }
    }
}

/// The same closed forms with the roles swapped: the point moves, the square stands.
#[test]
fn a_point_crossing_a_static_caster() {
    let bvh = Bvh::new(&square(-0.5, 1.0, Vec3::ZERO, 0));
    let light = directional(Vec3::NEG_Y);
    let lit = |x0: f64, x1: f64| lit_fraction(&bvh, &light, v(x0, 0.0, 0.2), v(x1, 0.0, 0.2), 7);
    // x = -2 + 3t in [-0.5, 0.5]: t in [1/2, 5/6].
    assert_close(lit(-2.0, 1.0), 2.0 / 3.0, "crosses whole");
    assert_close(lit(0.0, 3.0), 5.0 / 6.0, "leaves at 1/6");
    assert_close(lit(-3.0, 0.0), 5.0 / 6.0, "enters at 5/6");
    assert_close(lit(-0.2, 0.3), 0.0, "under it all shutter");
    // Moving with the caster: always under it, or never.
    let both = Bvh::new(&square(-0.5, 1.0, Vec3::new(3.0, 0.0, 0.0), 0));
    let with = |x: f64| lit_fraction(&both, &light, v(x, 0.0, 0.2), v(x + 3.0, 0.0, 0.2), 7);
    assert_close(with(0.0), 0.0, "carried under it");
    assert_close(with(0.6), 1.0, "carried beside it");
}

/// A spot light at (0, 2, 0) and a square half way down: the ray from (x, 0, 0.2) crosses
/// y = 1 at x / 2, so the square hides |x| <= 1, twice what a light straight down hides.
#[test]
fn a_spot_light_s_shadow_is_in_perspective() {
    let bvh = Bvh::new(&square(-0.5, 1.0, Vec3::ZERO, 0));
    let light = spot(Vec3::new(0.0, 2.0, 0.0));
    let p = |x: f64| v(x, 0.0, 0.2);
    // x = -3 + 6t, |x| <= 1: t in [1/3, 2/3].
    assert_close(
        lit_fraction(&bvh, &light, p(-3.0), p(3.0), 9),
        2.0 / 3.0,
        "spot",
    );
    // Straight down it hides |x| <= 0.5: t in [5/12, 7/12].
    let down = directional(Vec3::NEG_Y);
    assert_close(
        lit_fraction(&bvh, &down, p(-3.0), p(3.0), 9),
        5.0 / 6.0,
        "down",
    );
    // The caster moving, the point still: the square's image (x0 + 3t .. x0 + 1 + 3t at
    // y = 1) holds the crossing x = 0.5 for t in [1/2, 5/6] when x0 = -2.
    let moving = Bvh::new(&square(-2.0, 1.0, Vec3::new(3.0, 0.0, 0.0), 0));
    assert_close(
        lit_fraction(&moving, &light, p(1.0), p(1.0), 9),
        2.0 / 3.0,
        "caster moves",
    );
    // Both moving, the square fast and near the light: the point goes from x = -4 to 0, its
    // ray crosses y = 1.8 at x = 0.1 (-4 + 4t); the square's x0 = -10.5 + 10t holds it for
    // t >= 91/96. (Neither the square's start nor its end shifted back by the point's
    // motion meets the ray from P0: only its end does, where the ray nears the light.)
    let fast = Bvh::new(&square(-10.5, 1.8, Vec3::new(10.0, 0.0, 0.0), 0));
    let got = lit_fraction(&fast, &light, p(-4.0), p(0.0), 9);
    assert_close(got, 91.0 / 96.0, "both move");
    // A square beyond the light is not between it and the point.
    let beyond = Bvh::new(&square(-0.5, 3.0, Vec3::ZERO, 0));
    assert_close(
        lit_fraction(&beyond, &light, p(-3.0), p(3.0), 9),
        1.0,
        "beyond",
    );
}

/// A random triangle around `c`, with one of four motions: none, a translation, each corner
/// on its own path, or the chords of a rotation about a random axis through `c` (vertices
/// move linearly from a rotated copy's start to its end, as a skinned limb's do).
fn random_triangle(rng: &mut SplitMix64, c: DVec3, size: f32, id: u32) -> Triangle {
    let p0 = [0; 3].map(|_| (c + point(rng, size)).as_vec3());
    let p1 = match rng.next_u64() % 4 {
        0 => p0,
        1 => {
            let by = point(rng, 1.5).as_vec3();
            p0.map(|p| p + by)
        }
        2 => p0.map(|p| p + point(rng, 1.0).as_vec3()),
        _ => {
            let q = Quat::from_axis_angle(rng.unit_vector(), rng.range(-2.5, 2.5));
            let pivot = (c + point(rng, 0.5)).as_vec3();
            p0.map(|p| pivot + q * (p - pivot))
        }
    };
    Triangle::new(p0, p1, id, 0)
}

/// On random scenes (a moving receiver triangle and a few casters around its shadow ray,
/// both kinds of light), the exact intervals agree with the tracer's own test at 20000
/// stratified times, but within 1e-9 of an interval's end, and their measure with the
/// sampled one within half a stratum per transition.
#[test]
fn matches_dense_sampling_of_the_tracer() {
    const N: usize = 20_000;
    let mut rng = SplitMix64::new(11);
    let (mut partial, mut transitions_seen) = (0, 0);
    let cases = 120;
    for case in 0..cases {
        let spot_light = case % 2 == 1;
        let toward = {
            let d = rng.unit_vector().as_dvec3();
            v(d.x, d.y.abs() + 0.3, d.z).normalize()
        };
        let light = if spot_light {
            spot((toward * f64::from(rng.range(2.5, 4.0))).as_vec3())
        } else {
            directional(-toward.as_vec3())
        };
        // The receiver: a moving triangle, the point at random barycentrics on it.
        let receiver = random_triangle(&mut rng, DVec3::ZERO, 0.6, 0);
        let w = [rng.next_f32(), rng.next_f32(), rng.next_f32()].map(|x| f64::from(x) + 0.05);
        let at = |time: f64| {
            let c = receiver.at(time);
            (w[0] * c[0] + w[1] * c[1] + w[2] * c[2]) / (w[0] + w[1] + w[2])
        };
        let (p0, p1) = (at(0.0), at(1.0));
        let mut tris = vec![receiver];
        for id in 1..=5 {
            let along = toward * f64::from(rng.range(0.6, 2.0));
            tris.push(random_triangle(&mut rng, along, 0.8, id));
        }
        let bvh = Bvh::new(&tris);
        let intervals = shadowed_intervals(&bvh, &light, p0, p1, 0);
        let lit = lit_fraction(&bvh, &light, p0, p1, 0);
        let near_end = |t: f64| {
            intervals
                .iter()
                .any(|&(a, b)| (t - a).abs() < EXACT || (t - b).abs() < EXACT)
        };
        let mut lit_samples = 0usize;
        for k in 0..N {
            let t = (k as f64 + 0.5) / N as f64;
            let (ray, s_min, s_max) = light.shadow_ray(p0 + t * (p1 - p0));
            let traced = bvh.occluded(&ray, t, s_min, s_max, 0);
            let exact = intervals.iter().any(|&(a, b)| a < t && t < b);
            assert!(
                traced == exact || near_end(t),
                "case {case}: at t = {t} the tracer says shadowed = {traced}, the intervals \
                 {intervals:?} say {exact}"
            );
            lit_samples += usize::from(!traced);
        }
        let transitions = intervals
            .iter()
            .flat_map(|&(a, b)| [a, b])
            .filter(|&t| t > 0.0 && t < 1.0)
            .count();
        let sampled = lit_samples as f64 / N as f64;
        assert!(
            (lit - sampled).abs() <= transitions as f64 * 0.5 / N as f64 + EXACT,
            "case {case}: exact {lit}, sampled {sampled}, {transitions} transitions"
        );
        partial += usize::from(lit > 0.0 && lit < 1.0);
        transitions_seen += transitions;
    }
    eprintln!("{partial} of {cases} points partly lit, {transitions_seen} transitions");
    assert!(partial > cases / 3, "only {partial} partly lit points");
}

/// A unit square crossing a ground plane by 3 under a light straight down and under a
/// static roof, seen from above at the shutter's close: every G-buffer point (on the ground,
/// on the moving square, on the roof) is lit as the closed form says, and the radiance
/// follows.
#[test]
fn deferred_truth_of_a_crossing_square() {
    let quad = |x0: f32, y: f32| {
        let c = [(0.0, -0.5), (1.0, -0.5), (1.0, 0.5), (0.0, 0.5)]
            .map(|(x, z)| Vec3::new(x0 + x, y, z));
        [0, 1, 2, 0, 2, 3].map(|i| c[i]).to_vec()
    };
    let mesh = |name: &str, albedo: f32, t0: Vec<Vec3>, t1: Vec<Vec3>| Mesh {
        name: name.into(),
        albedo: Vec3::splat(albedo),
        closed: false,
        t0,
        t1,
    };
    let ground = plane_mesh(Vec2::new(8.0, 8.0), 2);
    let scene = Scene {
        name: "crossing".into(),
        camera: Camera {
            position: Vec3::new(0.0, 6.0, 4.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y_deg: 60.0,
            near: 0.1,
            far: 100.0,
            t1: None,
        },
        light: Light::Directional(DirectionalLight {
            direction: Vec3::NEG_Y,
            irradiance: 2.0,
            center: Vec3::ZERO,
            half_extent: 5.0,
            distance: 10.0,
            near: 0.1,
            far: 20.0,
            t1: None,
        }),
        ambient: 0.1,
        meshes: vec![
            mesh("ground", 0.5, ground.clone(), ground),
            mesh("square", 0.8, quad(-2.0, 1.0), quad(1.0, 1.0)),
            mesh("roof", 0.3, quad(0.5, 2.0), quad(0.5, 2.0)),
        ],
    };
    let mut steps = 0;
    let truth = deferred_truth(&scene, 64, 48, 1.0, (64, 64), &mut |_| steps += 1).unwrap();
    assert!(steps > 4, "{steps} progress reports");
    // Shares of the shutter during which the square (x0 = -2 + 3t) and the roof (x in
    // [0.5, 1.5]) are over a ground point at x; both span z in [-0.5, 0.5].
    let square_over = |x: f64| (((x + 2.0) / 3.0).min(1.0) - ((x + 1.0) / 3.0).max(0.0)).max(0.0);
    let roof_over = |x: f64| (0.5..=1.5).contains(&x);
    let (mut whole, mut ground_partly, mut on_square, mut on_roof) = (0, 0, 0, 0);
    for i in 0..truth.lit.len() {
        let lit = f64::from(truth.lit[i]);
        if !truth.hit[i] {
            assert_eq!(lit, 1.0);
            continue;
        }
        let [x, y, z] = truth.position[i].map(f64::from);
        let rgb = f64::from(truth.rgb[3 * i]);
        let albedo = f64::from(truth.albedo[i][0]);
        assert_eq!(truth.normal[i], [0.0, 1.0, 0.0], "pixel {i}");
        // Lambert straight down (cos = 1) weighted by the lit share, plus ambient.
        let expected_rgb = albedo / std::f64::consts::PI * 2.0 * lit + 0.1 * albedo;
        assert!(
            (rgb - expected_rgb).abs() < 1e-6,
            "pixel {i}: {rgb} {expected_rgb}"
        );
        // Near a shadow's edge the stored f32 position is too coarse to place the point.
        let edge = |e: f64, at: f64| (e - at).abs() < 1e-3;
        if edge(z.abs(), 0.5) || [-1.0, 0.5, 1.5].iter().any(|&e| edge(x, e)) {
            continue;
        }
        let under = z.abs() < 0.5;
        // Elsewhere the f32 position moves the closed forms by ~1e-7.
        let expected = if edge(y, 2.0) {
            on_roof += 1;
            1.0
        } else if edge(y, 1.0) {
            // On the square, which was at x - 3 + 3t: under the roof for t in
            // [(3.5 - x) / 3, (4.5 - x) / 3].
            on_square += 1;
            1.0 - (((4.5 - x) / 3.0).min(1.0) - ((3.5 - x) / 3.0).max(0.0))
        } else {
            assert!(y.abs() < 1e-5, "pixel {i} at {x} {y} {z}");
            if under && (-0.99..=0.99).contains(&x) && !roof_over(x) {
                // Crossed whole: 2/3 whatever x, up to the f32 rounding of the value.
                assert!(
                    (lit - 2.0 / 3.0).abs() < 1e-7,
                    "pixel {i} at x = {x}: {lit}"
                );
                whole += 1;
            }
            match (under, roof_over(x)) {
                (false, _) => 1.0,
                (true, true) => 0.0,
                (true, false) => 1.0 - square_over(x),
            }
        };
        assert!(
            (lit - expected).abs() < 1e-5,
            "pixel {i} at {x} {y} {z}: {lit}"
        );
        ground_partly += usize::from(y.abs() < 1e-5 && lit > 0.0 && lit < 1.0);
    }
    eprintln!(
        "ground: {whole} crossed whole, {ground_partly} partly lit; {on_square} on the \
         square, {on_roof} on the roof"
    );
    assert!(whole >= 20 && ground_partly > whole && on_square >= 10 && on_roof >= 10);
}

/// Points per second of the deferred truth on a real scene. A measurement, not a check:
/// `cargo test --release -p motion-shadows-app --lib deferred_truth_speed -- --ignored
/// --nocapture`.
#[test]
#[ignore = "a measurement; prints points per second"]
fn deferred_truth_speed() {
    use crate::scene::{BuiltinOptions, builtin};
    for name in ["game-level", "cubes-toward-light"] {
        let scene = builtin(name, &BuiltinOptions::default()).unwrap();
        let (w, h) = (480, 270);
        let start = std::time::Instant::now();
        let truth = deferred_truth(&scene, w, h, 1.0, (1024, 1024), &mut |_| {}).unwrap();
        let secs = start.elapsed().as_secs_f64();
        let hits = truth.hit.iter().filter(|&&h| h).count();
        let partly = truth.lit.iter().filter(|&&l| l > 0.0 && l < 1.0).count();
        eprintln!(
            "{name}: {} triangles, {w}x{h} in {secs:.2} s: {:.0} points/s ({hits} hits, \
             {partly} partly lit, {} threads)",
            scene.triangle_count(),
            f64::from(w * h) / secs,
            rayon::current_num_threads()
        );
    }
}
