//! An upper bound on the ranges a temporal frame stores, from the scene alone, so that the
//! first attempt has room for all of them and the shadow pass never runs twice (issue 26:
//! random-cubes overflowed the lower bound's room and re-ran its whole collection).
//!
//! Why it bounds (the exact construction, `exact_prism.glsl`): a triangle's corners move
//! linearly and stay in front of the light, so each of its images lies in the convex hull of
//! its six projected corners (a perspective projection keeps segments straight while w > 0),
//! and it stores ranges only at texel centres it covers: centres in that hull. At one
//! centre, it stores one range per covered run. With r = (X, Y, 1) the centre's ray and
//! v_k(t) the corners' clip (x, y, w), the run boundaries are the roots of
//! e_k(t) = det(v_i(t), v_j(t), r) = A + B t + C t^2, and the centre is covered while every
//! e_k has the sign of det(V(t)), a cubic that is the same for every centre (Cramer, see
//! `light_crossing.glsl`). If every e_k is monotone on [0, 1] at every centre of the
//! footprint, {e_k has a given sign} is an interval, their intersection too, so each stretch
//! between sign changes of det(V) holds at most one run: runs <= 1 + those sign changes.
//! e_k' = B + 2 C t is affine in t and in r, so it keeps one sign over [0, 1] x footprint iff
//! it has that sign at t = 0 and t = 1 at the footprint's corners. Elsewhere (an e_k that
//! turns, a corner at or behind the light) the shader's own cap holds: `EXACT_MAX_RUNS`.
//!
//! Kept loose where exactness would cost: the footprint is the hull grown by
//! `GROWTH_TEXELS` (for f32 and the rasterizer), a triangle whose corners reach near or
//! behind the light counts every texel of the map, and culling (closed meshes, triangles
//! behind the static layer) is ignored. `app/tests/gpu/range_bound.rs` checks it is never
//! below the count, and how far above, on every built-in scene.

//! An upper bound on the ranges a temporal frame stores, from the host's positions alone, so
//! that a map reserved for it never runs out of room and no frame is drawn twice or grown a
//! frame late (issue 26: random-cubes overflowed a first guess and re-ran its whole
//! collection; an engine learnt of an overflow one frame late).
//!
//! Why it bounds (the exact construction, `exact_prism.glsl`): a triangle's corners move
//! linearly and stay in front of the light, so each of its images lies in the convex hull of
//! its six projected corners (a perspective projection keeps segments straight while w > 0),
//! and it stores ranges only at texel centres it covers: centres in that hull. At one
//! centre, it stores one range per covered run. With r = (X, Y, 1) the centre's ray and
//! v_k(t) the corners' clip (x, y, w), the run boundaries are the roots of
//! e_k(t) = det(v_i(t), v_j(t), r) = A + B t + C t^2, and the centre is covered while every
//! e_k has the sign of det(V(t)), a cubic that is the same for every centre (Cramer, see
//! `light_crossing.glsl`). If every e_k is monotone on [0, 1] at every centre of the
//! footprint, {e_k has a given sign} is an interval, their intersection too, so each stretch
//! between sign changes of det(V) holds at most one run: runs <= 1 + those sign changes.
//! e_k' = B + 2 C t is affine in t and in r, so it keeps one sign over [0, 1] x footprint iff
//! it has that sign at t = 0 and t = 1 at the footprint's corners. Elsewhere (an e_k that
//! turns, a corner at or behind the light) the shader's own cap holds: `EXACT_MAX_RUNS`.
//! A triangle reaching behind the light (a flashlight among moving geometry) has no finite
//! images there: its footprint is the centres whose rays meet its swept hull in front of the
//! light (`Map::beyond_the_light_footprint`), every texel only where that hull holds the
//! light itself.
//!
//! Kept loose where exactness would cost: the footprint is the hull grown by
//! `GROWTH_TEXELS` (for f32 and the rasterizer), a triangle reaching behind the light counts
//! the cap at every centre of its footprint, and only culling of closed meshes is mirrored
//! (not triangles behind the static layer). `app/tests/gpu/range_bound.rs` checks
//! it is never below the count, and how far above, on every built-in scene;
//! `tests/gpu/range_ceiling.rs` that an engine's map reserved with it never overflows.

use glam::{DMat4, DVec2, DVec3, DVec4, Mat4, Vec3};

use super::view::{LightView, Lookup, PrismConstruction};
use crate::error::{Error, Result};

