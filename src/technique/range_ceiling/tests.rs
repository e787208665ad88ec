//! The whole bound against runs counted by brute force, sampled across the shutter.

use super::*;

/// Triangles of a spot light's map moving across the light's plane (corners in front
/// and behind, the light itself outside them): runs counted by brute force (a centre is
/// covered at t iff its ray is a positive combination of the corners, solved as a 3x3
/// system, 2,000 times across the shutter) never exceed the bound, which for most of them
/// is well below every centre of the map (the old bound for any such triangle).
#[test]
fn the_bound_holds_for_triangles_crossing_the_light() {
    let n = 20u32;
    let setup = Setup {
        to_view: DMat4::IDENTITY,
        proj: glam::camera::rh::proj::vulkan::perspective(1.2, 1.0, 0.1, 50.0).as_dmat4(),
        orthographic: false,
        map: Map {
            width: f64::from(n),
            height: f64::from(n),
        },
    };
    let whole = EXACT_MAX_RUNS * u64::from(n * n);
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let (mut crossing, mut below) = (0, 0);
    for _ in 0..200 {
        // Looking down -z: in front at z < 0. Corners from z = -3 to +1, offset sideways.
        let side = Vec3::new(next() as f32, next() as f32, 0.0) * 1.5;
        let mut corner =
            || side + Vec3::new(next() as f32, next() as f32, (2.0 * next() - 1.0) as f32);
        let t0: [Vec3; 3] = [corner(), corner(), corner()];
        let t1: [Vec3; 3] = [corner(), corner(), corner()];
        let clip = |p: Vec3| -> DVec3 {
            let c = setup.proj * p.as_dvec3().extend(1.0);
            DVec3::new(c.x, c.y, c.w)
        };
        let ws = t0.iter().chain(&t1).map(|&p| clip(p).z);
        if ws.clone().all(|w| w > 0.0) || ws.clone().all(|w| w < 0.0) {
            continue;
        }
        crossing += 1;
        let bound = setup.triangle_ranges_at_most(&t0, &t1, false);
        let mut runs = 0u64;
        for y in 0..n {
            for x in 0..n {
                let ray = DVec3::new(
                    (f64::from(x) + 0.5) / f64::from(n) * 2.0 - 1.0,
                    (f64::from(y) + 0.5) / f64::from(n) * 2.0 - 1.0,
                    1.0,
                );
                let mut was = false;
                for step in 0..=2000 {
                    let t = f64::from(step) / 2000.0;
                    let c = [0, 1, 2].map(|k| clip(t0[k]).lerp(clip(t1[k]), t));
                    let m = glam::DMat3::from_cols(c[0], c[1], c[2]);
                    let now = m.determinant() != 0.0 && (m.inverse() * ray).min_element() > 0.0;
                    runs += u64::from(now && !was);
                    was = now;
                }
            }
        }
        assert!(
            runs <= bound,
            "{t0:?} -> {t1:?}: {runs} runs, bound {bound}"
        );
        below += u64::from(bound < whole / 2);
    }
    eprintln!("{below} of {crossing} crossing triangles bounded below half the map's cap");
    assert!(crossing >= 40, "only {crossing} crossing cases");
    assert!(
        below * 2 >= crossing,
        "only {below} of {crossing} bounded below half the map's cap"
    );
}

/// Runs per centre counted by brute force (f64, 4,000 times across the shutter) for
/// random moving triangles under an orthographic light: never more than the bound, which
/// takes none of its reasoning from sampling.
#[test]
fn the_bound_holds_against_sampled_runs() {
    let map = Map {
        width: 24.0,
        height: 24.0,
    };
    let setup = Setup {
        to_view: DMat4::IDENTITY,
        proj: DMat4::IDENTITY,
        orthographic: true,
        map,
    };
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let mut tight = 0;
    for case in 0..60 {
        let t0: [Vec3; 3] = [(); 3].map(|_| Vec3::new(next() as f32, next() as f32, 0.5));
        // Even cases deform at random, odd ones translate.
        let shift = Vec3::new(next() as f32, next() as f32, 0.0);
        let t1: [Vec3; 3] = [0, 1, 2].map(|k| {
            let random = Vec3::new(next() as f32, next() as f32, 0.5);
            if case % 2 == 0 { random } else { t0[k] + shift }
        });
        let bound = setup.triangle_ranges_at_most(&t0, &t1, false);
        let mut runs = 0u64;
        for y in 0..24 {
            for x in 0..24 {
                let r = DVec2::new((x as f64 + 0.5) / 12.0 - 1.0, (y as f64 + 0.5) / 12.0 - 1.0);
                let mut was = false;
                for step in 0..=4000 {
                    let t = step as f64 / 4000.0;
                    let p: [DVec2; 3] =
                        [0, 1, 2].map(|k| t0[k].as_dvec3().lerp(t1[k].as_dvec3(), t).truncate());
                    let e = [0, 1, 2].map(|k| (p[(k + 1) % 3] - r).perp_dot(p[(k + 2) % 3] - r));
                    let now = (e.iter().all(|&v| v > 0.0)) || e.iter().all(|&v| v < 0.0);
                    runs += u64::from(now && !was);
                    was = now;
                }
            }
        }
        assert!(
            runs <= bound,
            "{t0:?} -> {t1:?}: {runs} runs, bound {bound}"
        );
        if case % 2 == 1 {
            tight += u64::from(runs * 4 > bound * 3);
        }
    }
    // A translation's footprint is its swept area and its runs one per centre: within
    // 4/3 but for the hull's growth on small ones (a loose bound would pass trivially).
    assert!(tight >= 25, "only {tight} of 30 translations within 4/3");
}
