//! The debug check of declared accesses: the validation layer cannot see reads and writes
//! made through device addresses (every buffer of the temporal shadow map), so a host that
//! leaves out a barrier it was told to issue gets no message and, on a forgiving device, no
//! wrong pixel. This check follows the declarations instead: it remembers each tracked
//! buffer's last declared use and every barrier reported since, and when a pass declares
//! its next use it asks whether a reported barrier (or a chain of them) orders the two.
//!
//! Off unless [`AccessCheck::enable`] is called: then each declared pass and barrier costs
//! a lock and a walk over the tracked buffers (a few dozen), nothing on the device. It
//! follows recording order, which it takes for the order of execution: one queue, command
//! buffers submitted in the order they were recorded. A use whose last access is the host's
//! ends a buffer's chain: the host waited for a fence before reading, which orders whatever
//! comes next.

use super::Access;
use crate::error::{Error, Result};
use ash::vk;
use std::collections::HashMap;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

/// The debug check of declared accesses (one per [`super::Context`],
/// [`super::Context::access_check`]), off until [`Self::enable`]. It remembers each library
/// buffer's last declared use (the passes declare theirs as they record; a host's shaders
/// with `PassAccesses::declare_run`) and the barriers reported since (the passes' own;
/// a host's through `Barrier::record` or [`Self::report_barrier`]), follows chains of
/// barriers, and [`Self::end_frame`] reports a use after a conflicting one (a write on either
/// side) with no barrier between as [`Error::MissingBarrier`]. It follows the order of
/// recording (one queue, command buffers submitted in the order recorded); a host read
/// ends a buffer's chain (the host waited for a fence). Cheap: a lock and a walk over the
/// tracked buffers per pass and barrier, nothing on the device.
#[derive(Default)]
pub struct AccessCheck {
    enabled: AtomicBool,
    state: Mutex<State>,
}

/// A barrier reported to the check, by whom (a pass's own entry or exit, or the host).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ReportedBarrier {
    /// Who recorded it: `"collection entry"`, `"generation exit"`, the host's label.
    pub by: String,
    /// Its source stages and accesses.
    pub before: Access,
    /// Its destination stages and accesses.
    pub after: Access,
}

/// One buffer's use by a pass, as the check takes it.
pub(crate) struct TrackedUse {
    pub buffer: vk::Buffer,
    pub name: &'static str,
    pub first: Access,
    pub last: Access,
    pub writes: bool,
}

#[derive(Default)]
struct State {
    buffers: HashMap<vk::Buffer, Tracked>,
    log: Vec<ReportedBarrier>,
    missing: Vec<Error>,
}

struct Tracked {
    pass: String,
    last: Access,
    writes: bool,
    /// What the barriers reported since `last` make it visible to: the destinations of
    /// every chain that starts at `last`.
    reached: Access,
}

/// Whether the stages `outer` include every stage of `inner`.
fn holds(outer: vk::PipelineStageFlags2, inner: vk::PipelineStageFlags2) -> bool {
    outer.contains(vk::PipelineStageFlags2::ALL_COMMANDS) || outer.contains(inner)
}

const WRITES: vk::AccessFlags2 = vk::AccessFlags2::from_raw(
    vk::AccessFlags2::SHADER_WRITE.as_raw()
        | vk::AccessFlags2::SHADER_STORAGE_WRITE.as_raw()
        | vk::AccessFlags2::TRANSFER_WRITE.as_raw()
        | vk::AccessFlags2::COLOR_ATTACHMENT_WRITE.as_raw()
        | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE.as_raw()
        | vk::AccessFlags2::HOST_WRITE.as_raw()
        | vk::AccessFlags2::MEMORY_WRITE.as_raw(),
);

/// Whether `outer` names every access of `inner` (the generic MEMORY and SHADER bits
/// standing for the specific ones).
fn holds_access(outer: vk::AccessFlags2, inner: vk::AccessFlags2) -> bool {
    let mut outer = outer;
    if outer.contains(vk::AccessFlags2::MEMORY_READ) {
        outer |= vk::AccessFlags2::from_raw(!WRITES.as_raw());
    }
    if outer.contains(vk::AccessFlags2::MEMORY_WRITE) {
        outer |= WRITES;
    }
    if outer.contains(vk::AccessFlags2::SHADER_READ) {
        outer |= vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_SAMPLED_READ;
    }
    if outer.contains(vk::AccessFlags2::SHADER_WRITE) {
        outer |= vk::AccessFlags2::SHADER_STORAGE_WRITE;
    }
    outer.contains(inner)
}

