//! What can go wrong with a thermal analysis or a compensation.

use thiserror::Error;

/// A thermal analysis or compensation that cannot be done honestly.
#[derive(Debug, Error)]
pub enum ThermalError {
    /// The recording has no temperature channel.
    #[error("the recording has no temperature channel")]
    NoTemperature,
    /// The temperature does not vary enough for a fit.
    #[error(
        "the temperature spans only {span_c:.3} °C ({min_c:.2} to {max_c:.2} °C): nothing to fit a temperature model to"
    )]
    NoSpread {
        /// Range, °C.
        span_c: f64,
        /// Lowest temperature, °C.
        min_c: f64,
        /// Highest temperature, °C.
        max_c: f64,
    },
    /// Fewer temperature bins than the polynomial has coefficients.
    #[error(
        "{bins} temperature bins of {width_c} °C cannot determine a polynomial of order {order} (needs at least {needed})"
    )]
    TooFewBins {
        /// Bins with data.
        bins: usize,
        /// Bin width, °C.
        width_c: f64,
        /// Requested order.
        order: usize,
        /// Bins needed.
        needed: usize,
    },
    /// Too few temperature bins to hold any out for choosing the order.
    #[error(
        "{bins} temperature bins of {width_c} °C are too few to choose the polynomial order by cross-validation (it needs bins between the two ends of the range): give the order"
    )]
    TooFewBinsToChoose {
        /// Bins with data.
        bins: usize,
        /// Bin width, °C.
        width_c: f64,
    },
    /// A model applied to a recording without the channel it was fitted for.
    #[error("the model has channel '{0}', which the recording does not have")]
    MissingChannel(String),
    /// A reference temperature outside the fitted range, or not a number.
    #[error(
        "the reference temperature {t_ref_c} °C is outside the fitted range {t_min_c:.2} to {t_max_c:.2} °C: the compensation would extrapolate"
    )]
    TrefOutsideRange {
        /// Requested reference, °C.
        t_ref_c: f64,
        /// Fitted range, °C.
        t_min_c: f64,
        /// Fitted range, °C.
        t_max_c: f64,
    },
    /// Runs whose gravity points different ways: not one sensor's thermal
    /// history in one orientation, and a temperature fit across them would
    /// take the turn for a temperature slope.
    #[error(
        "gravity turns by {angle_deg:.1}° between run {first} (accel mean [{:.3}, {:.3}, {:.3}] m/s²) and run {second} ([{:.3}, {:.3}, {:.3}] m/s²), far beyond what temperature moves an accelerometer: the runs are not one orientation; fit them apart",
        first_mean[0], first_mean[1], first_mean[2], second_mean[0], second_mean[1], second_mean[2]
    )]
    GravityTurned {
        /// The runs, counted from 1.
        first: usize,
        /// The other run.
        second: usize,
        /// The angle between their mean accelerometer vectors, degrees.
        angle_deg: f64,
        /// The first run's mean accelerometer vector, m/s².
        first_mean: [f64; 3],
        /// The second's.
        second_mean: [f64; 3],
    },
    /// A model that is not a usable compensation.
    #[error(transparent)]
    Model(#[from] crate::model_check::ModelError),
    /// A parameter out of range.
    #[error("{0}")]
    Invalid(String),
    /// Time windows that cannot be cut as asked.
    #[error(transparent)]
    Windows(#[from] crate::dynamic_adev::DynamicAdevError),
    /// The Allan engine refused the data.
    #[error(transparent)]
    Allan(#[from] allan::AllanError),
}
