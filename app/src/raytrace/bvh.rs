//! A motion BVH: a bounding volume hierarchy over moving triangles, queried at one shutter
//! time per ray.
//!
//! Built once per frame by binned SAH over each triangle's bounds over the whole shutter (the
//! union of its boxes at t = 0 and t = 1: corners move linearly, so the triangle stays inside
//! at every t). Each node also keeps its boxes at both shutter ends and is tested with their
//! blend at the ray's time: every corner `p0 + t d` lies in the blend of a box holding `p0`
//! and a box holding `p0 + d`, so the blended box bounds the node's triangles at that time
//! and is as tight as the scene allows, where the union would cover a fast object's whole
//! path. Flat node array, iterative traversal.

use super::intersect::Ray;
use super::triangles::Triangle;
use glam::DVec3;

/// Triangles a leaf holds at most when splitting would still pay.
const MAX_LEAF: usize = 8;
/// Bins per axis of the SAH sweep.
const BINS: usize = 16;
/// Past this depth, nodes are split at the median (halving), which bounds the depth and so
/// the traversal stack whatever the triangles' distribution: 48 + log2(2^25 triangles).
const SAH_DEPTH: usize = 48;
const STACK: usize = 128;
/// Node boxes are grown by this share of their largest coordinate: the blend of two boxes
/// and a corner's position at the same time are rounded separately (~1e-16 relative each),
/// and a box must never cut off a corner it holds.
const BOX_PAD: f64 = 1e-9;
/// Slab distances are rounded too: the far one is stretched as in PBRT (1 + 2 gamma(3)).
const SLAB_STRETCH: f64 = 1.0 + 2.0 * (3.0 * f64::EPSILON * 0.5) / (1.0 - 3.0 * f64::EPSILON * 0.5);

#[derive(Debug, Clone, Copy)]
struct Aabb {
    lo: DVec3,
    hi: DVec3,
}

impl Aabb {
    const EMPTY: Self = Self {
        lo: DVec3::splat(f64::INFINITY),
        hi: DVec3::splat(f64::NEG_INFINITY),
    };

    fn join(self, o: Self) -> Self {
        Self {
            lo: self.lo.min(o.lo),
            hi: self.hi.max(o.hi),
        }
    }

    fn area(self) -> f64 {
        let e = (self.hi - self.lo).max(DVec3::ZERO);
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }

    fn center(self) -> DVec3 {
        0.5 * (self.lo + self.hi)
    }
}

/// A node: its boxes at t = 0 and t = 1; a leaf (`count > 0`) holds triangles
/// `first .. first + count` of the tree's order, an inner node has its first child right after
/// it and its second at `first`.
#[derive(Debug, Clone, Copy)]
struct Node {
    lo0: DVec3,
    hi0: DVec3,
    lo1: DVec3,
    hi1: DVec3,
    first: u32,
    count: u16,
    axis: u16,
}

/// The hierarchy and the triangles in its order.
pub struct Bvh {
    nodes: Vec<Node>,
    triangles: Vec<Triangle>,
}

/// What the camera ray of a sample sees.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    /// Ray parameter of the hit.
    pub s: f64,
    /// Index into [`Bvh::triangles`].
    pub index: u32,
}

struct Item {
    bounds: [Aabb; 2],
    shutter: Aabb,
    center: DVec3,
    triangle: Triangle,
}

impl Bvh {
    pub fn new(triangles: &[Triangle]) -> Self {
        Self::with_sah_depth(triangles, SAH_DEPTH)
    }

