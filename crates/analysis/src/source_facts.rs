//! What is known of a recording as a whole once its channels are selected
//! and moved out of it: the facts `report` lists for each input, kept with
//! the selection so that the report reads each input once.

use imu::{Problem, ReadReport, Recording};

/// A recording's device, length, rate and problems, as read.
#[derive(Debug, Clone, Default)]
pub struct RecordingFacts {
    /// The device the file names.
    pub device: Option<String>,
    /// Samples on its clock.
    pub samples: usize,
    /// The rate found (given, fitted or recorded); `None` when nothing gave
    /// one (a selection then assumes 1 Hz, and says so).
    pub rate_hz: Option<f64>,
    /// Its duration, s.
    pub duration_s: Option<f64>,
    /// The reader's problems, listed.
    pub problems: Vec<Problem>,
    /// Problems beyond those listed.
    pub unlisted: usize,
    /// The run's temperature as its metadata states it
    /// ([`TEMPERATURE_KEY`]), °C: a constant-temperature run logged
    /// without a temperature column.
    pub temperature_c: Option<f64>,
}

/// The metadata entry that states a run's temperature, °C
/// (`# temperature_c: 34` in a text log).
pub const TEMPERATURE_KEY: &str = "temperature_c";

impl RecordingFacts {
    /// The facts of `rec`, read with `report`, before any channel of it is
    /// moved out (its length is its first channel's).
    pub fn of(rec: &Recording, report: &ReadReport) -> RecordingFacts {
        RecordingFacts {
            device: rec.meta.device.clone(),
            samples: rec.len(),
            rate_hz: rec.rate_hz,
            duration_s: rec.duration_s(),
            problems: report.problems.clone(),
            unlisted: report.unlisted,
            temperature_c: rec
                .meta
                .get(TEMPERATURE_KEY)
                .and_then(|v| v.trim().parse::<f64>().ok())
                .filter(|t| t.is_finite()),
        }
    }
}
