//! The model against closed forms: static and translating triangles, the crossing case,
//! culling, the far plane, and even fragment counts under random perspective motions.

use super::*;
use glam::camera::rh::{proj::vulkan, view::look_at_mat4};
use glam::{Mat4, Vec2, Vec3};

const SIZE: u32 = 64;
const MARGIN: f32 = 0.01;

/// Orthographic light down -Z with world x/y equal to framebuffer pixels, so that
/// expectations can be written directly in pixels. Bottom/top are swapped to undo
/// the Vulkan projection's y flip.
fn ortho_pixels() -> LightSetup {
    LightSetup {
        view: Mat4::IDENTITY,
        proj: vulkan::orthographic(0.0, SIZE as f32, SIZE as f32, 0.0, 0.1, 100.0),
        orthographic: true,
        width: SIZE,
        height: SIZE,
    }
}

fn perspective(eye: Vec3) -> LightSetup {
    LightSetup {
        view: look_at_mat4(eye, Vec3::ZERO, Vec3::Y),
        proj: vulkan::perspective(60f32.to_radians(), 1.0, 0.1, 100.0),
        orthographic: false,
        width: SIZE,
        height: SIZE,
    }
}

fn px(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(x, y, z)
}

fn sorted_times(frags: &[CpuFragment]) -> Vec<f32> {
    let mut t: Vec<f32> = frags.iter().map(|f| f.time).collect();
    t.sort_by(f32::total_cmp);
    t
}

/// Pixel containing the light-space projection of world point `p`.
fn pixel_of(light: &LightSetup, p: Vec3) -> (u32, u32) {
    let c = light.proj * light.view * p.extend(1.0);
    let ndc = c.truncate() / c.w;
    (
        ((ndc.x * 0.5 + 0.5) * light.width as f32) as u32,
        ((ndc.y * 0.5 + 0.5) * light.height as f32) as u32,
    )
}

#[test]
fn static_triangle_gives_one_fragment_per_cap_at_the_ray_plane_depth() {
    let light = perspective(Vec3::new(3.0, 4.0, 10.0));
    let tri = [px(-2.0, -1.5, 0.5), px(2.5, -1.0, -1.0), px(0.0, 2.5, 0.3)];
    let tris = prism_triangles(&light, tri, tri, false);
    // Caps + three four-triangle side surfaces (static edges never cross).
    assert_eq!(tris.len(), 14);
    assert_eq!(edge_cases(&light, tri, tri), [EdgeCase::Centre; 3]);

    let centroid = (tri[0] + tri[1] + tri[2]) / 3.0;
    let (x, y) = pixel_of(&light, centroid);
    assert!(edge_margin_at_pixel(&tris, &light, x, y) > MARGIN);
    let frags = fragments_at_pixel(&tris, &light, x, y);
    assert_eq!(frags.len(), 2, "{frags:?}");
    assert_eq!(sorted_times(&frags), vec![0.0, 1.0]);

    // Expected depth from a ray cast through the pixel centre in view space.
    let inv_proj = light.proj.inverse();
    let ndc = Vec2::new(
        (x as f32 + 0.5) / SIZE as f32 * 2.0 - 1.0,
        (y as f32 + 0.5) / SIZE as f32 * 2.0 - 1.0,
    );
    let dir = inv_proj.project_point3(ndc.extend(0.5));
    let v = tri.map(|p| light.view.transform_point3(p));
    let n = (v[1] - v[0]).cross(v[2] - v[0]);
    let hit = dir * (n.dot(v[0]) / n.dot(dir));
    let expected = -hit.z;
    for f in &frags {
        assert!(
            (f.depth - expected).abs() < 1e-3 * expected,
            "{f:?} vs {expected}"
        );
    }
}

/// Right triangle with a vertical left edge at x = 10.3 and a hypotenuse from
/// (30.7, 10.2) to (10.3, 40.6), translating by K pixels in +x.
const K: f32 = 8.0;
fn translating() -> ([Vec3; 3], [Vec3; 3]) {
    let p0 = [
        px(10.3, 10.2, -10.0),
        px(30.7, 10.2, -10.0),
        px(10.3, 40.6, -10.0),
    ];
    let p1 = p0.map(|p| p + Vec3::X * K);
    (p0, p1)
}
fn hypotenuse_x(y: f32) -> f32 {
    30.7 - 20.4 * (y - 10.2) / 30.4
}

