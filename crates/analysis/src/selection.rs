//! Which channels of a file an analysis takes, read in SI with their gaps.

use std::path::{Path, PathBuf};

use imu::log_file::{ColumnKind, classify_with_overrides, read_recording_from};
use imu::{Quantity, RecordingOptions, Setting};

use crate::AnalysisError;
use crate::channel_checks::{self, Checks};
use crate::channel_spec::ChannelSpec;
use crate::robot_logs::Input;
use crate::source_facts::RecordingFacts;

/// One column to analyse (a file's column as selected, not the data
/// model's [`imu::Channel`]).
#[derive(Clone)]
pub struct SelectedChannel {
    /// The file it is read from.
    pub file: PathBuf,
    /// 1-based column number in the file.
    pub column: usize,
    /// imutherm's name (`gyro_x`) or the header's.
    pub name: String,
    /// What it measures.
    pub quantity: Quantity,
    /// Unit of `data` (SI for known quantities).
    pub unit: String,
    /// Where the file's unit came from; `Assumed` is printed beside it.
    pub unit_source: imu::UnitSource,
    /// Sample rate, Hz.
    pub rate_hz: f64,
    /// Lines in the file, to say where the data ended.
    pub lines: u64,
    /// The samples, NaN at gaps.
    pub data: Vec<f64>,
}

/// The channels read from one file, and what else a command needs of it.
#[derive(Clone)]
pub struct Selection {
    /// The selected channels.
    pub channels: Vec<SelectedChannel>,
    /// Mean of the file's temperature channel, °C.
    pub temperature_mean_c: Option<f64>,
    /// The file's temperature channel, °C, sample by sample.
    pub temperature: Option<Vec<f64>>,
    /// Sample rate, Hz.
    pub rate_hz: f64,
    /// The device ids the recording gives its gyro and accelerometer
    /// (PX4 ULog `sensor_gyro`/`sensor_accel` `device_id`, a text log's
    /// `# device_id:` for both), which flight stacks match calibrations by.
    pub device_ids: DeviceIds,
    /// What the reader found and did, one line each (`warning: …`,
    /// `note: …`), for the caller to show: an analysis never rests on
    /// filled or dropped samples unsaid. The checks' findings are among
    /// them.
    pub notes: Vec<String>,
    /// What the file's inertial channels rule out (all of them, selected
    /// or not: motion shows on any axis).
    pub checks: Checks,
    /// The recording's device, length, rate and problems, as read.
    pub recording: RecordingFacts,
}

/// Reads the wanted channels of one file, converted to SI, with gaps where
/// the file has them.
pub fn read_channels(
    file: &Path,
    wanted: &[String],
    read: &RecordingOptions,
) -> Result<Selection, AnalysisError> {
    read_opened(file, crate::robot_logs::open(file, read)?, wanted, read)
}

/// [`read_channels`], with the digest of the file's bytes
/// ([`crate::file_identity::digest`]) taken from the same read: the file is
/// opened once, and a pipe works.
pub fn read_channels_digested(
    file: &Path,
    wanted: &[String],
    read: &RecordingOptions,
) -> Result<(Selection, String), AnalysisError> {
    let (input, digest) = crate::robot_logs::open_digesting(file, read)?;
    let selection = read_opened(file, input, wanted, read)?;
    Ok((selection, digest.value()))
}

/// Selections of one read, each with its IMU instance, or `None` for the
/// one stream read.
pub type EachSelection = Vec<(Option<u32>, Selection)>;

/// [`read_channels_digested`] of each IMU instance `pick` asks: a log of
/// several IMUs is opened and decoded once for all of them. Each selection
/// comes with its instance, or with `None` for the one stream read; a text
/// log has no instances, so [`imu::InstancePick::All`] gives nothing for it
/// (its body unread, and its digest then that of its header alone).
/// A choice of instances for a text log is refused as by
/// [`read_channels_digested`] when `read` names one.
pub fn read_channels_digested_each(
    file: &Path,
    wanted: &[String],
    read: &RecordingOptions,
    pick: &imu::InstancePick,
) -> Result<(EachSelection, String), AnalysisError> {
    let (input, digest) = crate::robot_logs::open_digesting(file, read)?;
    let each = match input {
        #[cfg(feature = "robotlogs")]
        Input::Log(log) => crate::robot_logs::read_channels_each(file, log, wanted, read, pick)?,
        Input::Text(_) if *pick == imu::InstancePick::All => Vec::new(),
        input => vec![(None, read_opened(file, input, wanted, read)?)],
    };
    Ok((each, digest.value()))
}