/// `EXACT_MAX_RUNS` of `glsl/exact_prism.glsl`: at most 6 edge roots and 3 light crossings
/// cut the shutter into 10 pieces, at most 5 covered.
const EXACT_MAX_RUNS: u64 = 5;
/// How far the hull is grown, in texels: far more than f32 rounding of the corners' images
/// (about 1e-3 texel at 4096 texels), far less than a texel. (A triangle that does not move
/// is cut to the light's frustum first; the cut points are as exact as its corners.)
const GROWTH_TEXELS: f64 = 0.125;
/// Corners imaged beyond this many map widths, or with w this close to 0 (relative to the
/// largest |w|), count the whole map: f32 no longer places them within the growth.
const FAR_MAP_WIDTHS: f64 = 64.0;
const NEAR_W: f64 = 1e-4;
/// A triangle reaching behind the light: each corner stands for a box this share of the
/// largest coordinate wide (f32 rounds corners by about 6e-8 of it), and a cone of recession
/// directions wider than `MAX_CONE` radians counts every centre (the far points it takes
/// grow as 1 / cos(span / 2)).
const BOX: f64 = 1e-5;
const MAX_CONE: f64 = 2.8;
/// e_k' must keep its sign by this share of its largest value over the footprint's
/// corners, so f32's roots cannot split a run the f64 test calls monotone.
const MONOTONE_MARGIN: f64 = 1e-6;
/// A closed mesh's triangle is culled here only if it faces away by this share of its
/// facing's scale (the device culls in f32).
const CULL_MARGIN: f64 = 1e-5;

/// A draw as the host holds it: the same positions, indices and transforms as the
/// [`super::Draw`] it mirrors, read on the CPU. Give the same slice twice (and equal
/// transforms) for a draw that does not move, exactly as its `Draw` names one stream twice.
#[derive(Debug, Clone, Copy)]
pub struct HostDraw<'a> {
    /// Object-space positions at shutter open.
    pub positions_t0: &'a [Vec3],
    /// Object-space positions at shutter close (as many).
    pub positions_t1: &'a [Vec3],
    /// Three per triangle, or None: the positions taken three at a time.
    pub indices: Option<&'a [u32]>,
    /// Object to world at shutter open.
    pub transform_t0: Mat4,
    /// Object to world at shutter close.
    pub transform_t1: Mat4,
    /// As [`super::Draw::closed`].
    pub closed: bool,
}

impl<'a> HostDraw<'a> {
    /// Both transforms the identity, not closed, as [`super::Draw::new`].
    pub fn new(
        positions_t0: &'a [Vec3],
        positions_t1: &'a [Vec3],
        indices: Option<&'a [u32]>,
    ) -> Self {
        Self {
            positions_t0,
            positions_t1,
            indices,
            transform_t0: Mat4::IDENTITY,
            transform_t1: Mat4::IDENTITY,
            closed: false,
        }
    }

    /// As [`super::Draw::is_static`]: one slice named twice and one transform.
    pub fn is_static(&self) -> bool {
        std::ptr::eq(self.positions_t0, self.positions_t1) && self.transform_t0 == self.transform_t1
    }

    /// Its triangles' world-space corners at t = 0 and t = 1, in draw order; an error names
    /// the first index beyond the positions, streams of different lengths, or corners that
    /// are not whole triangles (none is left out unsaid).
    pub fn triangles(&self) -> Result<impl Iterator<Item = ([Vec3; 3], [Vec3; 3])> + '_> {
        let n = self.positions_t0.len();
        if self.positions_t1.len() != n {
            return Err(Error::InvalidArgument(format!(
                "a host draw's positions: {n} at shutter open, {} at shutter close",
                self.positions_t1.len()
            )));
        }
        let listed = self.indices.map_or(n, <[u32]>::len);
        if listed % 3 != 0 {
            return Err(Error::InvalidArgument(format!(
                "a host draw lists {listed} corners ({}), not whole triangles",
                if self.indices.is_some() {
                    "indices"
                } else {
                    "positions"
                }
            )));
        }
        let count = match self.indices {
            Some(indices) => {
                if let Some((at, &i)) = indices.iter().enumerate().find(|(_, i)| **i as usize >= n)
                {
                    return Err(Error::InvalidArgument(format!(
                        "a host draw's index {at} is {i}, beyond its {n} positions"
                    )));
                }
                indices.len() / 3
            }
            None => n / 3,
        };
        let vertex = move |k: usize| self.indices.map_or(k, |i| i[k] as usize);
        Ok((0..count).map(move |tri| {
            let at = |positions: &[Vec3], transform: Mat4| {
                [0, 1, 2].map(|c| transform.transform_point3(positions[vertex(3 * tri + c)]))
            };
            (
                at(self.positions_t0, self.transform_t0),
                at(self.positions_t1, self.transform_t1),
            )
        }))
    }
}

