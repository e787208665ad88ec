//! Copying the map back to the host: its counters each frame, and all of it for tests and
//! debugging.

use super::*;
use crate::technique::declared_barriers::record_own;
use crate::technique::own_barriers;

impl TemporalShadowMap {
    /// The host-visible copy of the counters.
    pub(crate) fn counters_readback(&self) -> &Buffer {
        &self.counters_readback
    }

    /// Records a copy of the counters for [`Self::read_counters`] (after the submission
    /// completes). Call after the generation pass.
    ///
    /// # Safety
    /// `cmd` was allocated from the map's device, is recording, outside any render pass; no
    /// other command buffer reads back this map's counters at the same time.
    ///
    /// Synchronization: waits for the compute stage's counter writes (the generation pass);
    /// leaves the copy visible to host reads once the submission's fence has signalled. Both
    /// barriers come from [`Self::counter_readback_accesses`]; a map made
    /// [`Self::with_host_barriers`] records neither (the caller's then).
    pub unsafe fn record_counter_readback(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        let own = own_barriers::counter_readback(self);
        let check = self.counters.access_check();
        if self.outer_barriers {
            // SAFETY: `cmd` is of the map's device, recording outside any render pass (the
            // contract); its queue runs the generation pass's compute work, so it supports the
            // compute and transfer stages.
            unsafe {
                record_own(
                    device,
                    cmd,
                    check,
                    "counter readback entry",
                    own.entry.as_ref(),
                )
            };
        }
        self.counter_readback_accesses()
            .declare_run(check, "counter readback");
        let region = [vk::BufferCopy {
            src_offset: 0,
            dst_offset: 0,
            size: COUNTER_BYTES,
        }];
        // SAFETY: both buffers are this map's, alive as long as `self` (dropping them retires them
        // past pending frames), each COUNTER_BYTES long, and the counters were made visible to
        // transfer reads just above; no other readback of this map runs at the same time (the
        // contract).
        unsafe {
            device.cmd_copy_buffer(
                cmd,
                self.counters.raw(),
                self.counters_readback.raw(),
                &region,
            )
        };
        if self.outer_barriers {
            // SAFETY: the same command buffer, outside a render pass; host reads are a valid
            // destination once the fence signals.
            unsafe {
                record_own(
                    device,
                    cmd,
                    check,
                    "counter readback exit",
                    own.exit.as_ref(),
                )
            };
        }
    }

    /// The counters copied by [`Self::record_counter_readback`], once that submission has
    /// completed.
    pub fn read_counters(&self) -> Result<Counters> {
        self.counter_read_accesses()
            .declare_run(self.counters.access_check(), "read_counters");
        Ok(self.counters_readback.read::<Counters>(1)?[0])
    }

    /// Copies the static layer back to the host (see [`ShadowMapContents::static_layer`]).
    pub fn download_static_layer(&self, ctx: &Context) -> Result<Vec<u64>> {
        if !self.buffers.static_layer {
            // No layer on this map's path: every texel holds none.
            return Ok(vec![u64::MAX; (self.width * self.height) as usize]);
        }
        download(
            ctx,
            &self.static_nearest,
            (self.width * self.height) as usize,
        )
    }

    /// Copies the whole map back to the host (for tests, heat maps and debugging).
    pub fn download(&self, ctx: &Context) -> Result<ShadowMapContents> {
        let counts = self.read_counters()?;
        let pixels = (self.width * self.height) as usize;
        // Where the collection stored the ranges itself, there are no lists (the heads held
        // the texels' run counts).
        let lists = counts.ranges_direct == 0;
        let nodes = if lists && self.buffers.nodes {
            counts.node_count.min(self.node_capacity) as usize
        } else {
            0
        };
        // Sorted ranges fill the buffer's first `sorted_count` places (fewer than the lists
        // held where some were pruned).
        let sorted = !lists && self.range_storage == RangeStorage::Sorted;
        let stored = if sorted {
            counts.sorted_count
        } else {
            counts.range_count
        };
        let ranges = stored.min(self.range_capacity) as usize;
        Ok(ShadowMapContents {
            width: self.width,
            height: self.height,
            heads: if lists {
                download(ctx, &self.heads, pixels)?
            } else {
                vec![0; pixels]
            },
            nodes: download(ctx, &self.nodes, nodes)?,
            range_heads: download(ctx, &self.range_heads, pixels)?,
            ranges: download(ctx, &self.ranges, ranges)?,
            static_layer: self.download_static_layer(ctx)?,
            static_names: match &self.static_names {
                Some(buffer) if counts.static_names > 0 => {
                    let names = counts.static_names.min(self.static_name_capacity()) as usize;
                    let header = (STATIC_NAMES_HEADER_BYTES / 4) as usize;
                    let words: Vec<u32> = download(ctx, buffer, header + pixels + 2 * names)?;
                    words[header..].to_vec()
                }
                _ => Vec::new(),
            },
        })
    }
}

/// Copies the first `count` elements of a device-local buffer to the host.
pub(crate) fn download<T: bytemuck::Pod>(
    ctx: &Context,
    buffer: &Buffer,
    count: usize,
) -> Result<Vec<T>> {
    if !buffer.is_of(ctx) {
        return Err(Error::InvalidArgument(format!(
            "{} was made with another context than the one given to copy it",
            buffer.name()
        )));
    }
    let bytes = (count * std::mem::size_of::<T>()) as u64;
    if bytes == 0 {
        return Ok(Vec::new());
    }
    let staging = Buffer::new(ctx, "download", bytes, BufferUsage::Readback)?;
    let device = ctx.device();
    OneShot::new(ctx)?.run(|cmd| {
        // SAFETY: `cmd` is the OneShot's own command buffer, recording, outside any render pass, on
        // the context's graphics and compute queue.
        unsafe {
            memory_barrier(
                device,
                cmd,
                Access::ANY_SHADER_READ
                    .and(Access::COMPUTE_RW)
                    .and(Access::FRAGMENT_RW),
                Access::TRANSFER_READ,
            )
        };
        let region = [vk::BufferCopy {
            src_offset: 0,
            dst_offset: 0,
            size: bytes,
        }];
        // SAFETY: `bytes` is within both buffers: the staging buffer was made with exactly `bytes`,
        // and every caller (all in this file) passes a count clamped to `buffer`'s capacity (per-
        // texel buffers: width x height; the others: min(count, capacity)). Both are of `ctx`
        // (checked above) and outlive the OneShot, which waits.
        unsafe { device.cmd_copy_buffer(cmd, buffer.raw(), staging.raw(), &region) };
        // SAFETY: the same OneShot command buffer, outside a render pass; host reads are a valid
        // destination once its fence signals.
        unsafe { memory_barrier(device, cmd, Access::TRANSFER_WRITE, Access::HOST_READ) };
        Ok(())
    })?;
    staging.read(count)
}