/// [`read_channels`] of an input opened.
#[cfg_attr(not(feature = "robotlogs"), allow(clippy::infallible_destructuring_match))]
fn read_opened(
    file: &Path,
    input: Input,
    wanted: &[String],
    read: &RecordingOptions,
) -> Result<Selection, AnalysisError> {
    // A robot log goes to its reader; a text log's header alone decides
    // what is selected, before the body is read.
    let reader = match input {
        #[cfg(feature = "robotlogs")]
        Input::Log(log) => return crate::robot_logs::read_channels(file, log, wanted, read),
        Input::Text(reader) => reader,
    };
    let headers = reader.names().to_vec();
    let kinds: Vec<ColumnKind> = headers
        .iter()
        .map(|h| classify_with_overrides(h, &read.units))
        .collect();
    let inertial: Vec<usize> = (0..kinds.len()).filter(|&i| kinds[i].axis.is_some()).collect();
    let mut select: Vec<usize> = Vec::new();
    // Columns the user named by their full header.
    let mut by_header: Vec<usize> = Vec::new();
    if wanted.is_empty() {
        select = if inertial.is_empty() {
            (0..kinds.len())
                .filter(|&i| kinds[i].quantity != Quantity::Time)
                .collect()
        } else {
            inertial.clone()
        };
    }
    for w in wanted {
        let found = match ChannelSpec::parse(w) {
            ChannelSpec::Group(g) => {
                let members: Vec<usize> = (0..kinds.len())
                    .filter(|&i| g.holds(kinds[i].quantity, kinds[i].axis.is_some()))
                    .collect();
                if members.is_empty() {
                    return Err(AnalysisError::NoGroup {
                        file: file.to_path_buf(),
                        group: w.trim().to_string(),
                        columns: headers.join(", "),
                    });
                }
                members
            }
            ChannelSpec::Named(w) => {
                let w = w.as_str();
                // A full header names its column, whatever else resolves
                // to the same channel.
                match headers.iter().position(|h| h == w) {
                    Some(i) => {
                        by_header.push(i);
                        vec![i]
                    }
                    None => {
                        let same: Vec<usize> = (0..kinds.len())
                            .filter(|&i| kinds[i].name.eq_ignore_ascii_case(w))
                            .collect();
                        if same.is_empty() {
                            vec![reader.column_index(w)?]
                        } else {
                            same
                        }
                    }
                }
            }
        };
        for i in found {
            if !select.contains(&i) {
                select.push(i);
            }
        }
    }
    refuse_ambiguity(file, &headers, &kinds, &select, &by_header)?;
    // The same reader goes on to the body: a pipe or `-` is read once.
    let (mut rec, report) = read_recording_from(reader, read)?;
    let facts = RecordingFacts::of(&rec, &report);
    let mut notes = reader_notes(file, &report, "the time column's clock");
    let rate_hz = match rec.rate_hz {
        Some(r) => r,
        // A time column that times nothing (all zero, equal, running
        // backwards) is not a file without a clock: 1 Hz would be a guess
        // against what the file says.
        None if rec.timestamps.as_ref().is_some_and(|t| t.len() > 1) => {
            return Err(AnalysisError::NoClock {
                file: file.to_path_buf(),
                detail: describe_stamps(rec.timestamps.as_deref().unwrap_or_default()),
            });
        }
        None => {
            notes.push(format!(
                "note: {}: no sample rate given ({}), recorded (# sample_rate_hz:) or timed; assuming 1 Hz",
                file.display(),
                Setting::SampleRate
            ));
            1.0
        }
    };
    let checks = checked(file, &rec, &mut notes);
    let mut out = Vec::with_capacity(select.len());
    // Each header looked up once: a table of 200 000 columns is read in
    // time linear in its columns, not their square.
    let position: std::collections::HashMap<&str, usize> = rec
        .channels
        .iter()
        .enumerate()
        .rev()
        .map(|(k, c)| (c.source_name.as_str(), k))
        .collect();
    let positions: Vec<Option<usize>> = select
        .iter()
        .map(|&idx| position.get(headers[idx].as_str()).copied())
        .collect();
    drop(position);
    for (idx, pos) in select.into_iter().zip(positions) {
        let Some(pos) = pos else {
            return Err(AnalysisError::TimeColumn {
                file: file.to_path_buf(),
                column: idx + 1,
                name: headers[idx].clone(),
            });
        };
        out.push(take_channel(
            file,
            idx + 1,
            &mut rec.channels[pos],
            rate_hz,
            report.lines,
        ));
    }
    Ok(selection(&mut rec, out, rate_hz, notes, checks, facts))
}