/// At most how many depth-time ranges a temporal frame with the exact construction (the
/// default) stores in a map of a given size, from the triangles' corners at t = 0 and t = 1:
/// reserve that many ([`super::TemporalShadowMap::reserve_for`] does) and no frame overflows.
/// How loose it is: `docs/src/generation.md`, "One attempt: the upper bound".
#[derive(Debug, Clone)]
pub struct RangeCeiling {
    setup: Setup,
}

impl RangeCeiling {
    /// For a map of `width` x `height` texels lit by `light`; None with the papers' prisms
    /// (`PrismConstruction::Paper`, not bounded here) and with the exact lookup's
    /// conservative collection (`Lookup::Exact`: it covers whole texels, this counts runs
    /// at texel centres).
    pub fn new(light: &LightView, width: u32, height: u32) -> Option<Self> {
        (light.prisms == PrismConstruction::Exact && light.lookup == Lookup::DepthLine).then(|| {
            Self {
                setup: Setup {
                    to_view: light.view.as_dmat4(),
                    proj: light.proj.as_dmat4(),
                    orthographic: !light.is_spot(),
                    map: Map {
                        width: f64::from(width),
                        height: f64::from(height),
                    },
                },
            }
        })
    }

    /// At most how many ranges one triangle stores, its world-space corners at t = 0 and
    /// t = 1; `closed` as its draw's [`super::Draw::closed`]. A triangle of a static draw
    /// stores none where the frame keeps static draws in the static layer
    /// ([`super::TemporalShadowMap::uses_static_layer`]): leave those out.
    pub fn triangle(&self, t0: &[Vec3; 3], t1: &[Vec3; 3], closed: bool) -> u64 {
        self.setup.triangle_ranges_at_most(t0, t1, closed)
    }

    /// The sum over a draw's triangles (static or not: the caller leaves out static draws
    /// where the static layer holds them).
    pub fn draw(&self, draw: &HostDraw) -> Result<u64> {
        Ok(draw
            .triangles()?
            .map(|(t0, t1)| self.triangle(&t0, &t1, draw.closed))
            .sum())
    }
}

#[derive(Debug, Clone)]
struct Setup {
    to_view: DMat4,
    proj: DMat4,
    orthographic: bool,
    map: Map,
}

#[derive(Debug, Clone)]
struct Map {
    width: f64,
    height: f64,
}

impl Map {
    fn texels(&self) -> u64 {
        (self.width * self.height) as u64
    }

    /// Clip (x, y, w) to texel units (texel x's centre at x + 0.5).
    fn texel(&self, c: DVec3) -> DVec2 {
        DVec2::new(
            (c.x / c.z + 1.0) * 0.5 * self.width,
            (c.y / c.z + 1.0) * 0.5 * self.height,
        )
    }

    /// r . n for the centre's ray r = (X, Y, 1) (NDC), as an affine function of texel
    /// coordinates: (a, b, c) with r . n = a x + b y + c.
    fn affine(&self, n: DVec3) -> (f64, f64, f64) {
        (
            2.0 * n.x / self.width,
            2.0 * n.y / self.height,
            n.z - n.x - n.y,
        )
    }
}

