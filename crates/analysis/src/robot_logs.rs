//! Robot logs (ROS 2 and ROS 1 bags, PX4 ULog, ArduPilot DataFlash) as
//! inputs of every analysis, through the `robotlogs` crate; text logs go
//! on to `imu`'s reader unchanged. The stream to read comes with the
//! reader's options ([`imu::StreamChoice`]).

use std::fs::File;
use std::io::Read;
#[cfg(feature = "robotlogs")]
use std::io::{Seek, SeekFrom};
use std::path::Path;
use std::sync::{Arc, Mutex};

use imu::log_file::read_recording_from;
use imu::table::TableReader;
use imu::{ReadReport, Recording, RecordingOptions};
use serde::Serialize;

use crate::AnalysisError;
#[cfg(feature = "robotlogs")]
use crate::channel_spec::ChannelSpec;
#[cfg(feature = "robotlogs")]
use crate::file_identity::digest_of;
use crate::file_identity::{Digesting, Fingerprint, digest};
#[cfg(feature = "robotlogs")]
use crate::selection::{Selection, checked, reader_notes, selection, take_channel};

/// A stream found in a log, as `info` lists it.
#[derive(Debug, Clone, Serialize)]
pub struct Stream {
    /// Topic, or message name and instance.
    pub name: String,
    /// What it carries (`imu`, `temperature`, …).
    pub kind: &'static str,
    /// The instance of a PX4 or ArduPilot sensor.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub instance: Option<u32>,
    /// The message type.
    pub message_type: String,
    /// How many messages it holds.
    pub messages: usize,
    /// Mean message rate over the log's span, Hz.
    pub rate_hz: Option<f64>,
    /// The rate between consecutive messages (one over their median step),
    /// Hz: the mean's equal where the stream has no gap.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub step_rate_hz: Option<f64>,
    /// Where its temperature comes from.
    #[serde(skip_serializing_if = "String::is_empty")]
    pub temperature_source: String,
    /// Whether it is the stream read.
    pub selected: bool,
}

/// The format's name when `path` is a robot log (always `None` in a build
/// without robot-log support).
pub fn format_of(path: &Path) -> Option<&'static str> {
    #[cfg(feature = "robotlogs")]
    {
        robotlogs::detect(path).map(robotlogs::Format::name)
    }
    #[cfg(not(feature = "robotlogs"))]
    {
        let _ = path;
        None
    }
}

/// Reads any recording, robot log or text log, with its report and (for a
/// robot log) every stream in it; [`crate::source::read_source`] keeps the
/// format found too.
pub fn read_recording_with_report(
    path: &Path,
    opts: &RecordingOptions,
) -> Result<(Recording, ReadReport, Vec<Stream>), AnalysisError> {
    let (rec, report, streams, _) = read_any(path, opts)?;
    Ok((rec, report, streams))
}

