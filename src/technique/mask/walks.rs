//! The visibility mask's walks on a device that leaves loops after a fixed count (lavapipe):
//! how many iterations an invocation runs before its walk stops, and how many follow-up
//! rounds go on with what stopped (`super::mask_queue`).

use super::VisibilityMaskPass;
use crate::gpu::Context;

impl VisibilityMaskPass {
    /// With `rounds` follow-up dispatches (default [`crate::technique::DEFAULT_MASK_FOLLOW_UP_ROUNDS`]) for the
    /// moving receivers' walks that a device with a loop limit stopped: each goes on with a
    /// fresh budget. Set it before making bindings (they hold a header per round). Read only
    /// on such a device (lavapipe).
    pub fn with_follow_up_rounds(self, rounds: u32) -> Self {
        Self {
            follow_up_rounds: rounds,
            ..self
        }
    }

    /// With walks that stop after about `budget` loop iterations per invocation (per lane,
    /// as [`crate::gpu::DeviceInfo::shader_loop_budget`] counts them) instead of the device's
    /// budget, and go on in the follow-up rounds: never more than the device's (a larger
    /// `budget` is the device's); on a device without a loop limit, the walks then stop and
    /// go on as they would on one. For tests of the follow-up rounds with small scenes; 0
    /// restores the device's budget.
    pub fn with_loop_budget(self, ctx: &Context, budget: u32) -> Self {
        let device = ctx.info().shader_loop_budget();
        let loop_budget = match (device, budget) {
            (_, 0) => device,
            (0, budget) => budget,
            (device, budget) => budget.min(device),
        };
        Self {
            loop_budget,
            ..self
        }
    }

    /// Follow-up rounds recorded on a device with a loop limit (0 elsewhere).
    pub(super) fn rounds(&self) -> u32 {
        if self.loop_budget > 0 {
            self.follow_up_rounds
        } else {
            0
        }
    }
}
