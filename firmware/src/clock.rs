//! The module's monotonic clock: microseconds since boot, for frame timing in the summaries.

/// A monotonic microsecond clock (wraps after 71 minutes; differences stay right).
pub trait Monotonic {
    /// Microseconds since an arbitrary start.
    fn micros(&mut self) -> u32;
}

/// A clock that advances by a fixed step per reading (host tests).
#[derive(Debug, Default)]
pub struct StepClock {
    now: u32,
    step: u32,
}

impl StepClock {
    /// Starts at 0 and advances `step` µs per reading.
    pub fn new(step: u32) -> Self {
        Self { now: 0, step }
    }
}

impl Monotonic for StepClock {
    fn micros(&mut self) -> u32 {
        self.now = self.now.wrapping_add(self.step);
        self.now
    }
}