/// The recording, its report, its streams and, for a robot log, its
/// format's name.
pub(crate) type AnyRead = (Recording, ReadReport, Vec<Stream>, Option<&'static str>);

/// An input opened once: a robot log by its format, or a text log with its
/// header read on the one open file.
pub(crate) enum Input {
    /// A robot log, held open for its decoder.
    #[cfg(feature = "robotlogs")]
    Log(robotlogs::Log),
    /// A text log, a pipe or standard input.
    Text(TableReader),
}

#[cfg(feature = "robotlogs")]
fn choice_of(opts: &RecordingOptions) -> robotlogs::Choice {
    robotlogs::Choice {
        topic: opts.stream.topic.clone(),
        instance: opts.stream.instance,
        temp_topic: opts.stream.temp_topic.clone(),
        first_if_several: opts.stream.first_if_several,
        allow_partial: opts.stream.allow_partial,
        rate_hz: opts.rate_hz,
        max_grid_factor: opts.max_grid_factor,
    }
}

#[cfg(feature = "robotlogs")]
fn log_error(e: robotlogs::Error) -> AnalysisError {
    match e {
        robotlogs::Error::Text(e) => AnalysisError::Read(e),
        robotlogs::Error::Log(e) => AnalysisError::RobotLog(e.to_string()),
    }
}

/// Opens `path` once, telling a robot log from a text log by its first
/// bytes ([`robotlogs::open`]).
#[cfg(feature = "robotlogs")]
pub(crate) fn open(path: &Path, opts: &RecordingOptions) -> Result<Input, AnalysisError> {
    Ok(
        match robotlogs::open(path, &choice_of(opts)).map_err(log_error)? {
            robotlogs::Opened::Log(log) => Input::Log(log),
            robotlogs::Opened::Text(reader) => Input::Text(reader),
        },
    )
}

/// Opens `path` once as a text log.
#[cfg(not(feature = "robotlogs"))]
pub(crate) fn open(path: &Path, opts: &RecordingOptions) -> Result<Input, AnalysisError> {
    if opts.stream.is_given() {
        return Err(AnalysisError::NoRobotLogReaders);
    }
    Ok(Input::Text(TableReader::open(path)?))
}

/// The digest of an input read by [`open_digesting`]: known at the open
/// (a robot log), or growing as its reader reads (a text log).
pub(crate) enum Digest {
    /// Taken from the open file before its decoder reads it.
    #[cfg_attr(not(feature = "robotlogs"), allow(dead_code))]
    Known(String),
    /// Taken from the bytes as the text reader reads them.
    Reading(Arc<Mutex<Fingerprint>>),
}

impl Digest {
    /// The digest, once the input has been read to its end.
    pub(crate) fn value(self) -> String {
        match self {
            Digest::Known(d) => d,
            Digest::Reading(print) => print
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .finish(),
        }
    }
}

/// [`open`], with the digest of the input's bytes ([`crate::file_identity`])
/// taken from the same open file: a text log's as its reader reads it (a
/// pipe gives its bytes once), a robot log's from its handle, rewound after
/// for the decoder (a ULog is read by seeking, not in one pass). A directory
/// has no digest, as [`crate::file_identity::digest`] says.
pub(crate) fn open_digesting(path: &Path, opts: &RecordingOptions) -> Result<(Input, Digest), AnalysisError> {
    let file_error = |cause: std::io::Error| AnalysisError::File {
        path: path.to_path_buf(),
        cause,
    };
    let meta = std::fs::metadata(path).ok();
    if meta.as_ref().is_some_and(|m| m.is_dir()) {
        digest(path).map_err(file_error)?;
    }
    let raw: Box<dyn Read + Send> = if path == Path::new("-") {
        Box::new(std::io::stdin())
    } else {
        match File::open(path) {
            #[cfg_attr(not(feature = "robotlogs"), allow(unused_mut))]
            Ok(mut file) => {
                #[cfg(feature = "robotlogs")]
                if meta.as_ref().is_some_and(|m| m.is_file())
                    && let Some(format) = robotlogs::format::sniff(&mut file).map_err(file_error)?
                {
                    let d = digest_of(&mut file).map_err(file_error)?;
                    file.seek(SeekFrom::Start(0)).map_err(file_error)?;
                    return Ok((
                        Input::Log(robotlogs::Log::of_file(format, file)),
                        Digest::Known(d),
                    ));
                }
                Box::new(file)
            }
            // The reader names the error as it does for any command.
            Err(e) => {
                open(path, opts)?;
                return Err(file_error(e));
            }
        }
    };
    refuse_choice_for_text(path, opts)?;
    let (reader, print) = Digesting::new(raw);
    let regular_bytes = meta.filter(|m| m.is_file()).map(|m| m.len());
    let reader = TableReader::from_reader(path, Box::new(reader), regular_bytes)?;
    Ok((Input::Text(reader), Digest::Reading(print)))
}

/// Refuses a robot log's stream choice given for a text log.
fn refuse_choice_for_text(path: &Path, opts: &RecordingOptions) -> Result<(), AnalysisError> {
    #[cfg(feature = "robotlogs")]
    {
        robotlogs::refuse_choice_for_text(path, &choice_of(opts))
            .map_err(|e| log_error(robotlogs::Error::Log(e)))
    }
    #[cfg(not(feature = "robotlogs"))]
    {
        let _ = path;
        if opts.stream.is_given() {
            return Err(AnalysisError::NoRobotLogReaders);
        }
        Ok(())
    }
}

/// Reads an input [`open`] opened (`path` names a robot log's errors).
#[cfg_attr(not(feature = "robotlogs"), allow(unused_variables))]
pub(crate) fn read_input(
    path: &Path,
    input: Input,
    opts: &RecordingOptions,
) -> Result<AnyRead, AnalysisError> {
    match input {
        #[cfg(feature = "robotlogs")]
        Input::Log(log) => {
            let format = log.format();
            let r = robotlogs::read_opened(path, robotlogs::Opened::Log(log), opts, &choice_of(opts))
                .map_err(log_error)?;
            Ok(any_read(r, format))
        }
        Input::Text(reader) => {
            let (rec, report) = read_recording_from(reader, opts)?;
            Ok((rec, report, Vec::new(), None))
        }
    }
}

/// A robot log's read, with its streams as this crate lists them.
#[cfg(feature = "robotlogs")]
fn any_read(r: robotlogs::Read, format: robotlogs::Format) -> AnyRead {
    let streams = r
        .streams
        .into_iter()
        .map(|s| Stream {
            name: s.name,
            kind: s.kind,
            instance: s.instance,
            message_type: s.msg_type,
            messages: s.messages,
            rate_hz: s.rate_hz,
            step_rate_hz: s.step_rate_hz,
            temperature_source: s.temperature,
            selected: s.selected,
        })
        .collect();
    (r.recording, r.report, streams, Some(format.name()))
}

/// Opens and reads `path`, robot log or text log, once.
pub(crate) fn read_any(path: &Path, opts: &RecordingOptions) -> Result<AnyRead, AnalysisError> {
    read_input(path, open(path, opts)?, opts)
}

/// The channels of a robot log an analysis takes, in SI, as
/// [`crate::selection::read_channels`] gives them for a text log.
#[cfg(feature = "robotlogs")]
pub(crate) fn read_channels(
    file: &Path,
    log: robotlogs::Log,
    wanted: &[String],
    read: &RecordingOptions,
) -> Result<Selection, AnalysisError> {
    channels_of(file, read_input(file, Input::Log(log), read)?, wanted)
}

/// [`read_channels`] of each IMU instance `pick` asks, from one decode of
/// the log: each selection with its instance, or the one stream's with
/// `None`.
#[cfg(feature = "robotlogs")]
pub(crate) fn read_channels_each(
    file: &Path,
    log: robotlogs::Log,
    wanted: &[String],
    read: &RecordingOptions,
    pick: &imu::InstancePick,
) -> Result<Vec<(Option<u32>, Selection)>, AnalysisError> {
    let format = log.format();
    robotlogs::read_log_each(file, log, read, &choice_of(read), pick)
        .map_err(log_error)?
        .into_iter()
        .map(|(n, r)| Ok((n, channels_of(file, any_read(r, format), wanted)?)))
        .collect()
}

/// The channels `wanted` of a robot log's read, in SI.
#[cfg(feature = "robotlogs")]
fn channels_of(
    file: &Path,
    (mut rec, report, _, _): AnyRead,
    wanted: &[String],
) -> Result<Selection, AnalysisError> {
    let facts = crate::source_facts::RecordingFacts::of(&rec, &report);
    let mut notes = reader_notes(file, &report, "the messages' clock");
    let checks = checked(file, &rec, &mut notes);
    let rate_hz = rec.rate_hz.unwrap_or(1.0);
    let names: Vec<String> = rec.channels.iter().map(|c| c.name.clone()).collect();
    let inertial: Vec<usize> = (0..rec.channels.len())
        .filter(|&i| rec.channels[i].is_inertial())
        .collect();
    let mut select: Vec<usize> = if wanted.is_empty() { inertial } else { Vec::new() };
    for w in wanted {
        let group: Vec<usize> = match ChannelSpec::parse(w) {
            ChannelSpec::Group(g) => (0..rec.channels.len())
                .filter(|&i| g.holds(rec.channels[i].quantity, rec.channels[i].is_inertial()))
                .collect(),
            ChannelSpec::Named(w) => match rec
                .channels
                .iter()
                .position(|c| c.name.eq_ignore_ascii_case(&w) || c.source_name == w)
            {
                Some(i) => vec![i],
                None => {
                    return Err(AnalysisError::MissingChannel {
                        file: file.to_path_buf(),
                        what: format!("no channel '{w}' (channels: {})", names.join(", ")),
                    });
                }
            },
        };
        if group.is_empty() {
            return Err(AnalysisError::NoGroup {
                file: file.to_path_buf(),
                group: w.trim().to_string(),
                columns: names.join(", "),
            });
        }
        for i in group {
            if !select.contains(&i) {
                select.push(i);
            }
        }
    }
    let channels = select
        .into_iter()
        .map(|i| take_channel(file, i + 1, &mut rec.channels[i], rate_hz, report.lines))
        .collect();
    Ok(selection(&mut rec, channels, rate_hz, notes, checks, facts))
}
