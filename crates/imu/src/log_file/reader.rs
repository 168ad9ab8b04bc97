//! Reading a log (or any numeric table with a header) into a
//! [`Recording`], with everything found wrong on the way.

use std::path::Path;

use super::gaps::{RowLines, into_channels, report_whole_row_gaps};
use super::layout::{Layout, bad_metadata_rate, detected_format};
use super::time_axis::{TimeColumn, place_on_time};
use super::trailer::TRAILER_KEY;
use super::writer::KEY_RATE;
use crate::error::ReadError;
use crate::read_report::{Problem, ReadReport};
use crate::recording::{Channel, Metadata, Recording};
use crate::setting::{Setting, Value};
use crate::table::{ReadPolicy, TableReader};
use crate::units::{ColumnScale, Quantity, UnitOverride, UnitSource};

/// How to read a recording.
#[derive(Debug, Clone, Default)]
pub struct RecordingOptions {
    /// Sample rate in Hz; overrides the file's metadata.
    pub rate_hz: Option<f64>,
    /// Unit per column (by header name or imutherm name), overriding the
    /// header's: `gyro_x=deg/s`, parsed where it was given.
    pub units: Vec<UnitOverride>,
    /// Factors for columns' values, applied before their units convert
    /// them (`accel_x=4`); each is said in the report's notes.
    pub scales: Vec<ColumnScale>,
    /// The time column, by name; `None` looks for one named as
    /// [`crate::names::is_time_name`] says (`t`, `time`, `timestamp`,
    /// `stamp`, `sec`, …, with or without a unit) or with a time unit
    /// (`[s]`, `_ns`).
    pub time_column: Option<String>,
    /// Unit of the time column when its header has none: `s`, `ms`, `us`,
    /// `ns`. Without either, the unit is guessed (Unix epoch stamps by
    /// their magnitude, others by the median step) and the report's notes
    /// say so.
    pub time_unit: Option<String>,
    /// Skip malformed rows as gaps instead of failing.
    pub skip_bad_lines: bool,
    /// Which stream of a robot log (ROS bag, ULog, DataFlash) to read;
    /// a text log has one stream, and a choice given for it is refused by
    /// the readers that know streams.
    pub stream: StreamChoice,
    /// Largest time grid, as a multiple of the samples, that gaps may fill
    /// before the time column is refused as wrong; `None`:
    /// [`crate::timing::MAX_GRID_FACTOR`]. Raised for duty-cycled logs.
    pub max_grid_factor: Option<usize>,
}

/// The stream of a multi-stream log to read: `--topic`, `--instance`,
/// `--temp-topic`. Empty: the only IMU stream.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct StreamChoice {
    /// The IMU topic (ROS), or a stream name from `info`'s list.
    pub topic: Option<String>,
    /// The IMU instance (PX4, ArduPilot).
    pub instance: Option<u32>,
    /// The temperature topic (ROS).
    pub temp_topic: Option<String>,
    /// With several IMU streams and none chosen, read the first instead of
    /// refusing (for a listing of every stream).
    pub first_if_several: bool,
    /// Read a ROS 2 bag missing some of its listed files from the others,
    /// reporting the loss, instead of refusing it.
    pub allow_partial: bool,
}

impl StreamChoice {
    /// Whether anything was chosen (a text log refuses it).
    pub fn is_given(&self) -> bool {
        self.topic.is_some() || self.instance.is_some() || self.temp_topic.is_some() || self.allow_partial
    }
}

/// Which IMU instances of a log of several (PX4, ArduPilot) one read
/// assembles, each as its own IMU.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum InstancePick {
    /// The one stream the [`StreamChoice`] names.
    AsChosen,
    /// Every instance that holds samples; none for a log without
    /// instances.
    All,
    /// Every instance that holds samples where there are two or more;
    /// otherwise the one stream the choice names.
    Several,
    /// These instances.
    These(Vec<u32>),
}

/// Reads `# key: value` comment lines into metadata (other comments are
/// ignored).
pub fn parse_metadata(comments: &[String]) -> Metadata {
    let mut meta = Metadata::default();
    for c in comments {
        if let Some((k, v)) = c.split_once(':') {
            let (k, v) = (k.trim(), v.trim());
            if !k.is_empty() && !k.contains(' ') {
                match k {
                    "device" => meta.device = Some(v.to_string()),
                    "start_time" => meta.start_time = Some(v.to_string()),
                    _ => {}
                }
                meta.set(k, v);
            }
        }
    }
    meta
}

/// The sample rate written in the metadata, if any.
pub fn metadata_rate(meta: &Metadata) -> Option<f64> {
    meta.get(KEY_RATE)
        .and_then(|v| v.parse::<f64>().ok())
        .filter(|r| r.is_finite() && *r > 0.0)
}

/// Reads a thesis log, an imutherm log, or any numeric column file with a
/// header into a [`Recording`] in SI units. Problems that were recovered
/// from (a truncated last line, skipped rows, infinities made gaps, time
/// gaps) are dropped from view: use [`read_recording_with_report`] to see them.
pub fn read_recording(path: &Path, opts: &RecordingOptions) -> Result<Recording, ReadError> {
    read_recording_with_report(path, opts).map(|(rec, _)| rec)
}

/// A column that records when the host read each sample (`imutherm record
/// --host-time`). It is never taken as the time axis unless named: it
/// carries the host's scheduling jitter and the host's clock, not the
/// sensor's, and placing samples on a grid by it would invent gaps and
/// duplicates. The sample order and the NaN rows of lost stretches are the
/// record's time axis.
pub const HOST_TIME_COLUMN: &str = "host_time";