impl Map {
    /// Points (texel units) whose convex hull holds every centre that a triangle moving
    /// within the convex hull of clip-space `corners` (x, y, w) can cover, some of them at
    /// or behind the light or imaged beyond `reach`; None where that may be every centre.
    ///
    /// A centre's ray r = (X, Y, 1) meets the hull in front of the light iff r is a
    /// nonnegative combination of the corners. Eliminating w (Fourier-Motzkin), those rays
    /// are the convex hull of the images of the corners in front plus the cone of the
    /// recession directions: the (x, y) of corners with w = 0 and, for each corner i in
    /// front and j behind, -w_j c_i + w_i c_j (whose w is 0). The device rounds its f32
    /// corners (a backward error far below `BOX`), so each corner is replaced by the corners
    /// of a box around it and the exact rule applied to those. An image beyond `reach` is
    /// cut back along its ray from the map's centre, its direction added. Where the cone is
    /// pointed, the hull plus the cone meets the map only within `far` of the points along
    /// the cone's two extreme directions.
    fn beyond_the_light_footprint(&self, corners: &[DVec3], reach: f64) -> Option<Vec<DVec2>> {
        let scale = DVec2::new(0.5 * self.width, 0.5 * self.height);
        let centre = scale;
        let size = corners
            .iter()
            .map(|c| c.abs().max_element())
            .fold(0.0, f64::max);
        let h = BOX * size;
        let boxed: Vec<DVec3> = corners
            .iter()
            .flat_map(|c| {
                (0..8).map(move |k| {
                    let s = |bit: usize| if k >> bit & 1 == 1 { h } else { -h };
                    *c + DVec3::new(s(0), s(1), s(2))
                })
            })
            .collect();
        let mut points = Vec::new();
        let mut directions = Vec::new();
        for c in &boxed {
            if c.z > 0.0 {
                let off = self.texel(*c) - centre;
                let most = off.abs().max_element();
                if most > reach || !most.is_finite() {
                    let xy = c.truncate() * scale;
                    points.push(centre + xy * (reach / xy.abs().max_element()));
                    directions.push(xy);
                } else {
                    points.push(centre + off);
                }
            } else if c.z == 0.0 {
                directions.push(c.truncate() * scale);
            }
        }
        for i in boxed.iter().filter(|c| c.z > 0.0) {
            for j in boxed.iter().filter(|c| c.z < 0.0) {
                directions.push((-j.z * i.truncate() + i.z * j.truncate()) * scale);
            }
        }
        if points.is_empty() {
            return None;
        }
        if directions.is_empty() {
            return Some(points);
        }
        let (first, last) = pointed_cone(&directions)?;
        let (first, last) = (first.normalize(), last.normalize());
        // Far enough that a point farther along the cone from the hull is off the map.
        let half_span = first.angle_to(last).abs() / 2.0;
        let beyond = points
            .iter()
            .map(|p| (*p - centre).length())
            .fold(0.0, f64::max)
            + 2.0 * centre.length();
        let far = beyond / half_span.cos() + 1.0;
        let base = points.clone();
        for p in base {
            points.push(p + far * first);
            points.push(p + far * last);
        }
        Some(points)
    }
}

/// The extreme directions of the cone the nonzero `directions` span, counter-clockwise from
/// the first to the last, or None unless it spans at most `MAX_CONE` radians.
fn pointed_cone(directions: &[DVec2]) -> Option<(DVec2, DVec2)> {
    let mut angles: Vec<(f64, DVec2)> = directions
        .iter()
        .filter(|d| d.length() > 0.0)
        .map(|d| (d.y.atan2(d.x), *d))
        .collect();
    angles.sort_by(|a, b| a.0.total_cmp(&b.0));
    let n = angles.len();
    if n == 0 {
        return None;
    }
    // The widest gap between neighbours (the last to the first across the wrap included):
    // the cone is the rest of the circle.
    let (mut gap, mut after) = (angles[0].0 + std::f64::consts::TAU - angles[n - 1].0, 0);
    for k in 1..n {
        let g = angles[k].0 - angles[k - 1].0;
        if g > gap {
            (gap, after) = (g, k);
        }
    }
    let span = std::f64::consts::TAU - gap;
    (span <= MAX_CONE).then(|| (angles[after].1, angles[(after + n - 1) % n].1))
}

/// An affine function of texel coordinates, a x + b y + c.
type Affine = (f64, f64, f64);

fn eval(f: Affine, p: DVec2) -> f64 {
    f.0 * p.x + f.1 * p.y + f.2
}

impl Setup {
    fn triangle_ranges_at_most(&self, t0: &[Vec3; 3], t1: &[Vec3; 3], closed: bool) -> u64 {
        let view = |p: Vec3| -> DVec3 { self.to_view.transform_point3(p.as_dvec3()) };
        let (e0, e1): ([DVec3; 3], [DVec3; 3]) = (
            [0, 1, 2].map(|k| view(t0[k])),
            [0, 1, 2].map(|k| view(t1[k])),
        );
        let clip = |p: DVec3| -> DVec3 {
            let c: DVec4 = self.proj * p.extend(1.0);
            DVec3::new(c.x, c.y, c.w)
        };
        let v0: [DVec3; 3] = e0.map(clip);
        let v1: [DVec3; 3] = e1.map(clip);
        let map = &self.map;
        let moving = t0 != t1;
        let max_runs = if moving { EXACT_MAX_RUNS } else { 1 };
        let corners = || v0.iter().chain(&v1);
        if corners().all(|c| c.z <= 0.0) {
            // Wholly behind the light: the geometry shader emits nothing.
            return 0;
        }
        if closed && faces_away_whole_frame(&e0, &e1, self.orthographic) {
            return 0;
        }
        let w_scale = corners().map(|c| c.z.abs()).fold(0.0, f64::max);
        if !corners().all(|c| c.is_finite()) {
            return max_runs * map.texels();
        }
        if !moving {
            // One run, [0, 1], where the triangle covers the centre: its part inside the
            // light's frustum, projected.
            let inside = clip_to_frustum(&v0, NEAR_W * w_scale);
            let images: Vec<DVec2> = inside.iter().map(|&c| map.texel(c)).collect();
            return Footprint::new(&images, map).count(&[]).0;
        }
        let images: Vec<DVec2> = corners().map(|&c| map.texel(c)).collect();
        let reach = FAR_MAP_WIDTHS * map.width.max(map.height);
        let near = corners().any(|c| c.z <= NEAR_W * w_scale);
        if near || images.iter().any(|p| p.abs().max_element() > reach) {
            // Near or behind the light: the images of the corners no longer bound the
            // triangle's; the footprint is that of the swept hull's part in front of it, and
            // every centre counts the shader's cap.
            let corners: Vec<DVec3> = corners().copied().collect();
            return match map.beyond_the_light_footprint(&corners, reach) {
                Some(points) => EXACT_MAX_RUNS * Footprint::new(&points, map).count(&[]).0,
                None => EXACT_MAX_RUNS * map.texels(),
            };
        }
        let footprint = Footprint::new(&images, map);
        let turning = turning_edges(&v0, &v1, map, &footprint);
        let (centres, turns) = footprint.count(&turning);
        let runs = (1 + det_sign_changes(&v0, &v1)) * centres + turns;
        runs.min(EXACT_MAX_RUNS * centres)
    }
}