/// What a time column's stamps are when they give no clock.
fn describe_stamps(t: &[f64]) -> String {
    imu::timing::describe_stamps(t, "rows", "have no stamp")
}

/// Refuses a selection holding two columns that resolve to one channel
/// (`gx` and `gyro_x`, `gyro_x[deg/s]` and `gyro_x[rad/s]`): analysing one
/// of them under the channel's name would be a silent guess. Columns named
/// by their full header are the user's choice and stand.
fn refuse_ambiguity(
    file: &Path,
    headers: &[String],
    kinds: &[ColumnKind],
    select: &[usize],
    by_header: &[usize],
) -> Result<(), AnalysisError> {
    let mut seen: std::collections::HashMap<String, Vec<usize>> = std::collections::HashMap::new();
    for &i in select.iter().filter(|i| !by_header.contains(i)) {
        seen.entry(kinds[i].name.to_ascii_lowercase())
            .or_default()
            .push(i);
    }
    let mut clashes: Vec<&Vec<usize>> = seen.values().filter(|v| v.len() > 1).collect();
    clashes.sort();
    match clashes.first() {
        None => Ok(()),
        Some(cols) => Err(AnalysisError::AmbiguousChannel {
            file: file.to_path_buf(),
            channel: kinds[cols[0]].name.clone(),
            columns: cols
                .iter()
                .map(|&i| format!("{} ('{}')", i + 1, headers[i]))
                .collect::<Vec<_>>()
                .join(" and "),
            first: headers[cols[0]].clone(),
        }),
    }
}

/// What the reader found and did, one line each (`warning: …`, `note: …`):
/// its problems, and the samples it placed on `clock` (filled gaps,
/// duplicate, backward and dropped stamps).
pub(crate) fn reader_notes(file: &Path, report: &imu::ReadReport, clock: &str) -> Vec<String> {
    let mut notes = Vec::new();
    for p in &report.problems {
        match p.line {
            Some(line) => notes.push(format!("warning: {}:{line}: {}", file.display(), p.message)),
            None => notes.push(format!("warning: {}: {}", file.display(), p.message)),
        }
    }
    if report.unlisted > 0 {
        notes.push(format!(
            "warning: {}: {} more problems not listed",
            file.display(),
            report.unlisted
        ));
    }
    for n in &report.notes {
        notes.push(format!("note: {}: {n}", file.display()));
    }
    // What the reader did to the samples, repeated here so that an
    // analysis never rests on filled or dropped samples unsaid.
    if let Some(t) = &report.timing {
        let filled: usize = report
            .problems
            .iter()
            .filter(|p| p.kind == imu::ProblemKind::TimeGap)
            .map(|p| p.count)
            .sum();
        notes.push(format!(
            "note: {}: samples placed on {} ({} Hz, jitter {:.2e} s): {} gap{} filled \
             with {filled} empty samples, {} duplicate and {} backward stamps kept, {} repeated row{} dropped",
            file.display(),
            clock,
            imu::log_file::round_rate(t.rate_hz),
            t.jitter_s,
            t.gaps.len(),
            if t.gaps.len() == 1 { "" } else { "s" },
            t.duplicates.len() - report.dropped_samples.min(t.duplicates.len()),
            t.backwards.len(),
            report.dropped_samples,
            if report.dropped_samples == 1 { "" } else { "s" },
        ));
    }
    notes
}

/// Checks the recording's channels ([`channel_checks::check`]), each
/// finding a warning among `notes`.
pub(crate) fn checked(file: &Path, rec: &imu::Recording, notes: &mut Vec<String>) -> Checks {
    let checks = channel_checks::check(rec);
    for f in &checks.findings {
        notes.push(format!("warning: {}: {f}", file.display()));
    }
    checks
}

/// One selected channel of a recording read: its samples move out, except
/// the temperature's, which stays in the recording for the callers that need
/// it beside the channels.
pub(crate) fn take_channel(
    file: &Path,
    column: usize,
    ch: &mut imu::Channel,
    rate_hz: f64,
    lines: u64,
) -> SelectedChannel {
    SelectedChannel {
        file: file.to_path_buf(),
        column,
        name: ch.name.clone(),
        quantity: ch.quantity,
        unit: ch.unit.clone(),
        unit_source: ch.unit_source,
        rate_hz,
        lines,
        data: if ch.quantity == Quantity::Temperature {
            ch.data.clone()
        } else {
            std::mem::take(&mut ch.data)
        },
    }
}

