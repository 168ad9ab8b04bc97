//! Robot logs (ROS 2 and ROS 1 bags, PX4 ULog, ArduPilot DataFlash) as
//! inputs of every analysis, through the `robotlogs` crate; text logs go
//! on to `imu`'s reader unchanged. The stream to read comes with the
//! reader's options ([`imu::StreamChoice`]).

use std::path::Path;

use imu::{Quantity, ReadReport, Recording, RecordingOptions};
use serde::Serialize;

use crate::AnalysisError;
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
    /// Mean message rate, Hz.
    pub rate_hz: Option<f64>,
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

/// The IMU instances of a PX4 ULog or ArduPilot DataFlash log that hold
/// samples, in increasing order; empty for a log without instances (a
/// text log, a ROS bag).
pub fn imu_instances(path: &Path) -> Result<Vec<u32>, AnalysisError> {
    #[cfg(feature = "robotlogs")]
    {
        let Some(format) = robotlogs::detect(path) else {
            return Ok(Vec::new());
        };
        let d = robotlogs::decode(path, format).map_err(|e| AnalysisError::RobotLog(e.to_string()))?;
        let mut out: Vec<u32> = d
            .imu
            .iter()
            .filter(|s| !s.is_empty())
            .filter_map(|s| s.instance)
            .collect();
        out.sort_unstable();
        out.dedup();
        Ok(out)
    }
    #[cfg(not(feature = "robotlogs"))]
    {
        let _ = path;
        Ok(Vec::new())
    }
}

/// Reads any recording, robot log or text log, with its report and (for a
/// robot log) every stream in it.
pub fn read_recording_with_report(
    path: &Path,
    opts: &RecordingOptions,
) -> Result<(Recording, ReadReport, Vec<Stream>), AnalysisError> {
    #[cfg(not(feature = "robotlogs"))]
    {
        if opts.stream.is_given() {
            return Err(AnalysisError::Option(
                "--topic, --instance and --temp-topic need imutherm built with robot-log support".into(),
            ));
        }
        let (rec, rep) = imu::read_recording_with_report(path, opts)?;
        Ok((rec, rep, Vec::new()))
    }
    #[cfg(feature = "robotlogs")]
    read_any(path, opts)
}

#[cfg(feature = "robotlogs")]
fn read_any(
    path: &Path,
    opts: &RecordingOptions,
) -> Result<(Recording, ReadReport, Vec<Stream>), AnalysisError> {
    let choice = robotlogs::Choice {
        topic: opts.stream.topic.clone(),
        instance: opts.stream.instance,
        temp_topic: opts.stream.temp_topic.clone(),
        first_if_several: opts.stream.first_if_several,
        rate_hz: opts.rate_hz,
        max_grid_factor: opts.max_grid_factor,
    };
    let r = robotlogs::read(path, opts, &choice).map_err(|e| match e {
        robotlogs::Error::Text(e) => AnalysisError::Read(e),
        robotlogs::Error::Log(e) => AnalysisError::RobotLog(e.to_string()),
    })?;
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
            temperature_source: s.temperature,
            selected: s.selected,
        })
        .collect();
    Ok((r.recording, r.report, streams))
}

/// The channels of a robot log an analysis takes, in SI, as
/// [`crate::selection::read_channels`] gives them for a text log.
pub(crate) fn read_channels(
    file: &Path,
    wanted: &[String],
    read: &RecordingOptions,
) -> Result<Selection, AnalysisError> {
    let (mut rec, report, _) = read_recording_with_report(file, read)?;
    let mut notes = reader_notes(file, &report, "the messages' clock");
    let checks = checked(file, &rec, &mut notes);
    let rate_hz = rec.rate_hz.unwrap_or(1.0);
    let names: Vec<String> = rec.channels.iter().map(|c| c.name.clone()).collect();
    let inertial: Vec<usize> = (0..rec.channels.len())
        .filter(|&i| rec.channels[i].is_inertial())
        .collect();
    let of = |q: Quantity| -> Vec<usize> {
        inertial
            .iter()
            .copied()
            .filter(|&i| rec.channels[i].quantity == q)
            .collect()
    };
    let mut select: Vec<usize> = if wanted.is_empty() {
        inertial.clone()
    } else {
        Vec::new()
    };
    for w in wanted {
        let w = w.trim();
        let group: Vec<usize> = match w.to_ascii_lowercase().as_str() {
            "gyro" | "gyros" => of(Quantity::AngularRate),
            "accel" | "accels" | "acc" => of(Quantity::Acceleration),
            "inertial" | "imu" => inertial.clone(),
            "all" => (0..rec.channels.len()).collect(),
            _ => match rec
                .channels
                .iter()
                .position(|c| c.name.eq_ignore_ascii_case(w) || c.source_name == w)
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
                group: w.to_string(),
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
    Ok(selection(&mut rec, channels, rate_hz, notes, checks))
}
