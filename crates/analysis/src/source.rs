//! One read of a recording and everything known about where it came from:
//! its format, its streams (a robot log's), how its rate was found, and
//! the reader's report (clock, units and their sources, notes). `info`,
//! the analyses and Python's `read` take this one value, so none of them
//! opens or sniffs the file again to ask what it was.

use std::path::{Path, PathBuf};

use imu::{ReadReport, Recording, RecordingOptions};

use crate::AnalysisError;
use crate::robot_logs::{Stream, read_any};

/// Where a recording's sample rate came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RateSource {
    /// The user gave it.
    Given,
    /// Fitted to a robot log's message times.
    MessageTimes,
    /// Fitted to a text log's time column.
    TimeColumn,
    /// The file's own metadata (`# sample_rate_hz:`).
    FileMetadata,
    /// Nowhere: the recording has no rate.
    Unknown,
}

impl RateSource {
    /// As `info` prints it and its JSON gives it (`rate_source`).
    pub fn name(self) -> &'static str {
        match self {
            RateSource::Given => "given",
            RateSource::MessageTimes => "derived from the message times",
            RateSource::TimeColumn => "derived from the time column",
            RateSource::FileMetadata => "file metadata",
            RateSource::Unknown => "unknown",
        }
    }
}

/// A recording as read, with what the read found out about its source.
#[derive(Debug)]
pub struct Source {
    /// The path read.
    pub path: PathBuf,
    /// The format found: a robot log's (`ULog`, `ROS 2 bag`, …) or the
    /// text reader's (`imutherm log`, `numeric columns`, …).
    pub format: &'static str,
    /// Whether it is a robot log (bag, ULog, DataFlash), whose metadata
    /// describes the stream read rather than the file.
    pub robot_log: bool,
    /// Every stream of a robot log, the read one marked; empty for a text
    /// log.
    pub streams: Vec<Stream>,
    /// Where the rate came from.
    pub rate_source: RateSource,
    /// The samples, in SI, on their clock.
    pub recording: Recording,
    /// What the reader found: problems, the clock, notes.
    pub report: ReadReport,
}

impl Source {
    /// The file's name as documents give it.
    pub fn file_name(&self) -> String {
        self.path.display().to_string()
    }
}

/// Reads `path` once, robot log or text log, into a [`Source`].
pub fn read_source(path: &Path, opts: &RecordingOptions) -> Result<Source, AnalysisError> {
    let (recording, report, streams, robot_format) = read_any(path, opts)?;
    let robot_log = robot_format.is_some();
    let rate_source = if opts.rate_hz.is_some() {
        RateSource::Given
    } else if report.timing.is_some() && robot_log {
        RateSource::MessageTimes
    } else if report.timing.is_some() {
        RateSource::TimeColumn
    } else if recording.rate_hz.is_some() {
        RateSource::FileMetadata
    } else {
        RateSource::Unknown
    };
    Ok(Source {
        path: path.to_path_buf(),
        format: robot_format.unwrap_or_else(|| report.format.name()),
        robot_log,
        streams,
        rate_source,
        recording,
        report,
    })
}
