//! The visibility mask's requirement of the subgroup vote operations.

use crate::error::{Error, Result};

/// The mask's shader votes across its subgroup (`subgroupAny`: whether the loop limiter cut a
/// lane's walk): a device without the vote operations in compute shaders is refused by name.
pub(super) fn check_subgroup_vote(has_vote: bool) -> Result<()> {
    if has_vote {
        return Ok(());
    }
    Err(Error::MissingFeatures(
        "the visibility-mask pass needs the subgroup vote operations in compute shaders \
         (VkPhysicalDeviceSubgroupProperties: VK_SUBGROUP_FEATURE_VOTE_BIT for the compute stage)"
            .into(),
    ))
}

#[cfg(test)]
mod tests {
    use super::check_subgroup_vote;

    /// Without the vote operations the pass is refused, naming what is missing.
    #[test]
    fn a_device_without_subgroup_vote_is_refused_by_name() {
        assert!(check_subgroup_vote(true).is_ok());
        let refused = check_subgroup_vote(false).expect_err("no vote, no mask");
        assert!(
            refused.to_string().contains("VK_SUBGROUP_FEATURE_VOTE_BIT"),
            "{refused}"
        );
    }
}