/// The selection of `channels`, with the recording's temperature (moved
/// out of `rec`, not copied: a long recording's peak memory stays that of
/// its columns) and its mean over the samples that have one.
pub(crate) fn selection(
    rec: &mut imu::Recording,
    channels: Vec<SelectedChannel>,
    rate_hz: f64,
    notes: Vec<String>,
    checks: Checks,
    recording: RecordingFacts,
) -> Selection {
    let temperature = rec
        .channels
        .iter_mut()
        .find(|c| c.quantity == Quantity::Temperature)
        .map(|t| std::mem::take(&mut t.data));
    let temperature_mean_c = temperature.as_ref().and_then(|t| {
        let (sum, n) = t
            .iter()
            .filter(|v| v.is_finite())
            .fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
        (n > 0).then(|| sum / n as f64)
    });
    Selection {
        channels,
        temperature_mean_c,
        temperature,
        rate_hz,
        device_ids: DeviceIds::of(&rec.meta),
        notes,
        checks,
        recording,
    }
}

/// A recording's gyro and accelerometer device ids, where it gives them.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DeviceIds {
    /// The gyro's.
    pub gyro: Option<u32>,
    /// The accelerometer's.
    pub accel: Option<u32>,
}

impl DeviceIds {
    /// From the metadata: a PX4 stream's per-topic ids for its instance,
    /// an ArduPilot IMU's `INS_GYRn_ID`/`INS_ACCn_ID` from the log's PARM
    /// messages, else the one `device_id` for both.
    pub fn of(meta: &imu::Metadata) -> DeviceIds {
        let parse = |v: &str| {
            let v = v.trim();
            match v.strip_prefix("0x") {
                Some(hex) => u32::from_str_radix(hex, 16).ok(),
                None => v.parse().ok(),
            }
        };
        let common = meta.get("device_id").and_then(parse);
        let topic = |name: &str| {
            let instance = meta.get("instance")?;
            meta.get(&format!("px4.{name}/{instance}.device_id"))
                .and_then(parse)
        };
        // ArduPilot's IMU n (0-based) is INS_GYR_ID, INS_GYR2_ID, INS_GYR3_ID.
        let parameter = |sensor: &str| {
            let instance: u32 = meta.get("instance")?.trim().parse().ok()?;
            let suffix = if instance == 0 {
                String::new()
            } else {
                (instance + 1).to_string()
            };
            meta.get(&format!("ardupilot.INS_{sensor}{suffix}_ID"))
                .and_then(parse)
        };
        DeviceIds {
            gyro: topic("sensor_gyro").or_else(|| parameter("GYR")).or(common),
            accel: topic("sensor_accel").or_else(|| parameter("ACC")).or(common),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Metadata holding these entries, in order.
    fn meta(entries: &[(&str, &str)]) -> imu::Metadata {
        let mut meta = imu::Metadata::default();
        for (k, v) in entries {
            meta.set(*k, *v);
        }
        meta
    }

    #[test]
    fn a_px4_streams_ids_are_its_instances_and_a_text_logs_one_id_stands_for_both() {
        let ids = |gyro, accel| DeviceIds {
            gyro: Some(gyro),
            accel: Some(accel),
        };
        // As the ULog reader leaves them: every instance's ids, and the one
        // read (instance 1).
        let px4 = meta(&[
            ("px4.sensor_accel/0.device_id", "2424842"),
            ("px4.sensor_gyro/0.device_id", "2424586"),
            ("px4.sensor_accel/1.device_id", "3670050"),
            ("px4.sensor_gyro/1.device_id", "3669794"),
            ("instance", "1"),
            ("device_id", "3669794"),
        ]);
        assert_eq!(DeviceIds::of(&px4), ids(3_669_794, 3_670_050));
        let text = meta(&[("device_id", "0x2f0009")]);
        assert_eq!(DeviceIds::of(&text), ids(0x2f0009, 0x2f0009));
        assert_eq!(DeviceIds::of(&imu::Metadata::default()), DeviceIds::default());
        // A DataFlash log's PARM ids, as its reader leaves them: IMU 1 is
        // INS_GYR2_ID / INS_ACC2_ID.
        let df = meta(&[
            ("ardupilot.INS_GYR_ID", "2490378"),
            ("ardupilot.INS_ACC_ID", "2490634"),
            ("ardupilot.INS_GYR2_ID", "3407882"),
            ("ardupilot.INS_ACC2_ID", "3408138"),
            ("instance", "1"),
            ("device_id", "3407882"),
        ]);
        assert_eq!(DeviceIds::of(&df), ids(3_407_882, 3_408_138));
    }
}
