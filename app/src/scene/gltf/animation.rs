//! Choosing an animation and reading its channels into keyframes once, so the two shutter
//! times are sampled from the same data.

use glam::{Quat, Vec3};
use gltf::animation::Property;

use super::accessor::read_floats;
use super::options::AnimationRef;
use super::sampler::{Interpolation, Keyframes};
use gltf::accessor::Dimensions;

pub(super) struct Channel {
    pub node: usize,
    pub property: Property,
    pub keys: Keyframes,
}

/// The chosen animation's channels; `None` chosen means the rest pose (no channels).
pub(super) fn channels(
    document: &gltf::Document,
    buffers: &[Vec<u8>],
    chosen: Option<&AnimationRef>,
) -> Result<Vec<Channel>, String> {
    let Some(chosen) = chosen else {
        return Ok(Vec::new());
    };
    let animation = find(document, chosen)?;
    let mut out = Vec::new();
    for (i, channel) in animation.channels().enumerate() {
        let sampler = channel.sampler();
        // The gltf crate's validation does not look at a channel's target path, and
        // `Target::property` unwraps it: an unknown path would panic there.
        let path = &document.as_json().animations[animation.index()].channels[i]
            .target
            .path;
        let gltf::json::validation::Checked::Valid(property) = *path else {
            return Err(format!(
                "animation {} channel {i}: its target path is not translation, rotation, \
                 scale or weights",
                animation.index()
            ));
        };
        let path = match property {
            Property::Translation => "translation",
            Property::Rotation => "rotation",
            Property::Scale => "scale",
            Property::MorphTargetWeights => "weights",
        };
        let label = |i: usize| format!("animation {} channel {i} ({path})", animation.index());
        let interpolation = match sampler.interpolation() {
            gltf::animation::Interpolation::Step => Interpolation::Step,
            gltf::animation::Interpolation::Linear => Interpolation::Linear,
            gltf::animation::Interpolation::CubicSpline => Interpolation::CubicSpline,
        };
        let times = read_floats(
            &sampler.input(),
            buffers,
            "animation input",
            &[Dimensions::Scalar],
        )?;
        let (shape, width) = match property {
            Property::Translation | Property::Scale => (Dimensions::Vec3, Some(3)),
            Property::Rotation => (Dimensions::Vec4, Some(4)),
            Property::MorphTargetWeights => (Dimensions::Scalar, None),
        };
        let values = read_floats(&sampler.output(), buffers, "animation output", &[shape])?;
        let keys = Keyframes::new(times, values, interpolation, width)
            .and_then(|k| match property {
                Property::Rotation => k.check_rotations().map(|()| k),
                _ => Ok(k),
            })
            .map_err(|e| format!("{}: {e}", label(i)))?;
        out.push(Channel {
            node: channel.target().node().index(),
            property,
            keys,
        });
    }
    Ok(out)
}

fn find<'a>(
    document: &'a gltf::Document,
    chosen: &AnimationRef,
) -> Result<gltf::Animation<'a>, String> {
    let available = || {
        let names: Vec<String> = document
            .animations()
            .map(|a| match a.name() {
                Some(n) => format!("{n:?}"),
                None => format!("#{} (unnamed)", a.index()),
            })
            .collect();
        if names.is_empty() {
            "the file has no animations".to_owned()
        } else {
            format!("available: {}", names.join(", "))
        }
    };
    let found = match chosen {
        AnimationRef::Index(i) => document.animations().nth(*i),
        AnimationRef::Name(name) => document.animations().find(|a| a.name() == Some(name)),
    };
    found.ok_or_else(|| {
        let what = match chosen {
            AnimationRef::Index(i) => format!("animation index {i}"),
            AnimationRef::Name(n) => format!("animation {n:?}"),
        };
        format!("{what} not found ({})", available())
    })
}

/// Every node's local transform and morph weights at one time: the node's own values,
/// overridden by whatever the channels animate.
#[derive(Debug, Clone)]
pub(super) struct Pose {
    pub translation: Vec<Vec3>,
    pub rotation: Vec<Quat>,
    pub scale: Vec<Vec3>,
    /// Animated morph weights, where a channel drives them.
    pub weights: Vec<Option<Vec<f32>>>,
    /// Nodes given as a matrix that no channel animates keep it verbatim (it may shear or
    /// mirror in ways a decomposition would lose).
    pub matrix: Vec<Option<glam::Mat4>>,
}

impl Pose {
    pub(super) fn at(document: &gltf::Document, channels: &[Channel], time: f32) -> Pose {
        let n = document.nodes().len();
        let mut pose = Pose {
            translation: vec![Vec3::ZERO; n],
            rotation: vec![Quat::IDENTITY; n],
            scale: vec![Vec3::ONE; n],
            weights: vec![None; n],
            matrix: vec![None; n],
        };
        for node in document.nodes() {
            let i = node.index();
            match node.transform() {
                gltf::scene::Transform::Matrix { matrix } => {
                    let m = glam::Mat4::from_cols_array_2d(&matrix);
                    pose.matrix[i] = Some(m);
                    let (s, r, t) = m.to_scale_rotation_translation();
                    (pose.scale[i], pose.rotation[i], pose.translation[i]) = (s, r, t);
                }
                gltf::scene::Transform::Decomposed {
                    translation,
                    rotation,
                    scale,
                } => {
                    pose.translation[i] = Vec3::from(translation);
                    pose.rotation[i] = Quat::from_array(rotation).normalize();
                    pose.scale[i] = Vec3::from(scale);
                }
            }
        }
        for c in channels {
            let rotation = c.property == Property::Rotation;
            let v = c.keys.sample(time, rotation);
            // The specification forbids animating a node given as a matrix; if a file does,
            // the animated parts win over the matrix.
            if c.property != Property::MorphTargetWeights {
                pose.matrix[c.node] = None;
            }
            match c.property {
                Property::Translation => pose.translation[c.node] = Vec3::new(v[0], v[1], v[2]),
                Property::Scale => pose.scale[c.node] = Vec3::new(v[0], v[1], v[2]),
                Property::Rotation => {
                    pose.rotation[c.node] = Quat::from_xyzw(v[0], v[1], v[2], v[3])
                }
                Property::MorphTargetWeights => pose.weights[c.node] = Some(v),
            }
        }
        pose
    }

    pub(super) fn local(&self, node: usize) -> glam::Mat4 {
        self.matrix[node].unwrap_or_else(|| {
            glam::Mat4::from_scale_rotation_translation(
                self.scale[node],
                self.rotation[node],
                self.translation[node],
            )
        })
    }
}
