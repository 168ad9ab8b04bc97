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

use std::fs::File;
use std::path::Path;

pub use assemble::{Choice, StreamInfo};
pub use error::{LogError, LogErrorKind, RateTooHigh};
pub use format::{Format, detect};

use imu::{InstancePick, ReadReport, Recording, RecordingOptions, Setting};

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

/// A robot log opened: its format and, for a single file, the file
/// itself at its start, which its decoder reads without opening it again.
#[derive(Debug)]
pub struct Log {
    format: Format,
    /// `None` for a bag directory, whose files are opened one by one.
    file: Option<File>,
}

impl Log {
    /// Opens `path`, a log of `format`.
    pub fn open(path: &Path, format: Format) -> Result<Log, LogError> {
        let file = match format {
            Format::Ros2BagDir => None,
            _ => Some(File::open(path).map_err(|e| LogError::new(path, e.into()))?),
        };
        Ok(Log { format, file })
    }

    /// A log of `format` in `file`, opened and at its start.
    pub fn of_file(format: Format, file: File) -> Log {
        Log {
            format,
            file: Some(file),
        }
    }

    /// `path` opened once when its content is a robot log's; `None` for
    /// anything else, the file let go unread past its first bytes.
    pub fn detect(path: &Path) -> Result<Option<Log>, LogError> {
        let io = |e: std::io::Error| LogError::new(path, e.into());
        let meta = std::fs::metadata(path).map_err(io)?;
        if meta.is_dir() {
            return Ok(detect(path).map(|format| Log { format, file: None }));
        }
        if !meta.is_file() {
            return Ok(None);
        }
        let mut file = File::open(path).map_err(io)?;
        Ok(format::sniff(&mut file).map_err(io)?.map(|format| Log {
            format,
            file: Some(file),
        }))
    }

    /// Its format.
    pub fn format(&self) -> Format {
        self.format
    }
}

/// Decodes every IMU and temperature stream of a robot log.
pub fn decode(path: &Path, format: Format) -> Result<streams::Decoded, LogError> {
    Ok(decode_log(path, Log::open(path, format)?, false)?.0)
}

/// [`decode`] of a log opened; with `allow_partial`, a bag missing some of
/// its listed files is read from the others, and the missing ones are
/// returned.
pub fn decode_log(
    path: &Path,
    log: Log,
    allow_partial: bool,
) -> Result<(streams::Decoded, Vec<format::MissingFile>), LogError> {
    let mut d = streams::Decoded::default();
    let file = match log.file {
        Some(file) if log.format != Format::Ros2BagDir => file,
        _ => return decode_bag(path, allow_partial),
    };
    match log.format {
        Format::Mcap => mcap_file::read(path, file, &mut d)?,
        Format::Sqlite => sqlite_bag::read(path, file, &mut d)?,
        Format::Ros1Bag => ros1_bag::read(path, file, &mut d)?,
        Format::ULog => ulog::read(path, file, &mut d)?,
        Format::DataFlash => dataflash::read(path, file, &mut d)?,
        Format::Ros2BagDir => {}
    }
    Ok((d, Vec::new()))
}

/// A ROS 2 bag directory: `metadata.yaml` read once, then each storage
/// file opened once, told MCAP or SQLite3 by the handle its reader reads.
fn decode_bag(
    dir: &Path,
    allow_partial: bool,
) -> Result<(streams::Decoded, Vec<format::MissingFile>), LogError> {
    let mut d = streams::Decoded::default();
    let storage = format::bag_storage(dir, allow_partial)?;
    for f in storage.present {
        let mut file = File::open(&f).map_err(|e| LogError::new(&f, e.into()))?;
        match format::sniff(&mut file).map_err(|e| LogError::new(&f, e.into()))? {
            Some(Format::Mcap) => mcap_file::read(&f, file, &mut d)?,
            Some(Format::Sqlite) => sqlite_bag::read(&f, file, &mut d)?,
            _ => {
                return Err(
                    error::malformed(dir, "ROS 2 bag", "a storage file neither MCAP nor SQLite3")
                        .at(f.display().to_string()),
                );
            }
        }
    }
    Ok((d, storage.missing))
}

