//! Robot logs (ROS 2 and ROS 1 bags, PX4 ULog, ArduPilot DataFlash) as
//! inputs of every command that reads a recording, through the
//! `robotlogs` crate; text logs go on to `imu`'s reader unchanged.
//!
//! The stream choice (`--topic`, `--instance`, `--temp-topic`) is one of
//! the shared read flags, but the reader options every command passes on
//! are `imu`'s, which know nothing of streams: the choice is kept here
//! when the flags are turned into options, for the one run of the program.

use std::path::Path;
use std::sync::Mutex;

use anyhow::Result;

use imu::{ReadReport, Recording, RecordingOptions};

use crate::args::ReadArgs;
use crate::commands::selection::{Channel, Selection};

/// A stream found in a log, as `info` lists it.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Stream {
    pub name: String,
    pub kind: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub instance: Option<u32>,
    pub message_type: String,
    pub messages: usize,
    pub rate_hz: Option<f64>,
    #[serde(skip_serializing_if = "String::is_empty")]
    pub temperature_source: String,
    pub selected: bool,
}

/// The stream choice of the command line.
#[derive(Debug, Clone, Default)]
struct StreamChoice {
    topic: Option<String>,
    instance: Option<u32>,
    temp_topic: Option<String>,
    /// `info` lists every stream: with several, it shows the first.
    first_if_several: bool,
}

static CHOICE: Mutex<Option<StreamChoice>> = Mutex::new(None);

/// Keeps the stream flags for the readers of this run.
pub fn remember(a: &ReadArgs) {
    let mut c = CHOICE.lock().unwrap_or_else(|p| p.into_inner());
    let first_if_several = c.as_ref().is_some_and(|c| c.first_if_several);
    *c = Some(StreamChoice {
        topic: a.topic.clone(),
        instance: a.instance,
        temp_topic: a.temp_topic.clone(),
        first_if_several,
    });
}

/// For `info`: with several IMU streams and none chosen, the first is
/// summarised and every one listed, instead of an error.
pub fn list_every_stream() {
    let mut c = CHOICE.lock().unwrap_or_else(|p| p.into_inner());
    c.get_or_insert_with(StreamChoice::default).first_if_several = true;
}

fn choice() -> StreamChoice {
    CHOICE
        .lock()
        .unwrap_or_else(|p| p.into_inner())
        .clone()
        .unwrap_or_default()
}

/// The format's name when `path` is a robot log.
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
/// robot log) every stream in it.
pub fn read_recording_with_report(
    path: &Path,
    opts: &RecordingOptions,
) -> Result<(Recording, ReadReport, Vec<Stream>)> {
    let c = choice();
    #[cfg(feature = "robotlogs")]
    {
        let choice = robotlogs::Choice {
            topic: c.topic,
            instance: c.instance,
            temp_topic: c.temp_topic,
            first_if_several: c.first_if_several,
            rate_hz: opts.rate_hz,
        };
        let r = robotlogs::read(path, opts, &choice)?;
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
    #[cfg(not(feature = "robotlogs"))]
    {
        if c.topic.is_some() || c.instance.is_some() || c.temp_topic.is_some() {
            anyhow::bail!("--topic, --instance and --temp-topic need imutherm built with robot-log support");
        }
        let (rec, rep) = imu::read_recording_with_report(path, opts)?;
        Ok((rec, rep, Vec::new()))
    }
}

/// The channels of a robot log a command analyses; `None` for a text log,
/// which the caller reads itself.
pub fn read_channels(file: &Path, wanted: &[String], read: &RecordingOptions) -> Result<Option<Selection>> {
    if format_of(file).is_none() {
        return Ok(None);
    }
    let (mut rec, report, _) = read_recording_with_report(file, read)?;
    for p in &report.problems {
        eprintln!("warning: {}: {}", file.display(), p.message);
    }
    if report.unlisted > 0 {
        eprintln!(
            "warning: {}: {} more problems not listed",
            file.display(),
            report.unlisted
        );
    }
    for n in &report.notes {
        eprintln!("note: {}: {n}", file.display());
    }
    if let Some(t) = &report.timing {
        eprintln!(
            "note: {}: samples placed on the messages' clock ({} Hz, jitter {:.2e} s): {} gap{} filled with {} empty samples",
            file.display(),
            imu::log::round_rate(t.rate_hz),
            t.jitter_s,
            t.gaps.len(),
            if t.gaps.len() == 1 { "" } else { "s" },
            t.gaps.iter().map(|g| g.1).sum::<usize>(),
        );
    }
    let rate_hz = rec.rate_hz.unwrap_or(1.0);
    let names: Vec<String> = rec.channels.iter().map(|c| c.name.clone()).collect();
    let mut select: Vec<usize> = Vec::new();
    let inertial: Vec<usize> = (0..rec.channels.len())
        .filter(|&i| rec.channels[i].is_inertial())
        .collect();
    if wanted.is_empty() {
        select = inertial.clone();
    }
    for w in wanted {
        let w = w.trim();
        let group: Vec<usize> = match w.to_ascii_lowercase().as_str() {
            "gyro" | "gyros" => inertial
                .iter()
                .copied()
                .filter(|&i| rec.channels[i].quantity == imu::Quantity::AngularRate)
                .collect(),
            "accel" | "accels" | "acc" => inertial
                .iter()
                .copied()
                .filter(|&i| rec.channels[i].quantity == imu::Quantity::Acceleration)
                .collect(),
            "inertial" | "imu" => inertial.clone(),
            "all" => (0..rec.channels.len()).collect(),
            _ => match rec
                .channels
                .iter()
                .position(|c| c.name.eq_ignore_ascii_case(w) || c.source_name == w)
            {
                Some(i) => vec![i],
                None => anyhow::bail!(
                    "{}: no channel '{w}' (channels: {})",
                    file.display(),
                    names.join(", ")
                ),
            },
        };
        for i in group {
            if !select.contains(&i) {
                select.push(i);
            }
        }
    }
    let temperature = rec.temperature().map(|t| t.data.clone());
    let temperature_mean_c = temperature.as_ref().and_then(|t| {
        let (s, n) = t
            .iter()
            .filter(|v| v.is_finite())
            .fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
        (n > 0).then(|| s / n as f64)
    });
    let channels = select
        .into_iter()
        .map(|i| {
            let ch = &mut rec.channels[i];
            Channel {
                file: file.to_path_buf(),
                column: i + 1,
                name: ch.name.clone(),
                quantity: ch.quantity,
                unit: ch.unit.clone(),
                unit_source: ch.unit_source,
                rate_hz,
                lines: report.lines,
                data: std::mem::take(&mut ch.data),
            }
        })
        .collect();
    Ok(Some(Selection {
        channels,
        temperature_mean_c,
        temperature,
        rate_hz,
    }))
}
