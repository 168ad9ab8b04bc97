//! What can be wrong with a simulation.

use thiserror::Error;

/// A simulation that cannot run as configured.
#[derive(Debug, Error)]
pub enum SimError {
    /// A parameter out of its range.
    #[error("{name} = {value}: {why}")]
    InvalidParameter {
        /// The parameter, as in the configuration (`gyro.n[0]`).
        name: String,
        /// Its value.
        value: f64,
        /// What it must be.
        why: &'static str,
    },
    /// A preset name imutherm does not know.
    #[error("unknown preset '{0}' (known: {known})", known = crate::presets::NAMES.join(", "))]
    UnknownPreset(String),
    /// A temperature profile that cannot be used.
    #[error("temperature profile: {0}")]
    Profile(String),
    /// A unit of a population that cannot be drawn as asked.
    #[error("population: {0}")]
    Population(String),
    /// A configuration file that does not parse.
    #[error("configuration: {0}")]
    Config(String),
    /// Writing the output failed. Transparent: the system's message is
    /// printed once, not once as this error and once as its source.
    #[error(transparent)]
    Io(#[from] std::io::Error),
}