    /// As [`Bvh::new`], with nodes below `sah_depth` split at the median (tests: 0 gives a
    /// pure median tree).
    pub(crate) fn with_sah_depth(triangles: &[Triangle], sah_depth: usize) -> Self {
        let mut items: Vec<Item> = triangles
            .iter()
            .map(|tri| {
                let [(lo0, hi0), (lo1, hi1)] = tri.end_bounds();
                let bounds = [Aabb { lo: lo0, hi: hi0 }, Aabb { lo: lo1, hi: hi1 }];
                let shutter = bounds[0].join(bounds[1]);
                Item {
                    bounds,
                    shutter,
                    center: shutter.center(),
                    triangle: *tri,
                }
            })
            .collect();
        let mut nodes = Vec::with_capacity(2 * items.len().max(1));
        if !items.is_empty() {
            build(&mut items, &mut nodes, sah_depth);
        }
        Self {
            nodes,
            triangles: items.into_iter().map(|i| i.triangle).collect(),
        }
    }

    pub fn triangles(&self) -> &[Triangle] {
        &self.triangles
    }

    /// Levels of the tree (a lone root is 1, no triangles 0).
    pub fn depth(&self) -> usize {
        let mut deepest = 0;
        let mut stack = if self.nodes.is_empty() {
            vec![]
        } else {
            vec![(0usize, 1usize)]
        };
        while let Some((i, d)) = stack.pop() {
            deepest = deepest.max(d);
            let node = &self.nodes[i];
            if node.count == 0 {
                stack.extend([(i + 1, d + 1), (node.first as usize, d + 1)]);
            }
        }
        deepest
    }

    /// The nearest triangle the ray meets at time `t` with parameter in `[s_min, s_max]`;
    /// among equally near ones the lowest id (what the GPU's atomic minimum of depth and id
    /// keeps).
    pub fn closest(&self, ray: &Ray, t: f64, s_min: f64, s_max: f64) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        let mut best_id = u32::MAX;
        let mut s_far = s_max;
        self.traverse(ray, t, s_min, &mut s_far, |tri, index, s_far| {
            if let Some(s) = ray.intersect(&tri.at(t), s_min, *s_far) {
                // `s` is at most the best so far (the test's upper bound): ties go by id.
                if best.is_none_or(|b| s < b.s || tri.id < best_id) {
                    best = Some(Hit { s, index });
                    best_id = tri.id;
                    *s_far = s;
                }
            }
            false
        });
        best
    }

    /// Whether any triangle but the one with id `skip` meets the ray at time `t` with
    /// parameter in `[s_min, s_max]`.
    pub fn occluded(&self, ray: &Ray, t: f64, s_min: f64, s_max: f64, skip: u32) -> bool {
        let mut found = false;
        let mut s_far = s_max;
        self.traverse(ray, t, s_min, &mut s_far, |tri, _, s_far| {
            found = tri.id != skip && ray.intersect(&tri.at(t), s_min, *s_far).is_some();
            found
        });
        found
    }

    /// Visits `(index, triangle)` in every leaf reached through nodes whose boxes `keep`
    /// accepts, given as `(lo0, hi0, lo1, hi1)` (padded, at t = 0 and t = 1; the box at time
    /// t is their blend); `visit` returns true to stop. For queries over the whole shutter
    /// (the lit fraction of a moving point, `shutter.rs`), which need both ends, not one
    /// time's blend.
    pub fn visit_swept(
        &self,
        mut keep: impl FnMut(DVec3, DVec3, DVec3, DVec3) -> bool,
        mut visit: impl FnMut(u32, &Triangle) -> bool,
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let mut stack = [0u32; STACK];
        let mut top = 0;
        let mut current = 0u32;
        loop {
            let node = &self.nodes[current as usize];
            if keep(node.lo0, node.hi0, node.lo1, node.hi1) {
                if node.count > 0 {
                    let first = node.first as usize;
                    for i in first..first + node.count as usize {
                        if visit(i as u32, &self.triangles[i]) {
                            return;
                        }
                    }
                } else {
                    stack[top] = node.first;
                    top += 1;
                    current += 1;
                    continue;
                }
            }
            if top == 0 {
                return;
            }
            top -= 1;
            current = stack[top];
        }
    }

    /// Visits the triangles of every leaf whose box at time t the ray enters within
    /// `[s_min, s_far]`, near child first; `visit` may shorten `s_far` and returns true to
    /// stop.
    #[inline]
    fn traverse(
        &self,
        ray: &Ray,
        t: f64,
        s_min: f64,
        s_far: &mut f64,
        mut visit: impl FnMut(&Triangle, u32, &mut f64) -> bool,
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let negative = [ray.dir.x < 0.0, ray.dir.y < 0.0, ray.dir.z < 0.0];
        let mut stack = [0u32; STACK];
        let mut top = 0;
        let mut current = 0u32;
        loop {
            let node = &self.nodes[current as usize];
            if enters(node, ray, t, s_min, *s_far) {
                if node.count > 0 {
                    let first = node.first as usize;
                    for i in first..first + node.count as usize {
                        if visit(&self.triangles[i], i as u32, s_far) {
                            return;
                        }
                    }
                } else {
                    // The child on the ray's side of the split first: its hits shorten the
                    // ray before the other is tested.
                    let (near, far) = if negative[node.axis as usize] {
                        (node.first, current + 1)
                    } else {
                        (current + 1, node.first)
                    };
                    stack[top] = far;
                    top += 1;
                    current = near;
                    continue;
                }
            }
            if top == 0 {
                return;
            }
            top -= 1;
            current = stack[top];
        }
    }
}