fn describe(pass: &str, a: Access) -> String {
    format!("{pass} ({:?}: {:?})", a.stages, a.access)
}

impl AccessCheck {
    /// Turns the check on (for the context's life).
    pub fn enable(&self) {
        self.enabled.store(true, Ordering::Relaxed);
    }

    /// Whether the check is on.
    pub fn is_enabled(&self) -> bool {
        self.enabled.load(Ordering::Relaxed)
    }

    fn state(&self) -> std::sync::MutexGuard<'_, State> {
        // A panic while the lock was held left at worst a stale entry: keep checking.
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Reports a global memory barrier recorded (by the host, or by a pass for its own
    /// entry or exit) from `before` to `after`, labelled `by`. The barrier must have been
    /// recorded at this point of the recording order.
    pub fn report_barrier(&self, by: &str, before: Access, after: Access) {
        if !self.is_enabled() {
            return;
        }
        let mut state = self.state();
        state.log.push(ReportedBarrier {
            by: by.to_owned(),
            before,
            after,
        });
        for t in state.buffers.values_mut() {
            let starts = holds(before.stages, t.last.stages)
                && (!t.writes || holds_access(before.access, t.last.access & WRITES));
            // A chain: this barrier's first scope meets an earlier one's second.
            let continues = t.reached.stages.intersects(before.stages)
                || (t
                    .reached
                    .stages
                    .contains(vk::PipelineStageFlags2::ALL_COMMANDS)
                    && !before.stages.is_empty());
            if starts || continues {
                t.reached = t.reached.and(after);
            }
        }
    }

    /// A pass (named `pass`) runs with these uses: each is checked against its buffer's
    /// last declared use, then becomes it.
    pub(crate) fn pass_runs(&self, pass: &str, uses: &[TrackedUse]) {
        if !self.is_enabled() {
            return;
        }
        let mut state = self.state();
        let State {
            buffers, missing, ..
        } = &mut *state;
        for u in uses {
            let Some(t) = buffers.get_mut(&u.buffer) else {
                buffers.insert(
                    u.buffer,
                    Tracked {
                        pass: pass.to_owned(),
                        last: u.last,
                        writes: u.writes,
                        reached: Access::NONE,
                    },
                );
                continue;
            };
            let fenced = t.last.stages.contains(vk::PipelineStageFlags2::HOST);
            if !fenced && (t.writes || u.writes) {
                let ordered = holds(t.reached.stages, u.first.stages)
                    && (!t.writes || holds_access(t.reached.access, u.first.access));
                if !ordered {
                    missing.push(Error::MissingBarrier {
                        resource: u.name.to_owned(),
                        previous: describe(&t.pass, t.last),
                        next: describe(pass, u.first),
                    });
                }
            }
            if !fenced && !t.writes && !u.writes {
                // Reads after reads: a later writer waits for both.
                t.last = t.last.and(u.last);
            } else {
                t.last = u.last;
            }
            t.pass = pass.to_owned();
            t.writes = u.writes;
            t.reached = Access::NONE;
        }
    }

    /// Forgets a destroyed buffer (its handle may come back for another).
    pub(crate) fn forget(&self, buffer: vk::Buffer) {
        if self.is_enabled() {
            self.state().buffers.remove(&buffer);
        }
    }

    /// Ends a frame: the first declared use since the last call that came after a
    /// conflicting one with no reported barrier between them, as
    /// [`Error::MissingBarrier`] naming the buffer and both accesses (and how many more
    /// there were); Ok when there was none or the check is off.
    pub fn end_frame(&self) -> Result<()> {
        let mut missing = std::mem::take(&mut self.state().missing);
        if missing.is_empty() {
            return Ok(());
        }
        let more = missing.len() - 1;
        let first = missing.swap_remove(0);
        if more > 0 {
            log::error!("{more} more missing barrier(s) after: {first}");
        }
        Err(first)
    }

    /// The barriers reported since the last call, in order (an empty list when off).
    pub fn take_barrier_log(&self) -> Vec<ReportedBarrier> {
        std::mem::take(&mut self.state().log)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ash::vk::Handle;

    fn used(first: Access, last: Access, writes: bool) -> TrackedUse {
        TrackedUse {
            buffer: vk::Buffer::from_raw(7),
            name: "ranges",
            first,
            last,
            writes,
        }
    }

    fn check() -> AccessCheck {
        let c = AccessCheck::default();
        c.enable();
        c
    }

    #[test]
    fn a_write_then_a_read_needs_a_barrier_naming_both_sides() {
        let c = check();
        c.pass_runs(
            "generation",
            &[used(Access::COMPUTE_RW, Access::COMPUTE_RW, true)],
        );
        c.pass_runs(
            "lighting",
            &[used(Access::HOST_READ, Access::HOST_READ, false)],
        );
        match c.end_frame() {
            Err(Error::MissingBarrier {
                resource,
                previous,
                next,
            }) => {
                assert_eq!(resource, "ranges");
                assert!(
                    previous.starts_with("generation (COMPUTE_SHADER"),
                    "{previous}"
                );
                assert!(next.starts_with("lighting (HOST"), "{next}");
            }
            other => panic!("{other:?}"),
        }
        c.end_frame().expect("reported once");
    }

    #[test]
    fn a_chain_of_barriers_orders_a_write_before_a_read() {
        let c = check();
        let fragment_read = Access {
            stages: vk::PipelineStageFlags2::FRAGMENT_SHADER,
            access: vk::AccessFlags2::SHADER_STORAGE_READ,
        };
        c.pass_runs(
            "generation",
            &[used(Access::COMPUTE_RW, Access::COMPUTE_RW, true)],
        );
        // Compute to transfer, then transfer to fragment: a chain through the transfer stage.
        c.report_barrier("one", Access::COMPUTE_RW, Access::TRANSFER_WRITE);
        c.report_barrier("two", Access::TRANSFER_WRITE, fragment_read);
        c.pass_runs("lighting", &[used(fragment_read, fragment_read, false)]);
        c.end_frame().expect("the chain orders them");
        // Without the first, nothing starts at the compute write: no chain.
        let c = check();
        c.pass_runs(
            "generation",
            &[used(Access::COMPUTE_RW, Access::COMPUTE_RW, true)],
        );
        c.report_barrier("two", Access::TRANSFER_WRITE, fragment_read);
        c.report_barrier("unrelated", Access::HOST_READ, fragment_read);
        c.pass_runs("lighting", &[used(fragment_read, fragment_read, false)]);
        let report = c
            .end_frame()
            .expect_err("no barrier starts at the compute write");
        assert!(report.to_string().contains("lighting"), "{report}");
    }

    #[test]
    fn a_barrier_without_the_write_access_does_not_order_a_write() {
        let c = check();
        c.pass_runs(
            "generation",
            &[used(Access::COMPUTE_RW, Access::COMPUTE_RW, true)],
        );
        let compute_read = Access {
            stages: vk::PipelineStageFlags2::COMPUTE_SHADER,
            access: vk::AccessFlags2::SHADER_STORAGE_READ,
        };
        c.report_barrier("execution only", compute_read, Access::TRANSFER_READ);
        c.pass_runs(
            "readback",
            &[used(Access::TRANSFER_READ, Access::TRANSFER_READ, false)],
        );
        let report = c.end_frame().expect_err("the write was not made available");
        assert!(report.to_string().contains("readback"), "{report}");
    }

    #[test]
    fn off_it_records_nothing() {
        let c = AccessCheck::default();
        c.pass_runs(
            "generation",
            &[used(Access::COMPUTE_RW, Access::COMPUTE_RW, true)],
        );
        c.pass_runs(
            "lighting",
            &[used(Access::HOST_READ, Access::HOST_READ, false)],
        );
        c.report_barrier("x", Access::COMPUTE_RW, Access::HOST_READ);
        c.end_frame().expect("off");
        assert!(c.take_barrier_log().is_empty());
    }
}