/// The polygon of clip-space (x, y, w) corners cut to the light's frustum: w >= `near_w`
/// and |x|, |y| <= w (Sutherland-Hodgman), so that its images lie on the map.
fn clip_to_frustum(corners: &[DVec3; 3], near_w: f64) -> Vec<DVec3> {
    let planes: [DVec3; 5] = [
        DVec3::new(0.0, 0.0, 1.0),
        DVec3::new(-1.0, 0.0, 1.0),
        DVec3::new(1.0, 0.0, 1.0),
        DVec3::new(0.0, -1.0, 1.0),
        DVec3::new(0.0, 1.0, 1.0),
    ];
    let mut poly = corners.to_vec();
    for (n, plane) in planes.iter().enumerate() {
        // Inside where plane . c >= offset (the near one) or >= 0.
        let offset = if n == 0 { near_w } else { 0.0 };
        let side = |c: DVec3| plane.dot(c) - offset;
        let mut out = Vec::with_capacity(poly.len() + 1);
        for k in 0..poly.len() {
            let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
            let (sa, sb) = (side(a), side(b));
            if sa >= 0.0 {
                out.push(a);
            }
            if (sa >= 0.0) != (sb >= 0.0) {
                out.push(a.lerp(b, sa / (sa - sb)));
            }
        }
        poly = out;
        if poly.is_empty() {
            break;
        }
    }
    poly
}

/// Whether a closed mesh's triangle is culled: its facing (as `shared.glsl`'s `facing`)
/// negative at t = 0, 1/3, 2/3 and 1 with both inner Bernstein coefficients negative, each
/// by a margin, so that f32 on the device culls at least what this culls.
fn faces_away_whole_frame(e0: &[DVec3; 3], e1: &[DVec3; 3], orthographic: bool) -> bool {
    let f = [0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0].map(|t| {
        let p = [0, 1, 2].map(|k| e0[k].lerp(e1[k], t));
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        let value = if orthographic { n.z } else { -n.dot(p[0]) };
        let scale = if orthographic {
            n.length()
        } else {
            n.length() * p[0].length()
        };
        (value, scale)
    });
    let margin = CULL_MARGIN * f.iter().map(|x| x.1).fold(0.0, f64::max);
    let v = f.map(|x| x.0);
    let b1 = (-5.0 * v[0] + 18.0 * v[1] - 9.0 * v[2] + 2.0 * v[3]) / 6.0;
    let b2 = (2.0 * v[0] - 9.0 * v[1] + 18.0 * v[2] - 5.0 * v[3]) / 6.0;
    [v[0], b1, b2, v[3]].iter().all(|&x| x < -margin)
}

/// For each edge k whose e_k may turn somewhere in the footprint: e_k' = B + 2 C t at t = 0
/// and t = 1, as affine functions of the texel, and the margin by which both must share a
/// sign for e_k to count as monotone there.
fn turning_edges(
    v0: &[DVec3; 3],
    v1: &[DVec3; 3],
    map: &Map,
    footprint: &Footprint,
) -> Vec<(Affine, Affine, f64)> {
    let Some((lo, hi)) = footprint.bounds else {
        return Vec::new();
    };
    let corners = [
        DVec2::new(lo.x, lo.y),
        DVec2::new(hi.x, lo.y),
        DVec2::new(lo.x, hi.y),
        DVec2::new(hi.x, hi.y),
    ];
    let d: [DVec3; 3] = [0, 1, 2].map(|k| v1[k] - v0[k]);
    let mut turning = Vec::new();
    for k in 0..3 {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        // det(a, b, r) = r . (a x b).
        let n_b = v0[i].cross(d[j]) + d[i].cross(v0[j]);
        let n_c = d[i].cross(d[j]);
        let at0 = map.affine(n_b);
        let at1 = map.affine(n_b + 2.0 * n_c);
        let values = corners.iter().flat_map(|&p| [eval(at0, p), eval(at1, p)]);
        let largest = values.clone().map(f64::abs).fold(0.0, f64::max);
        if largest == 0.0 {
            // e_k does not change at all: no root.
            continue;
        }
        let margin = MONOTONE_MARGIN * largest;
        let mut values = values;
        if values.clone().all(|v| v > margin) || values.all(|v| v < -margin) {
            continue;
        }
        turning.push((at0, at1, margin));
    }
    turning
}

