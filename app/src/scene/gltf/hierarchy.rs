//! World transforms of the node hierarchy, and which nodes a scene draws.

use glam::Mat4;

use super::animation::Pose;

/// Each node's parent, checking the tree the specification requires (one parent per node,
/// no cycles), because a cycle would otherwise loop forever below.
pub(super) fn parents(document: &gltf::Document) -> Result<Vec<Option<usize>>, String> {
    let mut parent = vec![None; document.nodes().len()];
    for node in document.nodes() {
        for child in node.children() {
            if parent[child.index()].replace(node.index()).is_some() {
                return Err(format!("node {} has more than one parent", child.index()));
            }
        }
    }
    for start in 0..parent.len() {
        let (mut at, mut steps) = (start, 0);
        while let Some(p) = parent[at] {
            at = p;
            steps += 1;
            if steps > parent.len() {
                return Err(format!("node {start} is part of a cycle of children"));
            }
        }
    }
    Ok(parent)
}

/// World matrix of every node in `pose` (parents before children via memoised recursion
/// over the checked parent links).
pub(super) fn world_matrices(pose: &Pose, parents: &[Option<usize>]) -> Vec<Mat4> {
    let mut world: Vec<Option<Mat4>> = vec![None; parents.len()];
    for node in 0..parents.len() {
        // Walk up to the nearest node already known, then fill in downwards.
        let mut chain = vec![node];
        while let Some(p) = parents[*chain.last().unwrap()] {
            if world[p].is_some() {
                break;
            }
            chain.push(p);
        }
        for &n in chain.iter().rev() {
            if world[n].is_none() {
                let above = parents[n].and_then(|p| world[p]).unwrap_or(Mat4::IDENTITY);
                world[n] = Some(above * pose.local(n));
            }
        }
    }
    world
        .into_iter()
        .map(|m| m.unwrap_or(Mat4::IDENTITY))
        .collect()
}

/// The nodes the model draws: those of its default scene (or its first), or, in a file with
/// no scenes, every root node. Depth first, in file order.
pub(super) fn drawn_nodes(document: &gltf::Document, parents: &[Option<usize>]) -> Vec<usize> {
    let roots: Vec<usize> = match document
        .default_scene()
        .or_else(|| document.scenes().next())
    {
        Some(scene) => scene.nodes().map(|n| n.index()).collect(),
        None => (0..parents.len())
            .filter(|&n| parents[n].is_none())
            .collect(),
    };
    let nodes: Vec<gltf::Node> = document.nodes().collect();
    let mut out = Vec::new();
    let mut stack: Vec<usize> = roots.into_iter().rev().collect();
    while let Some(n) = stack.pop() {
        out.push(n);
        stack.extend(
            nodes[n]
                .children()
                .map(|c| c.index())
                .collect::<Vec<_>>()
                .into_iter()
                .rev(),
        );
    }
    out
}
