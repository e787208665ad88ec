//! The visibility mask's overflow queues (issue 35): on a device that leaves a shader
//! invocation's loops after a fixed count (lavapipe), a moving receiver's walk along its path
//! through the map may need more iterations than one invocation runs. Its walk then stops
//! between two texels (the texels' time windows are disjoint, so their shares add up) and the
//! pixel joins a queue with where it stopped; follow-up dispatches, one per round, go on from
//! there with a fresh budget each, sized by the queue's count (indirect, so that an empty
//! round costs a barrier and an empty dispatch). A pixel still unfinished after the last
//! round, or (depth lines) one texel's list alone too long for an invocation, is counted over
//! budget.
//!
//! The exact lookup's walk may stop within one texel's list too (a texel may name hundreds of
//! triangles, each tested with loops of its own): it then carries that texel's union of
//! shadowed intervals so far, in a pool beside the queues.
//!
//! Layout (u32 words, mirrored in `glsl/visibility_mask.comp`): per follow-up round r = 1 ..
//! rounds, a header of 5 words (the indirect dispatch's group counts x, y, z, the count of
//! entries, the count of carried unions), then two queues of `capacity` entries of 7 words
//! each (pixel, time, texel, sum so far, limit, cursor in the texel's list, carry slot), then
//! two pools of [`carry_capacity`] unions of 16 words; round r reads queue and pool r % 2,
//! which round r - 1 wrote.

use super::gpu_constants::{
    CARRY_SHARE, CARRY_WORDS as GLSL_CARRY_WORDS, QUEUE_ENTRY_WORDS, QUEUE_HEADER_WORDS,
};
use crate::error::Result;
use crate::gpu::{Buffer, BufferUsage, Context};
use ash::vk;

/// Follow-up rounds after the mask's first dispatch, by default: each goes on with every
/// unfinished path with a fresh loop budget. Empty rounds cost a barrier and a dispatch of
/// no groups (nothing measurable on lavapipe).
pub const DEFAULT_MASK_FOLLOW_UP_ROUNDS: u32 = 32;

// The queues' layout, shared with glsl/visibility_mask.comp through the generated constants.
const HEADER_WORDS: u64 = QUEUE_HEADER_WORDS as u64;
const ENTRY_WORDS: u64 = QUEUE_ENTRY_WORDS as u64;
const CARRY_WORDS: u64 = GLSL_CARRY_WORDS as u64;
/// Word of a header holding the count of entries (after the three group counts).
const COUNT_WORD: usize = 3;

/// The queues of one dispatch in flight (one per [`super::MaskBindings`]).
pub(super) struct MaskQueue {
    buffer: Buffer,
    /// Entries per queue: the pixels of the largest mask it serves; 0 on a device without a
    /// loop limit (no walk ever stops there, and nothing is allocated beyond 4 bytes).
    capacity: u32,
    rounds: u32,
}

impl MaskQueue {
    pub const NAME: &'static str = "visibility-mask overflow queues";

    /// Queues for masks of up to `pixels` pixels and `rounds` follow-up rounds.
    pub fn new(ctx: &Context, pixels: u32, rounds: u32) -> Result<Self> {
        let words = HEADER_WORDS * u64::from(rounds)
            + 2 * ENTRY_WORDS * u64::from(pixels)
            + 2 * CARRY_WORDS * u64::from(carry_capacity(pixels));
        Ok(Self {
            buffer: Buffer::new(ctx, Self::NAME, 4 * words, BufferUsage::Storage)?,
            capacity: pixels,
            rounds,
        })
    }

    pub fn buffer(&self) -> &Buffer {
        &self.buffer
    }

    pub fn capacity(&self) -> u32 {
        self.capacity
    }

    pub fn rounds(&self) -> u32 {
        self.rounds
    }

    /// The byte offset of round `round`'s indirect dispatch (1 ..= rounds).
    pub fn groups_offset(round: u32) -> u64 {
        4 * HEADER_WORDS * u64::from(round - 1)
    }

    /// Records the headers' reset: no groups (y = z = 1) and no entries for every round. The
    /// caller orders it before the first dispatch (a transfer write).
    ///
    /// # Safety
    /// `cmd` is a command buffer of the queue's device, recording, outside a render pass;
    /// no pending command buffer uses the queue.
    pub unsafe fn record_reset(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        let headers = empty_headers(self.rounds);
        if !headers.is_empty() {
            // SAFETY: the caller's contract; the headers are the buffer's first words.
            unsafe { self.buffer.record_write(device, cmd, &headers) };
        }
    }
}

/// Carried unions per pool, for queues of `capacity` entries: an eighth of them (only exact
/// walks that stopped within a texel's list carry one; one that finds its pool full goes on
/// from the texel's start instead). `carry_capacity()` in `glsl/visibility_mask.comp`.
pub(super) fn carry_capacity(capacity: u32) -> u32 {
    capacity.div_ceil(CARRY_SHARE)
}

/// Every round's header before the first dispatch.
fn empty_headers(rounds: u32) -> Vec<u32> {
    let mut header = [0u32; HEADER_WORDS as usize];
    header[1] = 1;
    header[2] = 1;
    header[COUNT_WORD] = 0;
    header.repeat(rounds as usize)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_round_starts_with_no_groups_and_no_entries() {
        assert_eq!(empty_headers(2), vec![0, 1, 1, 0, 0, 0, 1, 1, 0, 0]);
        assert_eq!(MaskQueue::groups_offset(1), 0);
        assert_eq!(MaskQueue::groups_offset(3), 40);
    }
}
