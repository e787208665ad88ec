//! What to take from a glTF model: which animation, when the shutter opens and for how long.

use serde::{Deserialize, Serialize};

/// An animation by its position in the file or by its name.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum AnimationRef {
    Index(usize),
    Name(String),
}

#[derive(Debug, Clone, PartialEq, Default)]
pub struct GltfOptions {
    /// `None`: the rest pose (the nodes' own transforms and weights), no motion.
    pub animation: Option<AnimationRef>,
    /// Animation time at shutter open, seconds; clamped to the animation's keys as glTF
    /// samplers are (no looping).
    pub time: f32,
    /// Shutter duration in seconds: the t1 positions are those at `time + shutter`.
    pub shutter: f32,
    /// Levels of midpoint (1-to-4) subdivision applied to every triangle.
    pub subdivide: u32,
}

/// A film camera's shutter angle as an exposure time: 180 degrees at 24 fps is 1/48 s.
pub fn shutter_seconds(angle_deg: f32, fps: f32) -> f32 {
    angle_deg / 360.0 / fps
}

#[cfg(test)]
mod tests {
    #[test]
    fn half_a_frame_at_24_fps_is_a_48th_of_a_second() {
        assert_eq!(super::shutter_seconds(180.0, 24.0), 1.0 / 48.0);
        assert_eq!(super::shutter_seconds(360.0, 30.0), 1.0 / 30.0);
    }
}
