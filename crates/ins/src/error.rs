use thiserror::Error;

/// What can go wrong navigating a recording.
#[derive(Debug, Error)]
pub enum InsError {
    /// A parameter out of its domain; the message names it.
    #[error("{0}")]
    Invalid(String),
    /// The recording is shorter than one alignment window and the horizon.
    #[error(
        "{needed_s:.1} s are needed (alignment {align_s} s + horizon {horizon_s} s), the recording has {have_s:.1} s"
    )]
    TooShort {
        /// Alignment plus horizon, s.
        needed_s: f64,
        /// The alignment window, s.
        align_s: f64,
        /// The longest time navigated after it, s.
        horizon_s: f64,
        /// The recording's length, s.
        have_s: f64,
    },
    /// Every window held a gap.
    #[error("every window crosses a gap (NaN samples): none could be navigated")]
    NoWindow,
}
