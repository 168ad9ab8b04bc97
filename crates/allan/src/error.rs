//! The errors of the Allan engine.

use thiserror::Error;

/// Everything that can go wrong when computing a statistic.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum AllanError {
    /// A statistic name that imutherm does not know.
    #[error(
        "unknown statistic '{0}' (expected one of adev, oadev, mdev, tdev, hdev, ohdev, totdev, mtotdev, ttotdev, htotdev, theo1)"
    )]
    UnknownStat(String),
    /// A data type name that imutherm does not know.
    #[error("unknown data type '{0}' (expected freq or phase)")]
    UnknownDataType(String),
    /// A tau grid that cannot be parsed.
    #[error(
        "invalid tau list '{0}': expected octave, decade, all, many, or a comma list of positive seconds"
    )]
    InvalidTaus(String),
    /// A sample rate that is not a positive finite number.
    #[error("invalid sample rate {0} Hz: it must be positive and finite")]
    InvalidRate(f64),
    /// A confidence level outside (0, 1).
    #[error("invalid confidence level {0}: it must lie strictly between 0 and 1")]
    InvalidConfidence(f64),
    /// Too few samples for even the smallest averaging factor.
    #[error("{stat} needs at least {needed} valid samples, the series has {got}")]
    TooShort {
        /// The statistic asked for.
        stat: &'static str,
        /// How many samples it needs at the least.
        needed: usize,
        /// How many it got.
        got: usize,
    },
    /// None of the requested taus can be supported by the data.
    #[error(
        "no requested tau can be computed from {n} samples at {rate_hz} Hz with {stat} (largest averaging factor {max_m}){constraint}"
    )]
    NoUsableTau {
        /// The statistic asked for.
        stat: &'static str,
        /// Number of samples.
        n: usize,
        /// Sample rate in Hz.
        rate_hz: f64,
        /// The largest averaging factor the data supports.
        max_m: usize,
        /// What the statistic asks of a tau, with the nearest it takes
        /// (Theo1: τ = 0.75·m·τ0 with m even), or empty.
        constraint: String,
    },
    /// Gap samples (NaN) in data given to a statistic that cannot skip them.
    #[error(
        "{stat} cannot skip gaps, and the series has {count} NaN samples (first at sample {first}); use adev, oadev, mdev, tdev, hdev or ohdev"
    )]
    GapsNotSupported {
        /// The statistic asked for.
        stat: &'static str,
        /// How many NaN samples there are.
        count: usize,
        /// Index of the first one (0-based sample index).
        first: usize,
    },
    /// An infinite sample: never a gap, always a mistake upstream.
    #[error("sample {index} is infinite")]
    Infinite {
        /// 0-based index of the sample.
        index: usize,
    },
}
