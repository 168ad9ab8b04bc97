//! What can go wrong reading channels or running an analysis.

use std::path::PathBuf;

use imu::setting::and_list;
use imu::{Given, Setting, Value};
use thiserror::Error;

/// An analysis that cannot be done; the message names the file and the
/// setting or channel at fault.
#[derive(Debug, Error)]
pub enum AnalysisError {
    /// A reading setting given a value out of its domain (the sample rate,
    /// the time unit, a unit override).
    #[error("{given}: {problem}")]
    Setting {
        /// The setting and the value given.
        given: Given,
        /// What is wrong with it.
        problem: String,
    },
    /// A robot log's stream chosen in a build without the robot-log readers.
    #[error(
        "{} need imutherm built with robot-log support",
        and_list(&[Setting::Topic, Setting::Instance, Setting::TempTopic].map(|s| s.to_string()))
    )]
    NoRobotLogReaders,
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
    /// Several columns resolve to one channel, and none was named by its
    /// full header.
    #[error(
        "{file}: columns {columns} resolve to one channel, {channel}: name one by its full header with {} (e.g. {})",
        Setting::Channels,
        Setting::Channels.given(Value::Spaced(first.clone()))
    )]
    AmbiguousChannel {
        /// The file.
        file: PathBuf,
        /// The channel they resolve to.
        channel: String,
        /// The columns, numbered and named.
        columns: String,
        /// The first column's header, for the example.
        first: String,
    },
    /// A time column whose stamps give no clock, and no rate given.
    #[error(
        "{file}: the time column cannot time the samples: {detail}; give the sample rate with {}",
        Setting::SampleRate.given(Value::Placeholder("HZ"))
    )]
    NoClock {
        /// The file.
        file: PathBuf,
        /// What the stamps are.
        detail: String,
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
    #[error("{}: {}", Setting::KalibrFile, .0)]
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
    /// A compensation fit refused the runs; the context names them.
    #[error("{context}")]
    Compensation {
        /// The runs, comma-separated.
        context: String,
        /// Its reason.
        #[source]
        cause: thermal::ThermalError,
    },
    /// A model refused to compensate a channel.
    #[error(transparent)]
    Model(thermal::ThermalError),
    /// A model cannot be written for a firmware, or a parameter file is not
    /// one the firmware loads.
    #[error("{context}")]
    Firmware {
        /// The setting or file at fault.
        context: String,
        /// Its reason.
        #[source]
        cause: thermal::firmware::FirmwareError,
    },
    /// A file the compensation needs (a run's bytes, a parameter file)
    /// could not be read.
    #[error("reading {}", path.display())]
    File {
        /// The file.
        path: PathBuf,
        /// The operating system's reason.
        #[source]
        cause: std::io::Error,
    },
    /// One run given twice, by two names or as a copy: it would count
    /// twice in a fit. A usage error.
    #[error("{} and {} are the same recording: give each run once", first.display(), second.display())]
    SameRecording {
        /// The run given first.
        first: PathBuf,
        /// The same run given again.
        second: PathBuf,
    },
    /// More averaging bins than a fit is allowed.
    #[error(
        "{}: bins over {lo:.2} to {hi:.2} °C would be {bins:.0}; at most \
         {max} are fitted: give a wider bin",
        Setting::BinWidth.given(Value::number(width)),
        max = crate::compensation::MAX_FIT_BINS
    )]
    TooManyBins {
        /// The bin width, °C.
        width: f64,
        /// The lowest temperature, °C.
        lo: f64,
        /// The highest, °C.
        hi: f64,
        /// The bins that would be.
        bins: f64,
    },
    /// A polynomial order the firmware cannot evaluate. A usage error.
    #[error(
        "{} {}: {} evaluates a cubic at most ({} or {})",
        Setting::FitOrder.given(Value::number(order)),
        Setting::FitFirmware.given(Value::text(firmware.key())),
        firmware.name(),
        Setting::FitOrder.given(Value::number(3)),
        Value::text("auto")
    )]
    OrderForFirmware {
        /// The order asked for.
        order: usize,
        /// The firmware.
        firmware: thermal::firmware::Firmware,
    },
    /// A calibration slot the firmware does not have. A usage error.
    #[error(
        "{}: {} has calibration instances {} to {}",
        Setting::CalibrationSlot.given(Value::number(instance)),
        firmware.name(),
        firmware.instances().start(),
        firmware.instances().end()
    )]
    Instance {
        /// The slot asked for.
        instance: u8,
        /// The firmware.
        firmware: thermal::firmware::Firmware,
    },
    /// An IMU instance asked for that the log or the model does not hold.
    /// A usage error.
    #[error(transparent)]
    Instances(#[from] crate::tcal_instances::InstanceError),
    /// Navigation refused the data.
    #[error("{context}: {cause}")]
    Ins {
        /// The file.
        context: String,
        /// Its reason.
        cause: ins::InsError,
    },
    /// The Monte Carlo of the identified model gave no figures.
    #[error("{context}: {cause}")]
    MonteCarlo {
        /// The file.
        context: String,
        /// Its reason.
        cause: crate::monte_carlo::MonteCarloError,
    },
}

impl AnalysisError {
    /// Whether the error is in the settings given rather than in the data: the
    /// command line ends such with status 2.
    pub fn is_usage(&self) -> bool {
        matches!(
            self,
            AnalysisError::SameRecording { .. }
                | AnalysisError::OrderForFirmware { .. }
                | AnalysisError::Instance { .. }
                | AnalysisError::Instances(_)
        )
    }

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

    pub(crate) fn monte_carlo(
        context: impl Into<String>,
    ) -> impl FnOnce(crate::monte_carlo::MonteCarloError) -> Self {
        let context = context.into();
        move |cause| AnalysisError::MonteCarlo { context, cause }
    }
}
