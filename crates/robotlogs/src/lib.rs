//! # robotlogs — IMU recordings from robot and flight-controller logs
//!
//! Reads the IMU of a ROS 2 bag (MCAP or SQLite3, a directory with
//! `metadata.yaml` or a bare `.mcap`), a ROS 1 bag (format 2.0), a PX4
//! ULog or an ArduPilot DataFlash log into an [`imu::Recording`] in SI
//! (rad/s, m/s², °C), recognised by content. The chosen stream's times go
//! through [`imu::timing`] as a text log's time column does: the clock's
//! rate fitted, gaps sized and reported, nothing dropped in silence.
//!
//! [`read`] is the one entry point: anything that is not a robot log is
//! read by [`imu::read_recording_with_report`].
//!
//! Messages are decoded as they are read (a chunk or a record at a time);
//! what is kept is the decoded samples of the IMU and temperature streams.

pub mod assemble;
pub mod dataflash;
pub mod error;
pub mod format;
pub mod inflate;
pub mod mcap_file;
pub mod ros1_bag;
pub mod ros_msgs;
pub mod sqlite_bag;
pub mod streams;
pub mod ulog;

use std::path::Path;

pub use assemble::{Choice, StreamInfo};
pub use error::{LogError, LogErrorKind};
pub use format::{Format, detect};

use imu::{ReadReport, Recording, RecordingOptions};

/// A recording read, with what the log holds.
#[derive(Debug, Clone)]
pub struct Read {
    /// The chosen stream, in SI, on its clock.
    pub recording: Recording,
    /// What reading found (gaps, notes on the time source).
    pub report: ReadReport,
    /// Every stream of the log; empty for a text log.
    pub streams: Vec<StreamInfo>,
    /// The robot-log format; `None` for a text log.
    pub format: Option<Format>,
}

/// An error of either reader.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A robot log.
    #[error(transparent)]
    Log(#[from] LogError),
    /// A text log.
    #[error(transparent)]
    Text(#[from] imu::ReadError),
}

/// Decodes every IMU and temperature stream of a robot log.
pub fn decode(path: &Path, format: Format) -> Result<streams::Decoded, LogError> {
    let mut d = streams::Decoded::default();
    match format {
        Format::Ros2BagDir => {
            let files = format::bag_files(path)?;
            for f in files {
                match format::detect(&f) {
                    Some(Format::Mcap) => mcap_file::read(&f, &mut d)?,
                    Some(Format::Sqlite) => sqlite_bag::read(&f, &mut d)?,
                    _ => {
                        return Err(error::malformed(
                            path,
                            "ROS 2 bag",
                            "a storage file neither MCAP nor SQLite3",
                        )
                        .at(f.display().to_string()));
                    }
                }
            }
        }
        Format::Mcap => mcap_file::read(path, &mut d)?,
        Format::Sqlite => sqlite_bag::read(path, &mut d)?,
        Format::Ros1Bag => ros1_bag::read(path, &mut d)?,
        Format::ULog => ulog::read(path, &mut d)?,
        Format::DataFlash => dataflash::read(path, &mut d)?,
    }
    Ok(d)
}

/// Reads a recording from any file imutherm reads: a robot log by its
/// content, anything else as a text log. A stream choice given for a text
/// log is an error, not ignored.
pub fn read(path: &Path, opts: &RecordingOptions, choice: &Choice) -> Result<Read, Error> {
    match detect(path) {
        Some(format) => {
            let d = decode(path, format)?;
            let choice = Choice {
                rate_hz: choice.rate_hz.or(opts.rate_hz),
                max_grid_factor: choice.max_grid_factor.or(opts.max_grid_factor),
                ..choice.clone()
            };
            let (recording, report, streams) = assemble::assemble(path, format.name(), d, &choice)?;
            Ok(Read {
                recording,
                report,
                streams,
                format: Some(format),
            })
        }
        None => {
            for (given, flag) in [
                (choice.topic.is_some(), "--topic"),
                (choice.instance.is_some(), "--instance"),
                (choice.temp_topic.is_some(), "--temp-topic"),
            ] {
                if given {
                    return Err(LogError::new(path, LogErrorKind::NotARobotLog(flag)).into());
                }
            }
            let (recording, report) = imu::read_recording_with_report(path, opts)?;
            Ok(Read {
                recording,
                report,
                streams: Vec::new(),
                format: None,
            })
        }
    }
}
