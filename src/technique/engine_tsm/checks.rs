//! The refusals of the engine's time-dependent shadow maps: a device without D32 depth maps,
//! and a record's bad counts, sizes and times, each refused by name before anything is made or
//! recorded.

use super::{MAP_FORMAT, MAX_TSM_MAPS};
use crate::error::{Error, Result};
use ash::vk;

/// Whether a device whose optimal-tiling format features are `features` can draw, sample and
/// copy D32_SFLOAT depth maps.
pub(super) fn check_map_format(
    features: impl Fn(vk::Format) -> vk::FormatFeatureFlags,
) -> Result<()> {
    let needed = vk::FormatFeatureFlags::DEPTH_STENCIL_ATTACHMENT
        | vk::FormatFeatureFlags::SAMPLED_IMAGE
        | vk::FormatFeatureFlags::TRANSFER_SRC
        | vk::FormatFeatureFlags::TRANSFER_DST;
    if !features(MAP_FORMAT).contains(needed) {
        return Err(Error::MissingFeatures(
            "the device cannot draw, sample and copy D32_SFLOAT depth images (time-dependent shadow maps)".into(),
        ));
    }
    Ok(())
}

/// The refusals of [`super::EngineTsmPass::record`], before anything is recorded: for a mask of
/// `size` pixels, a G-buffer at `time` (read only if `moving`) and `maps` maps.
pub(super) fn check_record(size: (u32, u32), time: f32, moving: bool, maps: u32) -> Result<()> {
    if maps == 0 || maps > MAX_TSM_MAPS {
        return Err(Error::InvalidArgument(format!(
            "{maps} time-dependent shadow maps (1 to {MAX_TSM_MAPS})"
        )));
    }
    if size.0 == 0 || size.1 == 0 {
        return Err(Error::InvalidArgument(format!(
            "mask size {}x{}",
            size.0, size.1
        )));
    }
    if moving && !(0.0..=1.0).contains(&time) {
        return Err(Error::InvalidArgument(format!(
            "G-buffer time {time} (the shutter is [0, 1])"
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// No maps, too many, an empty mask or a time outside the shutter are refused by name.
    #[test]
    fn bad_counts_sizes_and_times_are_refused() {
        assert!(check_record((8, 8), 1.0, true, 1).is_ok());
        assert!(check_record((8, 8), 0.0, true, MAX_TSM_MAPS).is_ok());
        // Without a motion image the time is not read.
        assert!(check_record((8, 8), 1.5, false, 4).is_ok());
        for (what, size, time, maps) in [
            ("0 time-dependent", (8, 8), 1.0, 0),
            ("1025 time-dependent", (8, 8), 1.0, MAX_TSM_MAPS + 1),
            ("mask size 0x8", (0, 8), 1.0, 4),
            ("mask size 8x0", (8, 0), 1.0, 4),
            ("G-buffer time 1.5", (8, 8), 1.5, 4),
            ("G-buffer time NaN", (8, 8), f32::NAN, 4),
        ] {
            match check_record(size, time, true, maps) {
                Err(Error::InvalidArgument(message)) => {
                    assert!(message.contains(what), "{message}")
                }
                other => panic!("{what}: {other:?}"),
            }
        }
    }

    /// A device that cannot draw, sample or copy D32 depth maps is refused by name.
    #[test]
    fn a_device_without_d32_depth_maps_is_refused() {
        let all = vk::FormatFeatureFlags::DEPTH_STENCIL_ATTACHMENT
            | vk::FormatFeatureFlags::SAMPLED_IMAGE
            | vk::FormatFeatureFlags::TRANSFER_SRC
            | vk::FormatFeatureFlags::TRANSFER_DST;
        assert!(check_map_format(|_| all).is_ok());
        for missing in [
            vk::FormatFeatureFlags::DEPTH_STENCIL_ATTACHMENT,
            vk::FormatFeatureFlags::SAMPLED_IMAGE,
            vk::FormatFeatureFlags::TRANSFER_SRC,
        ] {
            match check_map_format(|_| all & !missing) {
                Err(Error::MissingFeatures(message)) => {
                    assert!(message.contains("D32_SFLOAT"), "{message}")
                }
                other => panic!("{missing:?}: {other:?}"),
            }
        }
    }
}