/// Slab test of the node's box at time t. A NaN slab distance (a ray in a slab's plane with a
/// zero direction component) fails every comparison and leaves the interval as it was.
#[inline]
fn enters(node: &Node, ray: &Ray, t: f64, s_min: f64, s_max: f64) -> bool {
    let lo = node.lo0 + t * (node.lo1 - node.lo0);
    let hi = node.hi0 + t * (node.hi1 - node.hi0);
    let a = (lo - ray.origin) * ray.inv_dir;
    let b = (hi - ray.origin) * ray.inv_dir;
    let (mut near, mut far) = (s_min, s_max);
    for axis in 0..3 {
        let (mut n, mut f) = (a[axis], b[axis]);
        if n > f {
            std::mem::swap(&mut n, &mut f);
        }
        f *= SLAB_STRETCH;
        if n > near {
            near = n;
        }
        if f < far {
            far = f;
        }
        if near > far {
            return false;
        }
    }
    true
}

/// Builds the tree of `items` (reordering them), depth first, appending to `nodes`.
fn build(items: &mut [Item], nodes: &mut Vec<Node>, sah_depth: usize) {
    // (range start, range end, depth, the inner node whose second child this is). A first
    // child is made right after its parent (index + 1); a second child only after the whole
    // first subtree, when its index becomes known to its parent.
    let mut work = vec![(0usize, items.len(), 0usize, None::<usize>)];
    while let Some((start, end, depth, parent)) = work.pop() {
        let index = push_node(nodes, &items[start..end]);
        if let Some(parent) = parent {
            nodes[parent].first = index as u32;
        }
        match split(&mut items[start..end], depth >= sah_depth) {
            None => {
                nodes[index].first = start as u32;
                nodes[index].count = (end - start) as u16;
            }
            Some((mid, axis)) => {
                nodes[index].axis = axis as u16;
                work.push((start + mid, end, depth + 1, Some(index)));
                work.push((start, start + mid, depth + 1, None));
            }
        }
    }
}

fn push_node(nodes: &mut Vec<Node>, items: &[Item]) -> usize {
    let b0 = items.iter().fold(Aabb::EMPTY, |b, i| b.join(i.bounds[0]));
    let b1 = items.iter().fold(Aabb::EMPTY, |b, i| b.join(i.bounds[1]));
    let scale = [b0.lo, b0.hi, b1.lo, b1.hi]
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs().max_element()));
    let pad = DVec3::splat(BOX_PAD * scale);
    nodes.push(Node {
        lo0: b0.lo - pad,
        hi0: b0.hi + pad,
        lo1: b1.lo - pad,
        hi1: b1.hi + pad,
        first: 0,
        count: 0,
        axis: 0,
    });
    nodes.len() - 1
}

