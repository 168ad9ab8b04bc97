//! What the recorder counts, and why samples were lost.

/// What the recorder counted.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub struct Counters {
    /// Samples written.
    pub samples: u64,
    /// Rows of NaN written for lost samples.
    pub gap_samples: u64,
    /// Gaps (`# gap:` lines).
    pub gaps: u64,
    /// FIFO overflows.
    pub overflows: u64,
    /// FIFO resets after a read broken off.
    pub resyncs: u64,
    /// Bus transfers that failed and were retried.
    pub bus_errors: u64,
    /// Times the sensor was configured again (stalled, or reset).
    pub reconfigurations: u64,
}

/// Why samples were lost, for the gap's comment line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Loss {
    /// The FIFO overflowed: read too late.
    Overflow,
    /// A FIFO read broke off part-way.
    PartRead,
    /// The sensor stopped delivering.
    Stalled,
    /// The sensor had lost its configuration.
    Reset,
}

impl Loss {
    /// The cause as the `# gap:` line names it.
    pub fn describe(self) -> &'static str {
        match self {
            Loss::Overflow => "FIFO overflow: read too late",
            Loss::PartRead => "a FIFO read broke off: FIFO reset to regain frame alignment",
            Loss::Stalled => "the sensor stopped delivering: reconfigured",
            Loss::Reset => "the sensor had lost its configuration (a brown-out?): configured again",
        }
    }
}