#[test]
fn translating_triangle_enters_and_leaves_pixels_at_the_analytic_times() {
    let light = ortho_pixels();
    let (p0, p1) = translating();
    let tris = prism_triangles(&light, p0, p1, true);
    assert!(tris.len() <= 14);

    // Entered by the hypotenuse, covered at t = 1.
    let (x, y) = (33, 12);
    assert!(edge_margin_at_pixel(&tris, &light, x, y) > MARGIN);
    let frags = fragments_at_pixel(&tris, &light, x, y);
    let enter = (x as f32 + 0.5 - hypotenuse_x(y as f32 + 0.5)) / K;
    assert!(enter > 0.0 && enter < 1.0);
    let times = sorted_times(&frags);
    assert_eq!(times.len(), 2, "{frags:?}");
    assert!((times[0] - enter).abs() < 1e-3, "{times:?} vs {enter}");
    assert_eq!(times[1], 1.0);
    assert!(frags.iter().all(|f| (f.depth - 10.0).abs() < 1e-4));

    // Covered at t = 0, left by the vertical edge.
    let (x, y) = (15, 12);
    assert!(edge_margin_at_pixel(&tris, &light, x, y) > MARGIN);
    let leave = (x as f32 + 0.5 - 10.3) / K;
    let times = sorted_times(&fragments_at_pixel(&tris, &light, x, y));
    assert_eq!(times.len(), 2, "{times:?}");
    assert_eq!(times[0], 0.0);
    assert!((times[1] - leave).abs() < 1e-3, "{times:?} vs {leave}");

    // Covered throughout: only the caps; never covered: nothing.
    assert_eq!(
        sorted_times(&fragments_at_pixel(&tris, &light, 20, 20)),
        vec![0.0, 1.0]
    );
    assert!(fragments_at_pixel(&tris, &light, 50, 50).is_empty());

    // Every probe-safe pixel sees the prism surface an even number of times.
    for y in 0..SIZE {
        for x in 0..SIZE {
            if edge_margin_at_pixel(&tris, &light, x, y) > MARGIN {
                let n = fragments_at_pixel(&tris, &light, x, y).len();
                assert_eq!(n % 2, 0, "pixel ({x}, {y}) has {n} fragments");
            }
        }
    }
}

#[test]
fn edges_crossing_on_screen_take_the_crossing_case_and_keep_parity() {
    let light = ortho_pixels();
    // Rigid rotation by 60 degrees about (20, 20), the midpoint of edge (0, 1):
    // the t=0 and t=1 copies of that edge cross there at s = u = 0.5.
    let centre = px(20.0, 20.0, -10.0);
    let p0 = [
        px(10.0, 20.0, -10.0),
        px(30.0, 20.0, -10.0),
        px(20.0, 35.0, -10.0),
    ];
    let rot = glam::Quat::from_rotation_z(60f32.to_radians());
    let p1 = p0.map(|p| centre + rot * (p - centre));

    let cases = edge_cases(&light, p0, p1);
    assert_eq!(cases[0], EdgeCase::Crossing);
    let tris = prism_triangles(&light, p0, p1, true);
    let expected_len: usize = 2 + cases
        .iter()
        .map(|c| if *c == EdgeCase::Crossing { 2 } else { 4 })
        .sum::<usize>();
    assert_eq!(tris.len(), expected_len);
    assert!(tris.len() <= 14);

    let mut probed = 0;
    let mut covered = 0;
    for y in 0..SIZE {
        for x in 0..SIZE {
            if edge_margin_at_pixel(&tris, &light, x, y) > MARGIN {
                let n = fragments_at_pixel(&tris, &light, x, y).len();
                assert_eq!(n % 2, 0, "pixel ({x}, {y}) has {n} fragments");
                probed += 1;
                covered += usize::from(n > 0);
            }
        }
    }
    assert!(
        probed > 1000 && covered > 100,
        "{probed} probed, {covered} covered"
    );
}