/// At most how many times det(V(t)) changes sign in (0, 1): it is monotone between the roots
/// of its derivative, so once per stretch between them at most, counted where its ends'
/// signs differ or either end is too near zero to tell.
fn det_sign_changes(v0: &[DVec3; 3], v1: &[DVec3; 3]) -> u64 {
    let at = |t: f64| {
        let v = [0, 1, 2].map(|k| v0[k].lerp(v1[k], t));
        v[0].dot(v[1].cross(v[2]))
    };
    // Its magnitude's scale, for "too near zero".
    let scale = (0..=4)
        .map(|i| {
            let v = [0, 1, 2].map(|k| v0[k].lerp(v1[k], f64::from(i) / 4.0));
            v[0].length() * v[1].length() * v[2].length()
        })
        .fold(0.0, f64::max);
    let d: [DVec3; 3] = [0, 1, 2].map(|k| v1[k] - v0[k]);
    let p = v0;
    let c1 = d[0].dot(p[1].cross(p[2])) + p[0].dot(d[1].cross(p[2])) + p[0].dot(p[1].cross(d[2]));
    let c2 = p[0].dot(d[1].cross(d[2])) + d[0].dot(p[1].cross(d[2])) + d[0].dot(d[1].cross(p[2]));
    let c3 = d[0].dot(d[1].cross(d[2]));
    let mut ends = vec![0.0, 1.0];
    ends.extend(quadratic_roots01(3.0 * c3, 2.0 * c2, c1));
    ends.sort_by(f64::total_cmp);
    let tiny = 1e-9 * scale;
    ends.windows(2)
        .filter(|e| {
            let (a, b) = (at(e[0]), at(e[1]));
            a.abs() <= tiny || b.abs() <= tiny || (a < 0.0) != (b < 0.0)
        })
        .count() as u64
}

/// The real roots of a t^2 + b t + c in (0, 1) (a linear or constant one too).
fn quadratic_roots01(a: f64, b: f64, c: f64) -> Vec<f64> {
    let roots = if a == 0.0 {
        if b == 0.0 { vec![] } else { vec![-c / b] }
    } else {
        let disc = b * b - 4.0 * a * c;
        if disc < 0.0 {
            vec![]
        } else {
            let q = -0.5 * (b + disc.sqrt().copysign(b));
            if q == 0.0 {
                vec![0.0]
            } else {
                vec![q / a, c / q]
            }
        }
    };
    roots.into_iter().filter(|r| *r > 0.0 && *r < 1.0).collect()
}

/// The texel centres a triangle's ranges may lie at: the convex hull of its corners' images
/// at t = 0 and t = 1, grown by `GROWTH_TEXELS`, within the map.
struct Footprint {
    /// Each hull edge as a x + b y + c >= 0 inside, grown (a unit normal).
    edges: Vec<(f64, f64, f64)>,
    /// The grown hull's box, within the map's centres; None when it holds none.
    bounds: Option<(DVec2, DVec2)>,
}

impl Footprint {
    fn new(points: &[DVec2], map: &Map) -> Self {
        let hull = convex_hull(points);
        let n = hull.len();
        let mut edges = Vec::with_capacity(n.max(2));
        // A hull of two points is a segment: both of its sides bound the slab around it.
        for k in 0..if n == 2 {
            2
        } else if n >= 3 {
            n
        } else {
            0
        } {
            let (u, v) = (hull[k], hull[(k + 1) % n]);
            let d = (v - u).normalize();
            // Counter-clockwise hull: inside is to the left of u -> v.
            let (a, b) = (-d.y, d.x);
            edges.push((a, b, -(a * u.x + b * u.y) + GROWTH_TEXELS));
        }
        let lo = hull.iter().copied().fold(DVec2::INFINITY, DVec2::min) - GROWTH_TEXELS;
        let hi = hull.iter().copied().fold(DVec2::NEG_INFINITY, DVec2::max) + GROWTH_TEXELS;
        let lo = lo.max(DVec2::splat(0.5));
        let hi = hi.min(DVec2::new(map.width - 0.5, map.height - 0.5));
        Self {
            edges,
            bounds: (lo.x <= hi.x && lo.y <= hi.y).then_some((lo, hi)),
        }
    }