/// A rate to sensible digits: six significant figures, no trailing zeros
/// (`200.602`, not `200.60180541624874`).
pub fn round_rate(hz: f64) -> String {
    if !hz.is_finite() || hz <= 0.0 {
        return format!("{hz}");
    }
    let digits = (5 - hz.abs().log10().floor() as i32).max(0) as usize;
    let text = format!("{hz:.digits$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

/// A note when a static accelerometer read as m/s² (its unit assumed) has
/// a mean norm near 1 or 1000: the file is then in g or mg.
fn accel_unit_note(channels: &[Channel]) -> Option<String> {
    let axes: Vec<&Channel> = channels
        .iter()
        .filter(|c| c.quantity == Quantity::Acceleration && c.axis.is_some())
        .collect();
    if axes.is_empty() || axes.iter().any(|c| c.unit_source != UnitSource::Assumed) {
        return None;
    }
    let norm = axes
        .iter()
        .map(|c| {
            let (s, n) = c
                .data
                .iter()
                .filter(|v| v.is_finite())
                .fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
            if n == 0 { 0.0 } else { (s / n as f64).powi(2) }
        })
        .sum::<f64>()
        .sqrt();
    let looks = if (0.7..1.3).contains(&norm) {
        "g"
    } else if (700.0..1300.0).contains(&norm) {
        "mg"
    } else {
        return None;
    };
    Some(format!(
        "the accelerometer's unit is assumed m/s², but its mean norm is {norm:.4}: that looks like {looks}, \
         not m/s²; give {} (and y, z) or write the unit in the header",
        Setting::UnitOverride.given(Value::text(format!("accel_x={looks}")))
    ))
}

/// A note when the rate given is not the one the metadata writes: every
/// figure is then computed at the given one, and both are said.
fn rate_note(given: Option<f64>, file: Option<f64>) -> Option<String> {
    let (given, file) = (given?, file?);
    ((given / file - 1.0).abs() > 1e-3).then(|| {
        format!(
            "the file's metadata says {} Hz ('# {KEY_RATE}: {}'); {} replaces it, and every figure is computed at {} Hz",
            round_rate(file),
            round_rate(file),
            Setting::SampleRate.given(Value::number(given)),
            round_rate(given),
        )
    })
}

/// [`read_recording`], with everything found wrong on the way. NaN and
/// infinite samples become gaps; with a time column, samples are placed on
/// the grid of their timestamps (missing ones become gaps, duplicates and
/// steps backwards are dropped), and the rate is derived from it unless
/// given.
pub fn read_recording_with_report(
    path: &Path,
    opts: &RecordingOptions,
) -> Result<(Recording, ReadReport), ReadError> {
    read_recording_from(TableReader::open(path)?, opts)
}

/// [`read_recording_with_report`] from a file already opened (its header
/// read): a pipe or standard input can be read only once.
pub fn read_recording_from(
    reader: TableReader,
    opts: &RecordingOptions,
) -> Result<(Recording, ReadReport), ReadError> {
    let path = reader.path().to_path_buf();
    let Layout {
        mut meta,
        headers,
        kinds,
        time_index,
        notes,
    } = Layout::read(&reader, opts)?;
    let file_rate = metadata_rate(&meta);
    let bad_rate = bad_metadata_rate(&reader, file_rate);
    let mut table = reader.read_with(
        None,
        &ReadPolicy {
            skip_bad_lines: opts.skip_bad_lines,
        },
    )?;
    // From the stream's tail as it went by: the file is never read twice.
    if let Some(t) = table.trailer.take() {
        meta.set(TRAILER_KEY, t);
    }
    let table_columns = std::mem::take(&mut table.columns);
    let mut report = ReadReport {
        format: detected_format(&meta, &headers),
        lines: table.lines,
        rows: table_columns.first().map_or(0, Vec::len),
        ..ReadReport::default()
    };
    if let Some(p) = bad_rate {
        report.push(p);
    }
    report.notes.extend(notes);
    report.notes.extend(rate_note(opts.rate_hz, file_rate));
    for e in &table.problems {
        report.push(Problem::from_read_error(e));
    }
    let mut columns = Vec::with_capacity(headers.len());
    let mut time: Option<Vec<f64>> = None;
    for (i, data) in table_columns.into_iter().enumerate() {
        if Some(i) == time_index {
            time = Some(data);
        } else {
            columns.push((i, data));
        }
    }
    let rows = RowLines::new(&table);
    let whole_rows = report_whole_row_gaps(&columns, &rows, &mut report);
    let mut channels = into_channels(columns, &kinds, &headers, &whole_rows, &rows, &mut report);
    let mut rate_hz = opts.rate_hz.or(file_rate);
    let timestamps = match (time_index, time) {
        (Some(ti), Some(raw)) => {
            let time = TimeColumn {
                index: ti,
                raw,
                kind: &kinds[ti],
                header: &headers[ti],
            };
            Some(place_on_time(
                &path,
                time,
                opts,
                &rows,
                &mut channels,
                &mut rate_hz,
                &mut report,
            )?)
        }
        _ => None,
    };
    report.notes.extend(accel_unit_note(&channels));
    report.problems.sort_by_key(|p| p.line);
    Ok((
        Recording {
            channels,
            rate_hz,
            timestamps,
            meta,
        },
        report,
    ))
}
