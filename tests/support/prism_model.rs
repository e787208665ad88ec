//! Independent CPU model of the prism geometry shader (Hong & Oh 2018, §4.1) and a
//! reference rasterizer for it.
//!
//! GPU integration tests use this to predict, per shadow-map pixel, which (depth, time)
//! fragments the collection sub-pass should have stored. It is written from the
//! algorithm description, not from the shader source, so that a shared misreading
//! of the paper is the only way both can agree on a wrong answer.
//!
//! Conventions (mirroring the Vulkan pipeline):
//! * clip space z in [0, w]; framebuffer x = (ndc.x * 0.5 + 0.5) * W and
//!   y = (ndc.y * 0.5 + 0.5) * H (no y flip here: the projection matrix owns that);
//! * `depth` is linear light-view depth `-v.z`, `time` is 0 / 0.5 / 1 at the vertices.
//!
//! The prism construction uses f32 like the shader; the rasterizer uses f64 so that
//! its own rounding is negligible next to the GPU's fixed-point snapping (tests avoid
//! the GPU's tie rules by probing pixels with `edge_margin_at_pixel` > 0.01 px).

use glam::{DVec2, Mat4, Vec2, Vec3, Vec4};

/// One vertex emitted by the geometry shader.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrismVertex {
    pub clip: Vec4,
    /// Linear light-view depth (`-view.z`), interpolated perspective-correctly.
    pub depth: f32,
    /// Normalised shutter time in [0, 1].
    pub time: f32,
}

/// The light's camera and the shadow-map resolution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSetup {
    pub view: Mat4,
    pub proj: Mat4,
    pub orthographic: bool,
    pub width: u32,
    pub height: u32,
}

/// Which emission case each edge took (for tests that want to make sure both cases are
/// exercised).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EdgeCase {
    /// Side surface split into four triangles around the centre vertex H.
    Centre,
    /// The t=0 and t=1 edges cross on screen; two triangles meet at the crossing X.
    Crossing,
}

/// A fragment the rasterizer produced at one pixel centre.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CpuFragment {
    pub depth: f32,
    pub time: f32,
    /// How fast depth and time change across the screen here (per pixel): a rasterizer that
    /// snaps vertices to its sub-pixel grid may shift them by that much per pixel of snap.
    pub depth_per_pixel: f32,
    pub time_per_pixel: f32,
}

/// Edge order fixed by the algorithm; the side surface of edge (a, b) is P Q Q' P'.
const EDGES: [(usize, usize); 3] = [(0, 1), (1, 2), (2, 0)];

/// The crossing test is skipped (Centre case) unless every corner is this far in front
/// of the eye, because the perspective divide is meaningless at or behind w = 0.
const MIN_W_FOR_CROSSING: f32 = 1e-6;

/// Parallel (or degenerate) edge pairs have no single crossing point.
const MIN_CROSSING_DENOM: f32 = 1e-12;

/// View-space positions and clip positions of one time's triangle.
fn transform(light: &LightSetup, p: [Vec3; 3]) -> ([Vec3; 3], [Vec4; 3]) {
    let v = p.map(|p| light.view.transform_point3(p));
    let c = v.map(|v| light.proj * v.extend(1.0));
    (v, c)
}

/// True when all six clip points lie outside one and the same clip plane: only then is
/// the whole prism provably invisible (its hull is the hull of the six points).
fn outside_one_plane(clips: &[Vec4]) -> bool {
    let planes: [fn(Vec4) -> bool; 6] = [
        |c| c.x < -c.w,
        |c| c.x > c.w,
        |c| c.y < -c.w,
        |c| c.y > c.w,
        |c| c.z < 0.0,
        |c| c.z > c.w,
    ];
    planes.iter().any(|out| clips.iter().all(|&c| out(c)))
}