#[test]
fn culling_removes_invisible_prisms_only() {
    let light = ortho_pixels();
    // Counter-clockwise as seen from +z (the light) faces the light.
    let front = [
        px(10.0, 10.0, -10.0),
        px(30.0, 10.0, -10.0),
        px(10.0, 30.0, -10.0),
    ];
    let back = [front[0], front[2], front[1]];
    assert!(prism_triangles(&light, back, back, true).is_empty());
    assert_eq!(prism_triangles(&light, back, back, false).len(), 14);
    // Facing the light at one end of the shutter is enough to be kept.
    assert_eq!(prism_triangles(&light, back, front, true).len() % 2, 0);
    assert!(!prism_triangles(&light, back, front, true).is_empty());

    // Entirely left of the frustum at both times.
    let left = front.map(|p| p - Vec3::X * 100.0);
    assert!(prism_triangles(&light, left, left, false).is_empty());
    // Left at t = 0, inside at t = 1: kept.
    assert!(!prism_triangles(&light, left, front, false).is_empty());
}

#[test]
fn fragments_beyond_the_far_plane_are_clipped() {
    let light = ortho_pixels();
    // Depth runs linearly from 90 at x = 0 to 110 at x = 40; far plane at 100.
    let tri = [
        px(0.0, 0.0, -90.0),
        px(40.0, 0.0, -110.0),
        px(0.0, 40.0, -90.0),
    ];
    let tris = prism_triangles(&light, tri, tri, false);
    let depth_at = |x: u32| 90.0 + 20.0 * (x as f32 + 0.5) / 40.0;

    let near_frags = fragments_at_pixel(&tris, &light, 10, 5);
    assert_eq!(near_frags.len(), 2);
    assert!(
        near_frags
            .iter()
            .all(|f| (f.depth - depth_at(10)).abs() < 1e-3)
    );
    assert!(edge_margin_at_pixel(&tris, &light, 25, 5) > MARGIN);
    assert!(fragments_at_pixel(&tris, &light, 25, 5).is_empty());
    // The far clip line at x = 20 counts as an edge for the margin.
    assert!(edge_margin_at_pixel(&tris, &light, 19, 5) < 1.0);
}

/// Deterministic pseudo-random numbers in [-1, 1) (no rand dependency).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((self.0 >> 40) as f32 / (1u64 << 23) as f32) - 1.0
    }
    fn vec3(&mut self, scale: f32) -> Vec3 {
        Vec3::new(self.next(), self.next(), self.next()) * scale
    }
}

#[test]
fn random_perspective_motions_keep_even_fragment_counts() {
    let light = perspective(Vec3::new(2.0, 6.0, 9.0));
    let mut rng = Lcg(0x5eed);
    let mut crossings = 0;
    for _ in 0..40 {
        let p0 = [rng.vec3(2.5), rng.vec3(2.5), rng.vec3(2.5)];
        let shift = rng.vec3(1.5);
        let p1 = p0.map(|p| p + shift + rng.vec3(1.5));
        let tris = prism_triangles(&light, p0, p1, false);
        assert!(tris.len() <= 14);
        assert!(tris.iter().flatten().all(|v| v.clip.w > 0.0));
        crossings += edge_cases(&light, p0, p1)
            .iter()
            .filter(|c| **c == EdgeCase::Crossing)
            .count();
        for y in (0..SIZE).step_by(3) {
            for x in (0..SIZE).step_by(3) {
                if edge_margin_at_pixel(&tris, &light, x, y) > MARGIN {
                    let frags = fragments_at_pixel(&tris, &light, x, y);
                    assert_eq!(frags.len() % 2, 0, "pixel ({x}, {y}): {frags:?}");
                    assert!(frags.iter().all(|f| (0.0..=1.0).contains(&f.time)));
                }
            }
        }
    }
    assert!(
        crossings > 0,
        "random motions never exercised the crossing case"
    );
}
