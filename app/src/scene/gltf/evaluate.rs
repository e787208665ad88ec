//! The model posed at one time: every drawn primitive's vertices in world space.

use glam::{Mat4, Vec3};

use super::animation::{Channel, Pose, channels};
use super::geometry::{self, Geometry};
use super::hierarchy::{drawn_nodes, parents, world_matrices};
use super::options::GltfOptions;
use super::skinning::{Skin, normalize, skin_positions};
use super::source::Source;

/// One primitive drawn by one node.
pub(super) struct Instance {
    pub name: String,
    node: usize,
    pub geometry: Geometry,
    skin: Option<usize>,
    /// The node's, else the mesh's, else zero weights: used where no channel animates them.
    default_weights: Vec<f32>,
}

pub(super) struct Model {
    document: gltf::Document,
    parents: Vec<Option<usize>>,
    pub instances: Vec<Instance>,
    skins: Vec<Option<Skin>>,
    channels: Vec<Channel>,
}

/// Triangles the model's drawn primitives hold, before any subdivision.
pub(super) fn count_triangles(source: &Source) -> Result<u64, String> {
    let parents = parents(&source.document)?;
    let nodes: Vec<gltf::Node> = source.document.nodes().collect();
    let mut sum = 0u64;
    for n in drawn_nodes(&source.document, &parents) {
        if let Some(mesh) = nodes[n].mesh() {
            for p in mesh.primitives() {
                sum = sum.saturating_add(geometry::triangle_count(&p)?);
            }
        }
    }
    Ok(sum)
}

impl Model {
    pub(super) fn new(source: Source, options: &GltfOptions) -> Result<Model, String> {
        let Source { document, buffers } = source;
        let parents = parents(&document)?;
        let channels = channels(&document, &buffers, options.animation.as_ref())?;
        let nodes: Vec<gltf::Node> = document.nodes().collect();
        let mut skins: Vec<Option<Skin>> = document.skins().map(|_| None).collect();
        let mut instances = Vec::new();
        for n in drawn_nodes(&document, &parents) {
            let node = &nodes[n];
            let Some(mesh) = node.mesh() else { continue };
            let base = node
                .name()
                .or(mesh.name())
                .map_or_else(|| format!("node-{n}"), str::to_owned);
            let multiple = mesh.primitives().len() > 1;
            for primitive in mesh.primitives() {
                let context = |e: String| {
                    format!("mesh {} primitive {}: {e}", mesh.index(), primitive.index())
                };
                let mut geometry = geometry::read(&primitive, &buffers).map_err(context)?;
                let targets = geometry.targets.len();
                let default_weights = match node.weights().or(mesh.weights()) {
                    Some(w) if w.len() == targets => w.to_vec(),
                    Some(w) => {
                        return Err(context(format!(
                            "{} default morph weights for {targets} targets",
                            w.len()
                        )));
                    }
                    None => vec![0.0; targets],
                };
                let skin = match (node.skin(), geometry.influences.as_mut()) {
                    (Some(skin), Some(influences)) => {
                        let slot = &mut skins[skin.index()];
                        if slot.is_none() {
                            *slot = Some(Skin::read(&skin, &buffers)?);
                        }
                        let joints = slot.as_ref().map_or(0, |s| s.joints.len());
                        normalize(influences, joints).map_err(context)?;
                        Some(skin.index())
                    }
                    (Some(_), None) => {
                        return Err(context("skinned node without JOINTS_0/WEIGHTS_0".into()));
                    }
                    // Influences without a skin on the node are not used (specification).
                    (None, _) => None,
                };
                instances.push(Instance {
                    name: if multiple {
                        format!("{base}/{}", primitive.index())
                    } else {
                        base.clone()
                    },
                    node: n,
                    geometry,
                    skin,
                    default_weights,
                });
            }
        }
        for c in &channels {
            if c.property == gltf::animation::Property::MorphTargetWeights {
                let targets = nodes[c.node]
                    .mesh()
                    .and_then(|m| m.primitives().next())
                    .map_or(0, |p| p.morph_targets().len());
                if c.keys.width != targets {
                    return Err(format!(
                        "animation drives {} morph weights of node {}, whose mesh has {targets} targets",
                        c.keys.width, c.node
                    ));
                }
            }
        }
        Ok(Model {
            document,
            parents,
            instances,
            skins,
            channels,
        })
    }

    /// World positions of every instance's vertices at `time`, with whether each vertex's
    /// transform mirrors (negative determinant), which reverses its triangles' winding.
    pub(super) fn posed(&self, time: f32) -> Vec<(Vec<Vec3>, Vec<bool>)> {
        let pose = Pose::at(&self.document, &self.channels, time);
        let world = world_matrices(&pose, &self.parents);
        let joint_matrices: Vec<Option<Vec<Mat4>>> = self
            .skins
            .iter()
            .map(|s| s.as_ref().map(|s| s.joint_matrices(&world)))
            .collect();
        self.instances
            .iter()
            .map(|inst| {
                let g = &inst.geometry;
                let weights = pose.weights[inst.node]
                    .as_deref()
                    .unwrap_or(&inst.default_weights);
                let mut local = g.positions.clone();
                for (w, deltas) in weights.iter().zip(&g.targets) {
                    if *w != 0.0 {
                        for (p, d) in local.iter_mut().zip(deltas) {
                            *p += *w * *d;
                        }
                    }
                }
                match (inst.skin, g.influences.as_ref()) {
                    (Some(s), Some(influences)) => {
                        let matrices = joint_matrices[s].as_deref().unwrap_or_default();
                        skin_positions(&local, influences, matrices)
                    }
                    // A skinned mesh ignores its node's transform; any other takes it whole.
                    _ => {
                        let m = world[inst.node];
                        let mirrored = m.determinant() < 0.0;
                        let points = local.iter().map(|&p| m.transform_point3(p)).collect();
                        (points, vec![mirrored; local.len()])
                    }
                }
            })
            .collect()
    }
}