/// Whether the triangle's front (counter-clockwise as seen by the light) faces the light.
fn faces_light(v: [Vec3; 3], orthographic: bool) -> bool {
    let n = (v[1] - v[0]).cross(v[2] - v[0]);
    if orthographic {
        // Every light ray points down -Z, so only the normal's z sign matters.
        n.z > 0.0
    } else {
        n.dot(-v[0]) > 0.0
    }
}

fn cross2(x: Vec2, y: Vec2) -> f32 {
    x.x * y.y - x.y * y.x
}

/// Screen parameters (s along P->Q, u along P'->Q') of the strict crossing of the two
/// projected edges, if there is one.
fn crossing_params(p: Vec4, q: Vec4, p1: Vec4, q1: Vec4) -> Option<(f32, f32)> {
    if [p, q, p1, q1].iter().any(|c| c.w <= MIN_W_FOR_CROSSING) {
        return None;
    }
    let a = p.truncate().truncate() / p.w;
    let b = q.truncate().truncate() / q.w;
    let c = p1.truncate().truncate() / p1.w;
    let d = q1.truncate().truncate() / q1.w;
    let denom = cross2(b - a, d - c);
    if denom.abs() <= MIN_CROSSING_DENOM {
        return None;
    }
    let ac = c - a;
    let s = cross2(ac, d - c) / denom;
    let u = cross2(ac, b - a) / denom;
    // Strict: a crossing at an end point is a shared vertex, which the Centre split
    // already handles without producing a degenerate triangle.
    (s > 0.0 && s < 1.0 && u > 0.0 && u < 1.0).then_some((s, u))
}

/// The point of clip segment `from -> to` whose projection sits at screen parameter
/// `s`. Screen parameters are not clip parameters under perspective, hence the w
/// weighting.
fn at_screen_param(from: PrismVertex, to: PrismVertex, s: f32) -> PrismVertex {
    let sigma = s * from.w() / (s * from.w() + (1.0 - s) * to.w());
    PrismVertex {
        clip: from.clip.lerp(to.clip, sigma),
        depth: from.depth + (to.depth - from.depth) * sigma,
        time: from.time + (to.time - from.time) * sigma,
    }
}

impl PrismVertex {
    fn w(self) -> f32 {
        self.clip.w
    }
}

/// Triangles the geometry shader emits for one moving triangle: the two caps first,
/// then each edge's side surface in edge order (0,1), (1,2), (2,0). At most 14.
pub fn prism_triangles(
    light: &LightSetup,
    p0: [Vec3; 3],
    p1: [Vec3; 3],
    cull_back_faces: bool,
) -> Vec<[PrismVertex; 3]> {
    let (v0, c0) = transform(light, p0);
    let (v1, c1) = transform(light, p1);

    let all_clips = [c0[0], c0[1], c0[2], c1[0], c1[1], c1[2]];
    if outside_one_plane(&all_clips) {
        return Vec::new();
    }
    // A closed mesh's back faces are hidden behind its front faces, but only if the
    // triangle faces away during the whole shutter; at either end point facing the
    // light is enough to keep it (the model only checks the two end points).
    if cull_back_faces
        && !faces_light(v0, light.orthographic)
        && !faces_light(v1, light.orthographic)
    {
        return Vec::new();
    }

    let cap = |c: [Vec4; 3], v: [Vec3; 3], time: f32| -> [PrismVertex; 3] {
        [0, 1, 2].map(|i| PrismVertex {
            clip: c[i],
            depth: -v[i].z,
            time,
        })
    };
    let cap0 = cap(c0, v0, 0.0);
    let cap1 = cap(c1, v1, 1.0);

    let mut tris = Vec::with_capacity(14);
    tris.push(cap0);
    tris.push(cap1);
    for (a, b) in EDGES {
        let (p, q, q1, p1) = (cap0[a], cap0[b], cap1[b], cap1[a]);
        match crossing_params(p.clip, q.clip, p1.clip, q1.clip) {
            Some((s, u)) => {
                let x0 = at_screen_param(p, q, s);
                let x1 = at_screen_param(p1, q1, u);
                // Both project to the same screen point, and so does their clip-space
                // average (same xy/w), which puts X at mid-shutter between them.
                let x = PrismVertex {
                    clip: (x0.clip + x1.clip) * 0.5,
                    depth: (x0.depth + x1.depth) * 0.5,
                    time: 0.5,
                };
                tris.push([p, p1, x]);
                tris.push([q, q1, x]);
            }
            None => {
                let h = PrismVertex {
                    clip: (p.clip + q.clip + q1.clip + p1.clip) * 0.25,
                    depth: (p.depth + q.depth + q1.depth + p1.depth) * 0.25,
                    time: 0.5,
                };
                tris.push([p, q, h]);
                tris.push([q, q1, h]);
                tris.push([q1, p1, h]);
                tris.push([p1, p, h]);
            }
        }
    }
    tris
}