    /// Centres (x + 0.5, y + 0.5) inside, row by row; and the sum over them of how many of
    /// `turning` edges are not monotone there (e_k' at t = 0 and t = 1 not of one sign by
    /// the margin).
    fn count(&self, turning: &[(Affine, Affine, f64)]) -> (u64, u64) {
        let Some((lo, hi)) = self.bounds else {
            return (0, 0);
        };
        let (mut count, mut turns) = (0u64, 0u64);
        let mut row = (lo.y - 0.5).ceil();
        while row + 0.5 <= hi.y {
            let y = row + 0.5;
            let (mut from, mut to) = (lo.x, hi.x);
            for &(a, b, c) in &self.edges {
                let rest = b * y + c;
                if a > 0.0 {
                    from = from.max(-rest / a);
                } else if a < 0.0 {
                    to = to.min(-rest / a);
                } else if rest < 0.0 {
                    to = f64::NEG_INFINITY;
                }
            }
            // Centre columns i with from <= i + 0.5 <= to.
            let (first, last) = ((from - 0.5).ceil(), (to - 0.5).floor());
            if last >= first {
                let n = (last - first + 1.0) as u64;
                count += n;
                for &(at0, at1, margin) in turning {
                    let safe = monotone_columns(at0, at1, margin, y, (first, last));
                    turns += n - safe;
                }
            }
            row += 1.0;
        }
        (count, turns)
    }
}

/// Columns i in `cols` (inclusive) whose centre (i + 0.5, y) has both affine functions
/// above `margin`, or both below `-margin` (strictly).
fn monotone_columns(f: Affine, g: Affine, margin: f64, y: f64, cols: (f64, f64)) -> u64 {
    let mut safe = 0u64;
    for sign in [1.0, -1.0] {
        // sign * (a x + r) > margin for x = i + 0.5: an open half-line of i.
        let (mut lo, mut hi) = (cols.0, cols.1);
        for h in [f, g] {
            let (a, r) = (sign * h.0, sign * (h.1 * y + h.2));
            // a (i + 0.5) > margin - r
            let bound = (margin - r) / a - 0.5;
            if a > 0.0 {
                lo = lo.max(bound.floor() + 1.0);
            } else if a < 0.0 {
                hi = hi.min(bound.ceil() - 1.0);
            } else if r <= margin {
                hi = f64::NEG_INFINITY;
            }
        }
        if hi >= lo {
            safe += (hi - lo + 1.0) as u64;
        }
    }
    safe
}

