//! The deferred mask's walks on a device with a loop limit (lavapipe): the follow-up rounds
//! and the loop budget per invocation, which tests set to reach long walks with small scenes.

use super::Renderer;
use super::deferred::DeferredPasses;
use crate::error::Result;

impl Renderer<'_> {
    /// The deferred mask's follow-up rounds on a device with a loop limit (lavapipe): how many
    /// times a moving receiver's walk that stopped goes on with a fresh budget (default
    /// [`motion_shadows::technique::DEFAULT_MASK_FOLLOW_UP_ROUNDS`]). Fewer rounds refuse
    /// frames with long paths sooner (tests use it to reach that error with small scenes).
    pub fn set_mask_follow_up_rounds(&mut self, rounds: u32) -> Result<()> {
        self.deferred_passes()?;
        if let Some(passes) = self.deferred.take() {
            self.deferred = Some(DeferredPasses {
                mask: passes.mask.with_follow_up_rounds(rounds),
                ..passes
            });
        }
        Ok(())
    }

    /// The deferred mask's loop budget per invocation (0: the device's; see
    /// [`motion_shadows::technique::VisibilityMaskPass::with_loop_budget`]): a small one makes
    /// small scenes' walks stop and go on over the follow-up rounds, as long ones do on
    /// lavapipe (tests use it).
    pub fn set_mask_loop_budget(&mut self, budget: u32) -> Result<()> {
        self.deferred_passes()?;
        if let Some(passes) = self.deferred.take() {
            self.deferred = Some(DeferredPasses {
                mask: passes.mask.with_loop_budget(self.ctx, budget),
                ..passes
            });
        }
        Ok(())
    }
}
