//! Depth-time ranges against closed-form expectations.

use crate::support::gpu::{assert_no_validation_messages, context};
use crate::support::prism_model::{edge_margin_at_pixel, prism_triangles};
use crate::support::scene::{
    light_setup, light_view, mesh, overhead_directional, scene, square, temporal_map, translated,
};
use glam::{Vec3, Vec4};
use motion_shadows::technique::Range;

const SIZE: (u32, u32) = (64, 64);

/// World x and z of the centre of shadow-map pixel (x, y), by inverting the light's matrices.
fn pixel_centre_world(scene: &crate::support::scene::Scene, x: u32, y: u32) -> Vec3 {
    let light = light_view(scene, SIZE);
    let ndc = glam::Vec2::new(
        (x as f32 + 0.5) / SIZE.0 as f32 * 2.0 - 1.0,
        (y as f32 + 0.5) / SIZE.1 as f32 * 2.0 - 1.0,
    );
    let world = (light.proj * light.view).inverse() * Vec4::new(ndc.x, ndc.y, 0.5, 1.0);
    world.truncate() / world.w
}

/// Merges time intervals that touch (within `eps`) into disjoint ones.
fn union(mut intervals: Vec<(f32, f32)>, eps: f32) -> Vec<(f32, f32)> {
    intervals.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out: Vec<(f32, f32)> = Vec::new();
    for (s, e) in intervals {
        match out.last_mut() {
            Some(last) if s <= last.1 + eps => last.1 = last.1.max(e),
            _ => out.push((s, e)),
        }
    }
    out
}

/// A square translating parallel to the light's image plane: at every pixel of a row through
/// it, the ranges' union is the analytic interval during which the square covers the pixel
/// centre, at the square's constant depth.
///
/// Tolerance on times: 2e-3. The side surfaces of this prism are planes, so the prism is
/// exact; what remains is rasterization snapping vertices to 1/256 pixel, which shifts an
/// edge by 1/256 px, i.e. 1/256 / 32 = 1.2e-4 in time at 32 px of motion, plus f32 rounding.
#[test]
fn translating_square_ranges_match_analytic_times_and_depths() {
    let ctx = context();
    // The box is 16 units wide over 64 pixels: 0.25 units per pixel. The square (side 2) moves
    // 8 units = 32 pixels in +x over the shutter, at height 1 under a light 10 units up.
    let (x0, z0, side, height, travel) = (-5.0f32, -1.0f32, 2.0f32, 1.0f32, 8.0f32);
    let t0 = square(x0, z0, side, height);
    let t1 = translated(&t0, Vec3::X * travel);
    let s = scene(
        "translating-square",
        overhead_directional(8.0),
        vec![mesh("square", t0, t1, false)],
    );
    let map = temporal_map(&ctx, &s, SIZE);
    let expected_depth = 10.0 - height;

    let mut checked = 0;
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let centre = pixel_centre_world(&s, x, y);
            let inside_z = centre.z > z0 + 0.01 && centre.z < z0 + side - 0.01;
            let ranges = map.ranges_at(x, y);
            if !inside_z {
                if (centre.z - z0).abs() > 0.01 && (centre.z - z0 - side).abs() > 0.01 {
                    assert!(ranges.is_empty(), "pixel ({x},{y}) off the path has ranges");
                }
                continue;
            }
            // The square covers x in [x0 + travel t, x0 + side + travel t].
            let enter = ((centre.x - x0 - side) / travel).clamp(0.0, 1.0);
            let leave = ((centre.x - x0) / travel).clamp(0.0, 1.0);
            if leave - enter < 1e-3 {
                continue; // never or only touched: no interval to compare
            }
            for r in &ranges {
                assert!((r.d_s - expected_depth).abs() < 1e-4, "({x},{y}) {r:?}");
                assert!((r.d_e - expected_depth).abs() < 1e-4, "({x},{y}) {r:?}");
            }
            let got = union(ranges.iter().map(|r| (r.t_s, r.t_e)).collect(), 1e-4);
            assert_eq!(got.len(), 1, "pixel ({x},{y}): {ranges:?}");
            assert!(
                (got[0].0 - enter).abs() < 2e-3 && (got[0].1 - leave).abs() < 2e-3,
                "pixel ({x},{y}): ranges {got:?}, analytic [{enter}, {leave}]"
            );
            checked += 1;
        }
    }
    assert!(checked > 150, "only {checked} pixels checked");
    assert_no_validation_messages(&ctx);
}

