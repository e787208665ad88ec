//! Linear blend skinning: each vertex is the weighted sum of its joints' matrices
//! (joint world matrix times inverse bind matrix) applied to its morphed rest position.

use glam::{Mat4, Vec3};
use gltf::accessor::Dimensions;

use super::accessor::read_floats;

/// A skin's joints and inverse bind matrices, read once and posed per time.
pub(super) struct Skin {
    pub joints: Vec<usize>,
    pub inverse_bind: Vec<Mat4>,
}

impl Skin {
    pub(super) fn read(skin: &gltf::Skin, buffers: &[Vec<u8>]) -> Result<Skin, String> {
        let joints: Vec<usize> = skin.joints().map(|j| j.index()).collect();
        let inverse_bind = match skin.inverse_bind_matrices() {
            Some(a) => read_floats(&a, buffers, "inverseBindMatrices", &[Dimensions::Mat4])?
                .chunks_exact(16)
                .map(Mat4::from_cols_slice)
                .collect(),
            None => vec![Mat4::IDENTITY; joints.len()],
        };
        if inverse_bind.len() < joints.len() {
            return Err(format!(
                "skin {} has {} joints but {} inverse bind matrices",
                skin.index(),
                joints.len(),
                inverse_bind.len()
            ));
        }
        Ok(Skin {
            joints,
            inverse_bind,
        })
    }

    /// The matrix of each joint slot for the given world matrices of all nodes.
    pub(super) fn joint_matrices(&self, world: &[Mat4]) -> Vec<Mat4> {
        self.joints
            .iter()
            .zip(&self.inverse_bind)
            .map(|(&j, ibm)| world[j] * *ibm)
            .collect()
    }
}

/// Checks every influence names an existing joint slot and that each vertex has weight,
/// then scales weights to sum 1: exporters leave sums off 1 (CesiumMan has 210 vertices
/// between 0.19 and 0.99), and an unnormalised sum would shrink the vertex toward the origin.
pub(super) fn normalize(influences: &mut [Vec<(u32, f32)>], joints: usize) -> Result<(), String> {
    for (v, list) in influences.iter_mut().enumerate() {
        if let Some(&(j, _)) = list.iter().find(|(j, _)| *j as usize >= joints) {
            return Err(format!(
                "vertex {v} uses joint {j}, but the skin has {joints} joints"
            ));
        }
        let sum: f32 = list.iter().map(|(_, w)| w).sum();
        if !(sum.is_finite() && sum > 0.0) || list.iter().any(|(_, w)| *w < 0.0) {
            return Err(format!("vertex {v} has skin weights summing to {sum}"));
        }
        for (_, w) in list.iter_mut() {
            *w /= sum;
        }
    }
    Ok(())
}

/// The blended matrix of one vertex.
pub(super) fn blend(influences: &[(u32, f32)], joint_matrices: &[Mat4]) -> Mat4 {
    influences
        .iter()
        .fold(Mat4::ZERO, |m, &(j, w)| m + joint_matrices[j as usize] * w)
}

pub(super) fn skin_positions(
    positions: &[Vec3],
    influences: &[Vec<(u32, f32)>],
    joint_matrices: &[Mat4],
) -> (Vec<Vec3>, Vec<bool>) {
    positions
        .iter()
        .zip(influences)
        .map(|(&p, inf)| {
            let m = blend(inf, joint_matrices);
            (m.transform_point3(p), m.determinant() < 0.0)
        })
        .unzip()
}