/// The convex hull, counter-clockwise, without collinear points (Andrew's monotone chain);
/// one point for coincident ones, two for collinear ones.
fn convex_hull(points: &[DVec2]) -> Vec<DVec2> {
    let mut p = points.to_vec();
    p.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let turn = |o: DVec2, a: DVec2, b: DVec2| (a - o).perp_dot(b - o);
    let mut hull: Vec<DVec2> = Vec::with_capacity(2 * p.len());
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &DVec2>> = if pass == 0 {
            Box::new(p.iter())
        } else {
            Box::new(p.iter().rev())
        };
        for &q in iter {
            while hull.len() >= start + 2
                && turn(hull[hull.len() - 2], hull[hull.len() - 1], q) <= 0.0
            {
                hull.pop();
            }
            hull.push(q);
        }
        // The chain's last point is the next chain's first.
        hull.pop();
    }
    hull
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Centres within `GROWTH_TEXELS` of the hull of `points` (inside it, or that near its
    /// boundary), texel by texel: never more than the footprint counts, and every centre
    /// inside the hull itself counted.
    #[test]
    fn the_footprint_holds_every_centre_of_the_hull() {
        let map = Map {
            width: 41.0,
            height: 29.0,
        };
        let cases: [&[DVec2]; 4] = [
            &[
                DVec2::new(1.2, 2.7),
                DVec2::new(30.4, 5.1),
                DVec2::new(8.9, 21.3),
                DVec2::new(12.0, 3.0),
                DVec2::new(35.5, 25.5),
                DVec2::new(20.0, 10.0),
            ],
            // Reaching past the map on every side.
            &[
                DVec2::new(-5.0, -3.0),
                DVec2::new(10.0, 40.0),
                DVec2::new(55.0, 4.0),
            ],
            // A segment, and a point.
            &[
                DVec2::new(2.5, 2.5),
                DVec2::new(30.5, 20.5),
                DVec2::new(16.5, 11.5),
            ],
            &[DVec2::new(7.5, 7.5), DVec2::new(7.5, 7.5)],
        ];
        for points in cases {
            let hull = convex_hull(points);
            let inside = |p: DVec2, grow: f64| -> bool {
                match hull.len() {
                    1 => p.distance(hull[0]) <= grow,
                    2 => {
                        let (u, v) = (hull[0], hull[1]);
                        let t = ((p - u).dot(v - u) / (v - u).length_squared()).clamp(0.0, 1.0);
                        p.distance(u + t * (v - u)) <= grow
                    }
                    n => (0..n).all(|k| {
                        let (u, v) = (hull[k], hull[(k + 1) % n]);
                        (v - u).perp_dot(p - u) / (v - u).length() >= -grow
                    }),
                }
            };
            let (mut strict, mut near) = (0, 0);
            for y in 0..29 {
                for x in 0..41 {
                    let p = DVec2::new(f64::from(x) + 0.5, f64::from(y) + 0.5);
                    strict += u64::from(inside(p, 0.0));
                    near += u64::from(inside(p, GROWTH_TEXELS));
                }
            }
            let counted = Footprint::new(points, &map).count(&[]).0;
            assert!(counted >= near, "{points:?}: {counted} < {near}");
            // Growing the edges' lines overshoots only at corners and the segment's ends.
            assert!(counted <= near + 4, "{points:?}: {counted} vs {near}");
            assert!(strict <= near);
        }
    }

    #[test]
    fn the_hull_drops_inner_and_collinear_points() {
        let square = [
            DVec2::new(0.0, 0.0),
            DVec2::new(2.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(2.0, 2.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(0.0, 2.0),
        ];
        let hull = convex_hull(&square);
        assert_eq!(hull.len(), 4);
        let area: f64 = (0..4)
            .map(|k| hull[k].perp_dot(hull[(k + 1) % 4]))
            .sum::<f64>()
            / 2.0;
        assert_eq!(area, 4.0, "counter-clockwise, area 4");
        assert_eq!(
            convex_hull(&[DVec2::ZERO, DVec2::ONE, DVec2::splat(3.0)]).len(),
            2
        );
    }

    /// A triangle translating (every corner the same displacement) under an orthographic
    /// light: each e_k is linear in t, so one run per centre; a turning one may have more.
    #[test]
    fn edges_turn_only_where_the_triangle_turns() {
        let map = Map {
            width: 64.0,
            height: 64.0,
        };
        let whole = Footprint::new(
            &[
                DVec2::splat(0.0),
                DVec2::new(64.0, 0.0),
                DVec2::splat(64.0),
                DVec2::new(0.0, 64.0),
            ],
            &map,
        );
        let tri = [
            DVec3::new(-0.5, -0.5, 1.0),
            DVec3::new(0.5, -0.4, 1.0),
            DVec3::new(0.0, 0.5, 1.0),
        ];
        let moved = tri.map(|c| c + DVec3::new(0.3, 0.1, 0.0));
        assert!(turning_edges(&tri, &moved, &map, &whole).is_empty());
        assert_eq!(det_sign_changes(&tri, &moved), 0);
        // Turned by 180 degrees about its centroid: the edges sweep over centres and back.
        let centroid = (tri[0] + tri[1] + tri[2]) / 3.0;
        let turned = tri.map(|c| DVec3::new(2.0 * centroid.x - c.x, 2.0 * centroid.y - c.y, 1.0));
        let turning = turning_edges(&tri, &turned, &map, &whole);
        assert!(!turning.is_empty());
        let (centres, turns) = whole.count(&turning);
        assert_eq!(centres, 64 * 64);
        assert!(turns > 0 && turns < 3 * centres, "{turns}");
        // Mirrored through a line: the orientation flips once.
        let mirrored = tri.map(|c| DVec3::new(-c.x, c.y, 1.0));
        assert_eq!(det_sign_changes(&tri, &mirrored), 1);
    }

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
                    let r =
                        DVec2::new((x as f64 + 0.5) / 12.0 - 1.0, (y as f64 + 0.5) / 12.0 - 1.0);
                    let mut was = false;
                    for step in 0..=4000 {
                        let t = step as f64 / 4000.0;
                        let p: [DVec2; 3] = [0, 1, 2]
                            .map(|k| t0[k].as_dvec3().lerp(t1[k].as_dvec3(), t).truncate());
                        let e =
                            [0, 1, 2].map(|k| (p[(k + 1) % 3] - r).perp_dot(p[(k + 2) % 3] - r));
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
}
