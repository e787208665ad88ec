//! Where the visibility mask needs the host's triangle-id image ([`super::TriangleIdImage`]):
//! the rule [`super::VisibilityMaskPass::record`] refuses a dispatch by (issue 37).

use super::mask::MaskInputs;
use super::view::Lookup;

/// Why a dispatch of `inputs`, against a map whose last collection was for `lookup`, needs
/// the host's triangle-id image; `None` where it does not. Measured against the ray tracer
/// on a tumbling box (docs/src/deferred-frame.md#triangle-ids): on a depth-line map a moving
/// receiver's own triangle, one depth line per texel, cuts through a turning surface's path,
/// and no normal offset clears it; still receivers on still surfaces came out the same with
/// and without ids (plane test or offset), and the exact lookup's shadow ray starts past its
/// surface (its epsilon), so there the ids only spare a test.
pub(super) fn ids_required_by(inputs: &MaskInputs, lookup: Lookup) -> Option<&'static str> {
    (lookup == Lookup::DepthLine && inputs.motion.is_some()).then_some(
        "with moving receivers (MaskInputs::motion) on a depth-line map: without it a turning \
         surface's own triangle shadows it",
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::technique::{MaskInputs, MotionImage};
    use ash::vk::{self, Handle};
    use glam::Mat4;

    /// The triangle-id image is required exactly where a receiver's own triangle would
    /// otherwise shadow it (measured against the ray tracer, docs/src/deferred-frame.md#triangle-ids):
    /// on a depth-line map with moving receivers (the plane test for still pixels among
    /// them too); never on an exact map or for still receivers.
    #[test]
    fn ids_are_required_for_moving_receivers_on_depth_lines_only() {
        let view = vk::ImageView::from_raw;
        let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        let still = MaskInputs::new(view(1), read, view(2), (8, 8), Mat4::IDENTITY);
        let motion = MotionImage {
            view: view(3),
            layout: read,
        };
        let moving = still.with_motion(motion, 1.0);
        let plane_where_still = moving.with_plane_test_where_still();
        let (depth, exact) = (Lookup::DepthLine, Lookup::Exact);
        for (inputs, lookup, required) in [
            (still, depth, false),
            (moving, depth, true),
            (plane_where_still, depth, true),
            (still, exact, false),
            (moving, exact, false),
            (plane_where_still, exact, false),
        ] {
            let why = ids_required_by(&inputs, lookup);
            assert_eq!(
                why.is_some(),
                required,
                "moving {}, plane where still {}, {lookup:?}: {why:?}",
                inputs.motion.is_some(),
                inputs.plane_test_where_still
            );
        }
    }
}
