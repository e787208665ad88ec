//! The geometry shader's model: the prism a triangle sweeps over the shutter, emitted as
//! caps and side surfaces (split around a centre vertex, or at the crossing of the two
//! times' edges), culled when provably invisible. In f32, like the shader.

use super::{EdgeCase, LightSetup, PrismVertex};
use glam::{Vec2, Vec3, Vec4};

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
