//! Counts what the viewer allocates on the device (buffers, images, descriptor pools, the
//! map's growth), by when it happened: before and during the first frame (setup), in the
//! frames after it (must stay zero: an engine's frame allocates nothing), or on an event
//! (a resize makes the size's images again; a screenshot its readback buffer).

/// When an allocation is made.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// Start-up and the first frame.
    Setup,
    /// Every frame after the first.
    Frames,
    /// A resize or a screenshot.
    Event,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AllocationCounts {
    pub setup: u64,
    pub after_first_frame: u64,
    pub events: u64,
}

/// The counter every allocation site of the viewer goes through.
#[derive(Debug)]
pub struct AllocationCounter {
    phase: Phase,
    counts: AllocationCounts,
}

impl Default for AllocationCounter {
    fn default() -> Self {
        Self {
            phase: Phase::Setup,
            counts: AllocationCounts {
                setup: 0,
                after_first_frame: 0,
                events: 0,
            },
        }
    }
}

impl AllocationCounter {
    pub fn phase(&self) -> Phase {
        self.phase
    }

    pub fn set_phase(&mut self, phase: Phase) {
        self.phase = phase;
    }

    /// Counts `n` allocations in the current phase.
    pub fn note(&mut self, n: u64) {
        let slot = match self.phase {
            Phase::Setup => &mut self.counts.setup,
            Phase::Frames => &mut self.counts.after_first_frame,
            Phase::Event => &mut self.counts.events,
        };
        *slot += n;
    }

    /// Counts one allocation and hands back what it made.
    pub fn counted<T>(&mut self, made: T) -> T {
        self.note(1);
        made
    }

    /// Runs `f` as an event (its allocations counted there), then returns to the phase before.
    pub fn during_event<T>(&mut self, f: impl FnOnce(&mut Self) -> T) -> T {
        let before = self.phase;
        self.phase = Phase::Event;
        let result = f(self);
        self.phase = before;
        result
    }

    pub fn counts(&self) -> AllocationCounts {
        self.counts
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_by_phase_and_events_return_to_the_phase_before() {
        let mut counter = AllocationCounter::default();
        counter.note(3);
        counter.set_phase(Phase::Frames);
        counter.during_event(|c| c.note(2));
        assert_eq!(counter.phase(), Phase::Frames);
        let _: u8 = counter.counted(7);
        assert_eq!(
            counter.counts(),
            AllocationCounts {
                setup: 3,
                after_first_frame: 1,
                events: 2
            }
        );
    }
}
