//! A primitive's rest geometry: positions, triangles (strips and fans converted), morph
//! target deltas and skin influences, all checked against the vertex count.

use glam::Vec3;
use gltf::accessor::Dimensions;
use gltf::mesh::Mode;

use super::accessor::{read_floats, read_integers};

pub(super) struct Geometry {
    pub positions: Vec<Vec3>,
    /// Vertex numbers, three per triangle, counter-clockwise in the primitive's frame.
    pub triangles: Vec<u32>,
    /// One list of POSITION deltas per morph target.
    pub targets: Vec<Vec<Vec3>>,
    /// Per vertex, every (joint slot, weight) of all JOINTS_n/WEIGHTS_n sets.
    pub influences: Option<Vec<Influences>>,
}

/// One vertex's (joint slot, weight) pairs.
pub(super) type Influences = Vec<(u32, f32)>;

fn vec3s(flat: Vec<f32>) -> Vec<Vec3> {
    flat.chunks_exact(3)
        .map(|c| Vec3::new(c[0], c[1], c[2]))
        .collect()
}

/// Triangles of the primitive, without reading anything but the index accessor: used to
/// count a model's triangles before building it.
pub(super) fn triangle_count(primitive: &gltf::Primitive) -> Result<u64, String> {
    let n = match primitive.indices() {
        Some(a) => a.count(),
        None => primitive
            .get(&gltf::Semantic::Positions)
            .map_or(0, |a| a.count()),
    } as u64;
    match primitive.mode() {
        Mode::Triangles => Ok(n / 3),
        Mode::TriangleStrip | Mode::TriangleFan => Ok(n.saturating_sub(2)),
        other => Err(format!(
            "primitive mode {other:?} is not supported (only TRIANGLES, TRIANGLE_STRIP and \
             TRIANGLE_FAN)"
        )),
    }
}

pub(super) fn read(primitive: &gltf::Primitive, buffers: &[Vec<u8>]) -> Result<Geometry, String> {
    let position = primitive
        .get(&gltf::Semantic::Positions)
        .ok_or("primitive has no POSITION attribute")?;
    let positions = vec3s(read_floats(
        &position,
        buffers,
        "POSITION",
        &[Dimensions::Vec3],
    )?);
    let n = positions.len();
    let order: Vec<u32> = match primitive.indices() {
        Some(a) => read_integers(&a, buffers, "indices", &[Dimensions::Scalar])?,
        None => (0..n as u32).collect(),
    };
    if let Some(&bad) = order.iter().find(|&&i| i as usize >= n) {
        return Err(format!("vertex index {bad} out of range ({n} vertices)"));
    }
    let triangles = match primitive.mode() {
        Mode::Triangles => order[..order.len() / 3 * 3].to_vec(),
        // Every other strip triangle is listed clockwise; swapping its first two vertices
        // keeps the strip's winding (specification, 3.7.2.1).
        Mode::TriangleStrip => (0..order.len().saturating_sub(2))
            .flat_map(|i| {
                let (a, b) = if i % 2 == 0 { (i, i + 1) } else { (i + 1, i) };
                [order[a], order[b], order[i + 2]]
            })
            .collect(),
        Mode::TriangleFan => (0..order.len().saturating_sub(2))
            .flat_map(|i| [order[i + 1], order[i + 2], order[0]])
            .collect(),
        _ => return Err(triangle_count(primitive).unwrap_err()),
    };
    let mut targets = Vec::new();
    for (k, target) in primitive.morph_targets().enumerate() {
        let deltas = match target.positions() {
            Some(a) => vec3s(read_floats(
                &a,
                buffers,
                "morph target POSITION",
                &[Dimensions::Vec3],
            )?),
            // A target that moves only normals or colours leaves positions alone.
            None => vec![Vec3::ZERO; n],
        };
        if deltas.len() != n {
            return Err(format!(
                "morph target {k} has {} positions, not {n}",
                deltas.len()
            ));
        }
        targets.push(deltas);
    }
    Ok(Geometry {
        positions,
        triangles,
        targets,
        influences: influences(primitive, buffers, n)?,
    })
}

fn influences(
    primitive: &gltf::Primitive,
    buffers: &[Vec<u8>],
    n: usize,
) -> Result<Option<Vec<Influences>>, String> {
    let mut out: Option<Vec<Influences>> = None;
    for set in 0.. {
        let joints = primitive.get(&gltf::Semantic::Joints(set));
        let weights = primitive.get(&gltf::Semantic::Weights(set));
        let (joints, weights) = match (joints, weights) {
            (Some(j), Some(w)) => (j, w),
            (None, None) => break,
            _ => return Err(format!("JOINTS_{set} and WEIGHTS_{set} must come together")),
        };
        let j = read_integers(&joints, buffers, "JOINTS", &[Dimensions::Vec4])?;
        let w = read_floats(&weights, buffers, "WEIGHTS", &[Dimensions::Vec4])?;
        if j.len() != 4 * n || w.len() != 4 * n {
            return Err(format!(
                "JOINTS_{set}/WEIGHTS_{set} do not have {n} elements"
            ));
        }
        let all = out.get_or_insert_with(|| vec![Vec::new(); n]);
        for (v, list) in all.iter_mut().enumerate() {
            for c in 4 * v..4 * v + 4 {
                if w[c] != 0.0 {
                    list.push((j[c], w[c]));
                }
            }
        }
    }
    Ok(out)
}