/// Which case each edge (0,1), (1,2), (2,0) takes in `prism_triangles`, regardless of
/// culling.
pub fn edge_cases(light: &LightSetup, p0: [Vec3; 3], p1: [Vec3; 3]) -> [EdgeCase; 3] {
    let (_, c0) = transform(light, p0);
    let (_, c1) = transform(light, p1);
    EDGES.map(|(a, b)| match crossing_params(c0[a], c0[b], c1[a], c1[b]) {
        Some(_) => EdgeCase::Crossing,
        None => EdgeCase::Centre,
    })
}

/// An emitted triangle projected to the framebuffer.
struct ScreenTri {
    pos: [DVec2; 3],
    inv_w: [f64; 3],
    ndc_z: [f64; 3],
    depth: [f64; 3],
    time: [f64; 3],
    /// Twice the signed screen area; either winding is rasterized.
    area2: f64,
}

/// `None` when a vertex is at or behind the eye (w <= 0): those need real near-plane
/// clipping, which this model does not implement (see `fragments_at_pixel`).
fn project(tri: &[PrismVertex; 3], light: &LightSetup) -> Option<ScreenTri> {
    if tri.iter().any(|v| v.clip.w <= 0.0) {
        return None;
    }
    let (w, h) = (f64::from(light.width), f64::from(light.height));
    let pos = tri.map(|v| {
        let inv = 1.0 / f64::from(v.clip.w);
        DVec2::new(
            (f64::from(v.clip.x) * inv * 0.5 + 0.5) * w,
            (f64::from(v.clip.y) * inv * 0.5 + 0.5) * h,
        )
    });
    Some(ScreenTri {
        pos,
        inv_w: tri.map(|v| 1.0 / f64::from(v.clip.w)),
        ndc_z: tri.map(|v| f64::from(v.clip.z) / f64::from(v.clip.w)),
        depth: tri.map(|v| f64::from(v.depth)),
        time: tri.map(|v| f64::from(v.time)),
        area2: (pos[1] - pos[0]).perp_dot(pos[2] - pos[0]),
    })
}

impl ScreenTri {
    /// Screen-space barycentrics of `p` (undefined for zero area).
    fn barycentrics(&self, p: DVec2) -> [f64; 3] {
        let [a, b, c] = self.pos;
        [
            (c - b).perp_dot(p - b) / self.area2,
            (a - c).perp_dot(p - c) / self.area2,
            (b - a).perp_dot(p - a) / self.area2,
        ]
    }

    /// Inside the triangle (ties included: tests stay clear of them) and not z-clipped.
    fn covers(&self, p: DVec2) -> Option<[f64; 3]> {
        if self.area2 == 0.0 {
            return None;
        }
        let l = self.barycentrics(p);
        if l.iter().any(|&x| x < 0.0) {
            return None;
        }
        // With every w > 0, clipping against z = 0 and z = w removes exactly the
        // screen points whose ndc z (affine in screen space) leaves [0, 1]. The x/y
        // planes never remove a pixel centre inside the framebuffer.
        let z = dot3(l, self.ndc_z);
        (0.0..=1.0).contains(&z).then_some(l)
    }