/// Each storage file of a partial bag as a problem: which, and how many
/// messages the metadata says it held.
fn report_missing(missing: &[format::MissingFile], report: &mut ReadReport) {
    for m in missing {
        let held = match m.messages {
            Some(n) => format!(
                "its {n} message{} (by metadata.yaml) are not read",
                if n == 1 { "" } else { "s" }
            ),
            None => "metadata.yaml gives no message count for it".to_string(),
        };
        report.problems.push(imu::Problem {
            kind: imu::ProblemKind::SkippedData,
            line: None,
            column: None,
            channel: None,
            count: m.messages.map_or(1, |n| usize::try_from(n).unwrap_or(usize::MAX)),
            message: format!(
                "the storage file {} that metadata.yaml lists is missing, read without it as allowed: {held}",
                m.name
            ),
        });
    }
}

/// An input opened once: a robot log by the format its first bytes show,
/// or a text log with its header read, on the one open file.
pub enum Opened {
    /// A robot log (read by its decoder from the handle held).
    Log(Log),
    /// A text log, a pipe or standard input.
    Text(imu::table::TableReader),
}

/// Opens `path` once and tells a robot log from a text log by its first
/// bytes: a regular file is opened, looked at and rewound for the text
/// reader; a pipe or standard input goes to the text reader unlooked at
/// (its bytes can be read once); a directory is a ROS 2 bag or nothing. A
/// stream choice given for a text log is an error, not ignored.
pub fn open(path: &Path, choice: &Choice) -> Result<Opened, Error> {
    let text_because = |reader: Result<imu::table::TableReader, imu::ReadError>,
                        why: Option<String>|
     -> Result<Opened, Error> {
        refuse_choice_for_text(path, choice).map_err(|e| match (e.kind, why) {
            (LogErrorKind::NotARobotLog(setting), Some(why)) => {
                LogError::new(path, LogErrorKind::ChoiceForTextInput { setting, why })
            }
            (kind, _) => LogError::new(path, kind),
        })?;
        Ok(Opened::Text(reader?))
    };
    let text = |reader| text_because(reader, None);
    let Ok(meta) = std::fs::metadata(path) else {
        // Standard input, or a path the reader names the error of.
        let why = (path == Path::new("-")).then(|| {
            "standard input is read as text, once and unlooked at; give a robot log as a file".to_string()
        });
        return text_because(imu::table::TableReader::open(path), why);
    };
    if meta.is_dir() {
        return match detect(path) {
            Some(format) => Ok(Opened::Log(Log { format, file: None })),
            None => text(imu::table::TableReader::open(path)),
        };
    }
    if !meta.is_file() {
        let why = "a pipe or device is read as text, once and unlooked at; give a robot log as a file";
        return text_because(imu::table::TableReader::open(path), Some(why.to_string()));
    }
    let mut file = match File::open(path) {
        Ok(f) => f,
        Err(_) => return text(imu::table::TableReader::open(path)),
    };
    match format::sniff(&mut file) {
        Ok(Some(format)) => Ok(Opened::Log(Log {
            format,
            file: Some(file),
        })),
        Ok(None) => {
            let why = format::compressed_log(&mut file).map(|f| {
                format!(
                    "it is a gzip-compressed {}, and robot logs are read uncompressed: decompress it first",
                    f.name()
                )
            });
            text_because(imu::table::TableReader::from_file(path, file), why)
        }
        // A file that cannot be read or rewound is the text reader's to
        // name.
        Err(_) => text(imu::table::TableReader::open(path)),
    }
}

/// Refuses a stream choice given for a text log, which has one stream:
/// ignored, it would be a silent guess at what was meant.
pub fn refuse_choice_for_text(path: &Path, choice: &Choice) -> Result<(), LogError> {
    for (given, setting) in [
        (choice.topic.is_some(), Setting::Topic),
        (choice.instance.is_some(), Setting::Instance),
        (choice.temp_topic.is_some(), Setting::TempTopic),
        (choice.allow_partial, Setting::AllowPartial),
    ] {
        if given {
            return Err(LogError::new(path, LogErrorKind::NotARobotLog(setting)));
        }
    }
    Ok(())
}