/// A static triangle is in the static layer, at its constant depth, at each pixel whose
/// centre it covers and nowhere else; it leaves no range (a static triangle's range would be
/// [0, 1] at that depth: the layer says the same in 8 bytes).
#[test]
fn static_triangle_fills_the_static_layer_at_covered_pixels() {
    let ctx = context();
    let tri = vec![
        Vec3::new(-4.0, 2.0, -3.0),
        Vec3::new(-1.0, 2.0, 4.0),
        Vec3::new(5.0, 2.0, -1.0),
    ];
    let s = scene(
        "static-triangle",
        overhead_directional(8.0),
        vec![mesh("triangle", tri.clone(), tri.clone(), false)],
    );
    let map = temporal_map(&ctx, &s, SIZE);
    let setup = light_setup(&s, SIZE);
    let p = [tri[0], tri[1], tri[2]];
    // The cap alone says which pixel centres are covered (the sides have no area).
    let caps = &prism_triangles(&setup, p, p, false)[..1];
    let mut covered = 0;
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let ranges: Vec<Range> = map.ranges_at(x, y);
            assert!(ranges.is_empty(), "pixel ({x},{y}): {ranges:?}");
            if edge_margin_at_pixel(caps, &setup, x, y) < 0.01 {
                continue;
            }
            let inside =
                !crate::support::prism_model::fragments_at_pixel(caps, &setup, x, y).is_empty();
            match map.static_at(x, y) {
                Some((id, depth)) => {
                    assert!(inside, "pixel ({x},{y}) outside holds triangle {id}");
                    assert_eq!(id, 0, "pixel ({x},{y})");
                    assert!((depth - 8.0).abs() < 1e-4, "pixel ({x},{y}): depth {depth}");
                    covered += 1;
                }
                None => assert!(!inside, "pixel ({x},{y}) covered but empty"),
            }
        }
    }
    assert!(covered > 300, "only {covered} covered pixels");
    assert_no_validation_messages(&ctx);
}

/// How far from `c` the boundary of the convex polygon `poly` (which contains `c`) lies along
/// the unit direction `u`, in the xz plane.
fn boundary_distance(poly: &[glam::Vec2], c: glam::Vec2, u: glam::Vec2) -> f32 {
    let mut nearest = f32::INFINITY;
    for (i, &a) in poly.iter().enumerate() {
        let b = poly[(i + 1) % poly.len()];
        let normal = (b - a).perp();
        let outward = if normal.dot(c - a) > 0.0 {
            -normal
        } else {
            normal
        };
        let speed = outward.dot(u);
        if speed > 0.0 {
            nearest = nearest.min(outward.dot(a - c) / speed);
        }
    }
    nearest
}

/// A flat triangle whose vertices move straight through an interior point `c` (a half turn by
/// linear motion): at time t it is `c + (1 - 2t)(T0 - c)`, a point at t = 0.5. A pixel centre p
/// near c is covered while `|1 - 2t| >= |p - c| / rho` (rho: the distance from c to T0's
/// boundary in p's direction, or the opposite one once the triangle has turned over), so its
/// ranges must be [0, (1 - k+)/2] and [(1 + k-)/2, 1]. Every fragment has the same depth
/// (the triangle moves in its own plane), so only time order pairs them into these intervals.
#[test]
fn triangle_moving_in_its_plane_gives_the_analytic_intervals() {
    use glam::Vec2;
    let ctx = context();
    let c = Vec3::new(0.5, 2.0, 0.3);
    let offsets = [
        Vec3::new(-2.0, 0.0, -1.5),
        Vec3::new(-0.5, 0.0, 2.5),
        Vec3::new(2.5, 0.0, -1.0),
    ];
    let t0: Vec<Vec3> = offsets.iter().map(|o| c + *o).collect();
    let t1: Vec<Vec3> = offsets.iter().map(|o| c - *o).collect();
    let s = scene(
        "half-turn",
        overhead_directional(8.0),
        vec![mesh("turning", t0.clone(), t1.clone(), false)],
    );
    let map = temporal_map(&ctx, &s, SIZE);
    let setup = light_setup(&s, SIZE);
    let prism = prism_triangles(&setup, [t0[0], t0[1], t0[2]], [t1[0], t1[1], t1[2]], false);
    let polygon: Vec<Vec2> = t0.iter().map(|p| Vec2::new(p.x, p.z)).collect();
    let c2 = Vec2::new(c.x, c.z);

    let (mut checked, mut with_gap) = (0, 0);
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            if edge_margin_at_pixel(&prism, &setup, x, y) < 0.02 {
                continue;
            }
            let centre = pixel_centre_world(&s, x, y);
            let d = Vec2::new(centre.x, centre.z) - c2;
            let (u, r) = (d.normalize_or_zero(), d.length());
            let mut expected = Vec::new();
            let k_plus = r / boundary_distance(&polygon, c2, u);
            if k_plus < 1.0 {
                expected.push((0.0, (1.0 - k_plus) / 2.0));
            }
            let k_minus = r / boundary_distance(&polygon, c2, -u);
            if k_minus < 1.0 {
                expected.push(((1.0 + k_minus) / 2.0, 1.0));
            }
            // Too short to tell apart from a touch, or two intervals that nearly merge.
            let short = expected.iter().any(|(s, e)| e - s < 5e-3);
            let merging = expected.len() == 2 && expected[1].0 - expected[0].1 < 5e-3;
            if short || merging {
                continue;
            }
            let ranges = map.ranges_at(x, y);
            let got = union(ranges.iter().map(|r| (r.t_s, r.t_e)).collect(), 1e-4);
            assert_eq!(
                got.len(),
                expected.len(),
                "pixel ({x},{y}): ranges {ranges:?}, analytic {expected:?}"
            );
            for (g, e) in got.iter().zip(&expected) {
                assert!(
                    (g.0 - e.0).abs() < 2e-3 && (g.1 - e.1).abs() < 2e-3,
                    "pixel ({x},{y}): ranges {got:?}, analytic {expected:?}"
                );
            }
            checked += 1;
            with_gap += usize::from(expected.len() == 2);
        }
    }
    eprintln!("half turn: {checked} pixels checked, {with_gap} uncovered mid-frame");
    assert!(with_gap > 30, "only {with_gap} pixels uncovered mid-frame");
    assert_no_validation_messages(&ctx);
}
