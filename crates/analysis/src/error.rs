//! What can go wrong reading channels or running an analysis.

use std::path::PathBuf;

use thiserror::Error;

/// An analysis that cannot be done; the message names the file and the
/// flag or channel at fault.
#[derive(Debug, Error)]
pub enum AnalysisError {
    /// A reading option out of its domain (`--rate`, `--unit`, `--time-unit`).
    #[error("{0}")]
    Option(String),
    /// A group of channels (`gyro`, `accel`) the file does not have.
    #[error("{file}: no '{group}' channels (columns: {columns})")]
    NoGroup {
        /// The file.
        file: PathBuf,
        /// The group asked for.
        group: String,
        /// The file's columns, comma-separated.
        columns: String,
    },
    /// The time column asked for as a channel.
    #[error("{file}: column {column} ({name}) is the time column, not a channel to analyse")]
    TimeColumn {
        /// The file.
        file: PathBuf,
        /// 1-based column number.
        column: usize,
        /// Its header.
        name: String,
    },
    /// A channel an analysis needs and the file does not have.
    #[error("{file}: {what}")]
    MissingChannel {
        /// The file.
        file: PathBuf,
        /// What is missing, and what for.
        what: String,
    },
    /// Nothing to write a Kalibr file from.
    #[error("--kalibr: {0}")]
    Kalibr(String),
    /// The file could not be read.
    #[error(transparent)]
    Read(#[from] imu::ReadError),
    /// A robot log (bag, ULog, DataFlash) could not be read; the message
    /// names the file and where.
    #[error("{0}")]
    RobotLog(String),
    /// A statistic refused the data.
    #[error("{context}: {cause}")]
    Allan {
        /// The file and channel.
        context: String,
        /// The statistic's reason.
        cause: allan::AllanError,
    },
    /// A thermal analysis or compensation refused the data.
    #[error("{context}: {cause}")]
    Thermal {
        /// The file and channel, or the step.
        context: String,
        /// Its reason.
        cause: thermal::ThermalError,
    },
    /// A run that cannot be cut into the dynamic ADEV's windows.
    #[error("{context}: {cause}")]
    DynamicAdev {
        /// The file and channel.
        context: String,
        /// Its reason.
        cause: crate::dynamic_adev::DynamicAdevError,
    },
    /// Navigation refused the data.
    #[error("{context}: {cause}")]
    Ins {
        /// The file.
        context: String,
        /// Its reason.
        cause: ins::InsError,
    },
}

impl AnalysisError {
    pub(crate) fn allan(context: impl Into<String>) -> impl FnOnce(allan::AllanError) -> Self {
        let context = context.into();
        move |cause| AnalysisError::Allan { context, cause }
    }

    pub(crate) fn thermal(context: impl Into<String>) -> impl FnOnce(thermal::ThermalError) -> Self {
        let context = context.into();
        move |cause| AnalysisError::Thermal { context, cause }
    }

    pub(crate) fn dynamic_adev(
        context: impl Into<String>,
    ) -> impl FnOnce(crate::dynamic_adev::DynamicAdevError) -> Self {
        let context = context.into();
        move |cause| AnalysisError::DynamicAdev { context, cause }
    }

    pub(crate) fn ins(context: impl Into<String>) -> impl FnOnce(ins::InsError) -> Self {
        let context = context.into();
        move |cause| AnalysisError::Ins { context, cause }
    }
}