    /// Screen-space gradient of ndc z, to locate the near/far clip lines.
    fn ndc_z_gradient(&self) -> DVec2 {
        let [a, b, c] = self.pos;
        ((c - b).perp() * self.ndc_z[0]
            + (a - c).perp() * self.ndc_z[1]
            + (b - a).perp() * self.ndc_z[2])
            / self.area2
    }
}

fn dot3(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn pixel_centre(x: u32, y: u32) -> DVec2 {
    DVec2::new(f64::from(x) + 0.5, f64::from(y) + 0.5)
}

/// Fragments at the centre of pixel (x, y), in no particular order.
///
/// Only triangles entirely in front of the eye (w > 0 at all three vertices) are
/// rasterized; any other triangle is skipped, so tests must keep their geometry in
/// front of the light (always true for an orthographic light, where w = 1). Zero-area
/// triangles (e.g. the side surfaces of a static triangle) produce nothing. Pixels
/// outside the framebuffer produce nothing.
pub fn fragments_at_pixel(
    tris: &[[PrismVertex; 3]],
    light: &LightSetup,
    x: u32,
    y: u32,
) -> Vec<CpuFragment> {
    if x >= light.width || y >= light.height {
        return Vec::new();
    }
    let p = pixel_centre(x, y);
    tris.iter()
        .filter_map(|tri| project(tri, light))
        .filter_map(|st| {
            let l = st.covers(p)?;
            // Perspective-correct: attributes are affine in clip space, so interpolate
            // attr/w and 1/w linearly on screen.
            let at = |l: [f64; 3]| {
                let wts = [0, 1, 2].map(|i| l[i] * st.inv_w[i]);
                let sum: f64 = wts.iter().sum();
                (dot3(wts, st.depth) / sum, dot3(wts, st.time) / sum)
            };
            let (depth, time) = at(l);
            // Barycentrics extend affinely past the edges, so a nearby point may lie outside.
            const STEP: f64 = 1e-3;
            let (dx, dy) = (
                at(st.barycentrics(p + DVec2::X * STEP)),
                at(st.barycentrics(p + DVec2::Y * STEP)),
            );
            let slope = |d: f64, ddx: f64, ddy: f64| (DVec2::new(ddx - d, ddy - d) / STEP).length();
            Some(CpuFragment {
                depth: depth as f32,
                time: time as f32,
                depth_per_pixel: slope(depth, dx.0, dy.0) as f32,
                time_per_pixel: slope(time, dx.1, dy.1) as f32,
            })
        })
        .collect()
}

fn distance_to_segment(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.distance(a + ab * t)
}

/// Distance in pixels from the centre of pixel (x, y) to the nearest boundary that
/// decides coverage there: every edge of every projected triangle (zero-area ones
/// included, to stay conservative), plus the near/far clip lines of triangles that
/// cover the pixel. Triangles skipped by `fragments_at_pixel` (some w <= 0) are skipped
/// here too. `f32::INFINITY` when nothing is near.
pub fn edge_margin_at_pixel(tris: &[[PrismVertex; 3]], light: &LightSetup, x: u32, y: u32) -> f32 {
    let p = pixel_centre(x, y);
    let mut margin = f64::INFINITY;
    for st in tris.iter().filter_map(|tri| project(tri, light)) {
        for i in 0..3 {
            margin = margin.min(distance_to_segment(p, st.pos[i], st.pos[(i + 1) % 3]));
        }
        if let Some(l) = st.covers(p) {
            let grad = st.ndc_z_gradient().length();
            if grad > 0.0 {
                let z = dot3(l, st.ndc_z);
                margin = margin.min(z.abs() / grad).min((1.0 - z).abs() / grad);
            }
        }
    }
    margin as f32
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::camera::rh::{proj::vulkan, view::look_at_mat4};

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
}
