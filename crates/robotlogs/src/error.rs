//! What can go wrong reading a robot log, always with the file and where.

use std::path::PathBuf;

use imu::{Given, Setting, Value};

/// An error reading a robot log: the file, where in it, and what.
#[derive(Debug, thiserror::Error)]
#[error("{}{}: {kind}", path.display(), at.as_ref().map(|a| format!(" ({a})")).unwrap_or_default())]
pub struct LogError {
    /// The file (or bag directory).
    pub path: PathBuf,
    /// Where: a byte offset, a message number, a topic.
    pub at: Option<String>,
    /// What.
    pub kind: LogErrorKind,
}

/// The kinds of [`LogError`].
#[derive(Debug, thiserror::Error)]
pub enum LogErrorKind {
    /// The file could not be read.
    #[error("{0}")]
    Io(#[from] std::io::Error),
    /// The bytes do not follow the format.
    #[error("malformed {format}: {what}")]
    Malformed {
        /// The format expected.
        format: &'static str,
        /// What is wrong.
        what: String,
    },
    /// A compression the reader does not know.
    #[error("unsupported compression '{0}'")]
    Compression(String),
    /// The MCAP library's own error.
    #[error("MCAP: {0}")]
    Mcap(String),
    /// SQLite's own error.
    #[error("SQLite: {0}")]
    Sqlite(String),
    /// A SQLite3 bag larger than a read may hold in memory.
    #[error(
        "a SQLite3 bag of {} MiB is read into memory whole, more than the {} MiB a read may take",
        bytes.div_ceil(1 << 20),
        limit >> 20
    )]
    DatabaseTooLarge {
        /// The file's size.
        bytes: u64,
        /// The memory a read may take.
        limit: u64,
    },
    /// A SQLite3 bag in WAL mode whose log was never folded into it.
    #[error(
        "its write-ahead log {} holds messages not yet in the bag (the recorder did not close it); \
         open the bag once with sqlite3 to fold the log in, then read it",
        .0.display()
    )]
    UnfoldedLog(std::path::PathBuf),
    /// No IMU stream in the log.
    #[error(
        "no IMU stream (sensor_msgs Imu topic, PX4 sensor_gyro/sensor_combined, ArduPilot IMU) in the log"
    )]
    NoImuStream,
    /// Several IMU or temperature streams and none chosen.
    #[error("{count} {kind} streams; choose one with {setting}: {list}")]
    SeveralStreams {
        /// How many.
        count: usize,
        /// `IMU` or `temperature`.
        kind: &'static str,
        /// The setting that chooses one: a topic or an instance.
        setting: Setting,
        /// Each with its rate.
        list: String,
    },
    /// The chosen stream is not in the log.
    #[error("no stream {wanted} in the log; streams: {list}")]
    NoSuchStream {
        /// What was asked for.
        wanted: Given,
        /// What there is.
        list: String,
    },
    /// A stream choice given for a text log.
    #[error("{0} applies to robot logs (bags, ULog, DataFlash) only")]
    NotARobotLog(Setting),
    /// A stream choice given for input read as a text table that may hold
    /// a robot log the readers cannot look into: piped, or compressed.
    #[error(
        "{setting} applies to robot logs (bags, ULog, DataFlash), and this input is read as a text table: {why}"
    )]
    ChoiceForTextInput {
        /// The choice given.
        setting: Setting,
        /// Why the input is read as text.
        why: String,
    },
    /// The stamps give no clock at all (every one zero, NaN, equal or
    /// running backwards) and no rate was given.
    #[error(
        "the stamps of {stream} cannot time it: {detail}; give the nominal rate with {} to place the samples one per period in the log's order",
        Setting::SampleRate.given(Value::Placeholder("HZ"))
    )]
    NoClock {
        /// The stream.
        stream: String,
        /// What the stamps are.
        detail: String,
    },
    /// The samples cannot be placed on a grid (stamps far apart).
    #[error("the stamps of {0} span far more time than its samples fill: they cannot be placed on a clock")]
    BadClock(String),
    /// A sample rate was given at which the stamps' span holds far more
    /// periods than the stream has samples: the rate, not the stamps, is
    /// what is wrong.
    #[error(transparent)]
    RateTooHigh(Box<RateTooHigh>),
}

/// A given sample rate the stamps cannot hold ([`LogErrorKind::RateTooHigh`]).
#[derive(Debug, thiserror::Error)]
#[error(
    "the sample rate given, {given}, puts the {span_s:.6} s that the stamps of {stream} span on {slots:.3e} \
     periods for its {samples} samples: far more than gaps explain; give the stream's own rate, or none to take it from the stamps"
)]
pub struct RateTooHigh {
    /// The stream.
    pub stream: String,
    /// The rate as given.
    pub given: Given,
    /// The stamps' span, s.
    pub span_s: f64,
    /// Periods of the given rate in that span.
    pub slots: f64,
    /// Samples of the stream.
    pub samples: usize,
}

impl LogError {
    /// An error about `path`.
    pub fn new(path: impl Into<PathBuf>, kind: LogErrorKind) -> LogError {
        LogError {
            path: path.into(),
            at: None,
            kind,
        }
    }

    /// The same error, located.
    pub fn at(mut self, at: impl Into<String>) -> LogError {
        self.at = Some(at.into());
        self
    }
}

/// A malformed-format error.
pub(crate) fn malformed(path: &std::path::Path, format: &'static str, what: impl Into<String>) -> LogError {
    LogError::new(
        path,
        LogErrorKind::Malformed {
            format,
            what: what.into(),
        },
    )
}
