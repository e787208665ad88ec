//! GPU timestamps between passes: `mark(cmd, "collection")` after the collection pass records
//! the time since the previous mark under that name.

use super::context::{Context, Shared};
use super::retire::{Doomed, Handle};
use crate::error::{Result, VkContext};
use ash::vk;
use std::sync::Arc;

/// A timestamp query pool with a label per mark. Timing is best effort: where the device
/// cannot time ([`Self::unsupported_reason`]), marks record nothing and there are no spans.
pub struct TimestampQueries {
    shared: Arc<Shared>,
    /// Null when timing is off.
    pool: vk::QueryPool,
    /// Why timing is off, if it is.
    off: Option<&'static str>,
    capacity: u32,
    labels: Vec<String>,
    period_ns: f64,
    valid_mask: u64,
}

impl TimestampQueries {
    /// Room for `capacity` marks. Never fails for want of timing support: see
    /// [`Self::unsupported_reason`].
    pub fn new(ctx: &Context, capacity: u32) -> Result<Self> {
        let bits = ctx.info().timestamp_valid_bits;
        let off = if !ctx.info().host_query_reset {
            Some("the device was created without hostQueryReset, which the timestamps need")
        } else if bits == 0 {
            Some("the queue has no timestamps (timestampValidBits is 0)")
        } else if capacity == 0 {
            Some("room for no marks")
        } else {
            None
        };
        if let Some(why) = off {
            log::info!("timestamps are off: {why}");
        }
        let pool = if off.is_some() {
            vk::QueryPool::null()
        } else {
            let info = vk::QueryPoolCreateInfo::default()
                .query_type(vk::QueryType::TIMESTAMP)
                .query_count(capacity);
            // SAFETY: the device is live (the context holds it) and `info` asks for `capacity`
            // timestamp queries, capacity > 0 on this branch.
            let pool =
                unsafe { ctx.device().create_query_pool(&info, None) }.vk("vkCreateQueryPool")?;
            // SAFETY: a new pool, not in use; hostQueryReset is enabled.
            unsafe { ctx.device().reset_query_pool(pool, 0, capacity) };
            pool
        };
        Ok(Self {
            shared: ctx.shared.clone(),
            pool,
            off,
            capacity,
            labels: Vec::new(),
            period_ns: ctx.info().timestamp_period_ns as f64,
            valid_mask: if bits >= 64 {
                u64::MAX
            } else {
                (1u64 << bits) - 1
            },
        })
    }

    /// Whether marks record timestamps: the queue can time (timestampValidBits > 0) and the
    /// device has hostQueryReset enabled.
    pub fn supported(&self) -> bool {
        self.off.is_none()
    }

    /// Why timing is off (no hostQueryReset, no timestamps on the queue), or `None`.
    pub fn unsupported_reason(&self) -> Option<&'static str> {
        self.off
    }

    /// Forgets earlier marks (a host-side reset of the pool).
    ///
    /// # Safety
    /// No command buffer with marks recorded from this pool is pending execution.
    pub unsafe fn clear(&mut self) {
        self.labels.clear();
        if self.off.is_some() {
            return;
        }
        // SAFETY: the caller's contract; hostQueryReset is enabled (else `off`).
        unsafe {
            self.shared
                .device
                .reset_query_pool(self.pool, 0, self.capacity)
        };
    }

    /// Records a timestamp after all earlier commands; `label` names the span since the last.
    /// Marks beyond the capacity are ignored (timing is best effort, never a failure).
    ///
    /// # Safety
    /// `cmd` is a command buffer of the context's device in the recording state, on a queue
    /// family that supports timestamps, and this object outlives its execution.
    pub unsafe fn mark(&mut self, cmd: vk::CommandBuffer, label: &str) {
        if !self.supported() || self.labels.len() as u32 >= self.capacity {
            return;
        }
        // SAFETY: the caller's contract; the query was reset (new or `clear`).
        unsafe {
            self.shared.device.cmd_write_timestamp2(
                cmd,
                vk::PipelineStageFlags2::ALL_COMMANDS,
                self.pool,
                self.labels.len() as u32,
            )
        };
        self.labels.push(label.to_owned());
    }

    /// (label, milliseconds) of each span, merged by label in first-seen order. Call after
    /// the submission has completed.
    pub fn spans_ms(&self) -> Result<Vec<(String, f64)>> {
        let n = self.labels.len();
        if n < 2 {
            return Ok(Vec::new());
        }
        let mut raw = vec![0u64; n];
        // SAFETY: `self.pool` is this device's pool with `capacity >= n` queries, and `raw` holds n
        // u64 for TYPE_64, so the driver writes within it. Queries 0..n were written by `mark`;
        // WAIT on a query that was never submitted blocks, it does not read uninitialized memory.
        unsafe {
            self.shared.device.get_query_pool_results(
                self.pool,
                0,
                &mut raw,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .vk("vkGetQueryPoolResults")?;
        let mut spans: Vec<(String, f64)> = Vec::new();
        for i in 1..n {
            let ticks = (raw[i] & self.valid_mask).wrapping_sub(raw[i - 1] & self.valid_mask)
                & self.valid_mask;
            let ms = ticks as f64 * self.period_ns / 1e6;
            match spans.iter_mut().find(|(l, _)| *l == self.labels[i]) {
                Some((_, total)) => *total += ms,
                None => spans.push((self.labels[i].clone(), ms)),
            }
        }
        Ok(spans)
    }
}

impl Drop for TimestampQueries {
    /// Retires the pool: destroyed once no pending frame can write it.
    fn drop(&mut self) {
        if self.pool != vk::QueryPool::null() {
            self.shared
                .retire(Doomed::handles(vec![Handle::QueryPool(self.pool)]));
        }
    }
}