/// Reads a recording from any file imutherm reads: a robot log by its
/// content, anything else as a text log. A stream choice given for a text
/// log is an error, not ignored.
pub fn read(path: &Path, opts: &RecordingOptions, choice: &Choice) -> Result<Read, Error> {
    read_opened(path, open(path, choice)?, opts, choice)
}

/// The IMU instances of a decoded log that hold samples, in increasing
/// order; empty for a log without instances (a ROS bag).
pub fn instances(d: &streams::Decoded) -> Vec<u32> {
    let mut out: Vec<u32> = d
        .imu
        .iter()
        .filter(|s| !s.is_empty())
        .filter_map(|s| s.instance)
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}

/// A robot log decoded once and assembled as `pick` asks: each instance
/// with its number, or the one stream the choice names with `None` (and
/// nothing for [`InstancePick::All`] on a log without instances). The
/// instances come from the one decode, each stream moved out of it, so a
/// log of several IMUs is neither opened, decoded nor held again for each.
pub fn read_log_each(
    path: &Path,
    log: Log,
    opts: &RecordingOptions,
    choice: &Choice,
    pick: &InstancePick,
) -> Result<Vec<(Option<u32>, Read)>, Error> {
    let format = log.format;
    let (d, missing) = decode_log(path, log, choice.allow_partial)?;
    let base = with_options(choice, opts);
    let numbers = match pick {
        InstancePick::AsChosen => Vec::new(),
        InstancePick::All => {
            let found = instances(&d);
            if found.is_empty() {
                return Ok(Vec::new());
            }
            found
        }
        InstancePick::Several => Some(instances(&d))
            .filter(|found| found.len() >= 2)
            .unwrap_or_default(),
        InstancePick::These(these) => these.clone(),
    };
    if numbers.is_empty() {
        return Ok(vec![(None, assembled(path, format, d, &missing, &base)?)]);
    }
    let choices: Vec<Choice> = numbers
        .iter()
        .map(|&n| Choice {
            instance: Some(n),
            ..base.clone()
        })
        .collect();
    let each = assemble::assemble_each(path, format.name(), d, &choices)?;
    Ok(numbers
        .into_iter()
        .zip(each)
        .map(|(n, a)| (Some(n), read_of(format, &missing, a)))
        .collect())
}

/// The choice with the rate and the grid's limit the options give, where
/// the choice gives none.
fn with_options(choice: &Choice, opts: &RecordingOptions) -> Choice {
    Choice {
        rate_hz: choice.rate_hz.or(opts.rate_hz),
        max_grid_factor: choice.max_grid_factor.or(opts.max_grid_factor),
        ..choice.clone()
    }
}

/// One stream of a decoded log, on its clock, with its report.
fn assembled(
    path: &Path,
    format: Format,
    d: streams::Decoded,
    missing: &[format::MissingFile],
    choice: &Choice,
) -> Result<Read, Error> {
    Ok(read_of(
        format,
        missing,
        assemble::assemble(path, format.name(), d, choice)?,
    ))
}

/// A stream assembled, as read: its report names the bag's missing files.
fn read_of(
    format: Format,
    missing: &[format::MissingFile],
    (recording, mut report, streams): assemble::Assembled,
) -> Read {
    report_missing(missing, &mut report);
    Read {
        recording,
        report,
        streams,
        format: Some(format),
    }
}

/// [`read`] of an input [`open`] opened.
pub fn read_opened(
    path: &Path,
    opened: Opened,
    opts: &RecordingOptions,
    choice: &Choice,
) -> Result<Read, Error> {
    match opened {
        Opened::Log(log) => {
            let format = log.format;
            let (d, missing) = decode_log(path, log, choice.allow_partial)?;
            assembled(path, format, d, &missing, &with_options(choice, opts))
        }
        Opened::Text(reader) => {
            let (recording, report) = imu::log_file::read_recording_from(reader, opts)?;
            Ok(Read {
                recording,
                report,
                streams: Vec::new(),
                format: None,
            })
        }
    }
}