/// Where to split `items` (reordered so the first part comes first) and along which axis, by
/// SAH or else at the median; `None` makes a leaf.
fn split(items: &mut [Item], median_only: bool) -> Option<(usize, usize)> {
    let n = items.len();
    if n <= 2 {
        return None;
    }
    let centers = items.iter().fold(Aabb::EMPTY, |b, i| Aabb {
        lo: b.lo.min(i.center),
        hi: b.hi.max(i.center),
    });
    let extent = centers.hi - centers.lo;
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    if extent[axis] <= 0.0 {
        // All centres coincide: no split separates them; halve only to bound leaf size.
        return (n > MAX_LEAF).then_some((n / 2, axis));
    }
    if median_only {
        return (n > MAX_LEAF).then(|| (median(items, axis), axis));
    }
    let Some((axis, bin, cost)) = best_sah(items, &centers) else {
        return (n > MAX_LEAF).then(|| (median(items, axis), axis));
    };
    // Cost in triangle tests, a node visit counted as one: a leaf costs n.
    if cost >= n as f64 && n <= MAX_LEAF {
        return None;
    }
    let (lo, scale) = (centers.lo[axis], BINS as f64 / extent[axis]);
    let mid = partition(items, |i| bin_of(i.center[axis], lo, scale) <= bin);
    if mid == 0 || mid == n {
        return Some((median(items, axis), axis));
    }
    Some((mid, axis))
}

fn bin_of(c: f64, lo: f64, scale: f64) -> usize {
    (((c - lo) * scale) as usize).min(BINS - 1)
}

/// The best (axis, last bin of the first part, cost) of the binned surface area heuristic.
fn best_sah(items: &[Item], centers: &Aabb) -> Option<(usize, usize, f64)> {
    let parent = items.iter().fold(Aabb::EMPTY, |b, i| b.join(i.shutter));
    let parent_area = parent.area();
    let mut best: Option<(usize, usize, f64)> = None;
    for axis in 0..3 {
        let extent = centers.hi[axis] - centers.lo[axis];
        if extent <= 0.0 {
            continue;
        }
        let (lo, scale) = (centers.lo[axis], BINS as f64 / extent);
        let mut boxes = [Aabb::EMPTY; BINS];
        let mut counts = [0usize; BINS];
        for item in items {
            let b = bin_of(item.center[axis], lo, scale);
            boxes[b] = boxes[b].join(item.shutter);
            counts[b] += 1;
        }
        // Areas and counts of the parts right of each plane, then a sweep from the left.
        let mut right_area = [0.0; BINS];
        let mut right_count = [0usize; BINS];
        let (mut acc, mut count) = (Aabb::EMPTY, 0);
        for b in (1..BINS).rev() {
            acc = acc.join(boxes[b]);
            count += counts[b];
            right_area[b] = acc.area();
            right_count[b] = count;
        }
        let (mut acc, mut count) = (Aabb::EMPTY, 0);
        for b in 0..BINS - 1 {
            acc = acc.join(boxes[b]);
            count += counts[b];
            let right = right_count[b + 1];
            if count == 0 || right == 0 {
                continue;
            }
            let cost = 1.0
                + (acc.area() * count as f64 + right_area[b + 1] * right as f64)
                    / parent_area.max(f64::MIN_POSITIVE);
            if best.is_none_or(|(_, _, c)| cost < c) {
                best = Some((axis, b, cost));
            }
        }
    }
    best
}

/// Puts the items for which `first` holds before the others; returns how many there are.
fn partition(items: &mut [Item], first: impl Fn(&Item) -> bool) -> usize {
    let mut mid = 0;
    for i in 0..items.len() {
        if first(&items[i]) {
            items.swap(i, mid);
            mid += 1;
        }
    }
    mid
}

/// Halves the items at the median centre along `axis`.
fn median(items: &mut [Item], axis: usize) -> usize {
    let mid = items.len() / 2;
    items.select_nth_unstable_by(mid, |a, b| a.center[axis].total_cmp(&b.center[axis]));
    mid
}
