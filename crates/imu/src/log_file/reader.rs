//! Reading a log (or any numeric table with a header) into a
//! [`Recording`], with everything found wrong on the way.

use std::path::Path;

use rayon::prelude::*;

use super::columns::{ColumnKind, classify_with_sources, names_column};
use super::trailer::TRAILER_KEY;
use super::writer::KEY_RATE;
use crate::error::{ReadError, ReadErrorKind};
use crate::header::split_name_unit;
use crate::names::{is_time_name, quantity_of_name};
use crate::read_report::{FileFormat, Problem, ProblemKind, ReadReport};
use crate::recording::{Channel, Metadata, Recording};
use crate::table::{ReadPolicy, TableReader};
use crate::timing::{analyze_timestamps, regularize};
use crate::units::{Quantity, UnitSource, parse_unit};

/// How to read a recording.
#[derive(Debug, Clone, Default)]
pub struct RecordingOptions {
    /// Sample rate in Hz; overrides the file's metadata.
    pub rate_hz: Option<f64>,
    /// Unit per column (by header name or imutherm name), overriding the
    /// header's: `("gyro_x", "deg/s")`.
    pub units: Vec<(String, String)>,
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

/// A `# sample_rate_hz:` that is not a positive number of Hz, as a problem
/// naming its line: ignored, it would otherwise leave the rate to a
/// fallback without a word.
fn bad_metadata_rate(reader: &TableReader, file_rate: Option<f64>) -> Option<Problem> {
    if file_rate.is_some() {
        return None;
    }
    // The last line with the key is the one parse_metadata kept.
    let (i, value) = reader.comments().iter().enumerate().rev().find_map(|(i, c)| {
        let (k, v) = c.split_once(':')?;
        (k.trim() == KEY_RATE).then(|| (i, v.trim()))
    })?;
    Some(Problem {
        kind: ProblemKind::BadMetadata,
        line: reader.comment_line(i),
        column: None,
        channel: None,
        count: 1,
        message: format!("'# {KEY_RATE}: {value}' is not a positive number of Hz: ignored"),
    })
}

/// Reads a thesis log, an imutherm log, or any numeric column file with a
/// header into a [`Recording`] in SI units. Problems that were recovered
/// from (a truncated last line, skipped rows, infinities made gaps, time
/// gaps) are dropped from view: use [`read_recording_with_report`] to see them.
pub fn read_recording(path: &Path, opts: &RecordingOptions) -> Result<Recording, ReadError> {
    read_recording_with_report(path, opts).map(|(rec, _)| rec)
}

/// Runs of rows that are NaN in every column (a logger's gaps), as
/// (first row, rows). Reported once for the row range rather than once per
/// channel. Empty with fewer than two columns, or when a column has no NaN.
fn whole_row_gaps(columns: &[(usize, Vec<f64>)]) -> Vec<(usize, usize)> {
    if columns.len() < 2 || columns.iter().any(|(_, c)| !c.par_iter().any(|v| v.is_nan())) {
        return Vec::new();
    }
    let rows = columns.iter().map(|(_, c)| c.len()).min().unwrap_or(0);
    let all_nan = |r: usize| columns.iter().all(|(_, c)| c[r].is_nan());
    let mut runs = Vec::new();
    let mut r = 0;
    while r < rows {
        if all_nan(r) {
            let start = r;
            while r < rows && all_nan(r) {
                r += 1;
            }
            runs.push((start, r - start));
        } else {
            r += 1;
        }
    }
    runs
}

/// A column that records when the host read each sample (`imutherm record
/// --host-time`). It is never taken as the time axis unless named: it
/// carries the host's scheduling jitter and the host's clock, not the
/// sensor's, and placing samples on a grid by it would invent gaps and
/// duplicates. The sample order and the NaN rows of lost stretches are the
/// record's time axis.
pub const HOST_TIME_COLUMN: &str = "host_time";

fn is_time_header(kind: &ColumnKind, header: &str) -> bool {
    let (name, _) = split_name_unit(header);
    let n = name.to_ascii_lowercase();
    if n == HOST_TIME_COLUMN {
        return false;
    }
    kind.quantity == Quantity::Time || is_time_name(&kind.name)
}

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

/// The unit of a time column whose header and flags name none, and why:
/// Unix epoch stamps by their magnitude (s ≈ 1.7e9, ms ≈ 1.7e12, µs ≈
/// 1.7e15, ns ≈ 1.7e18), others by the median step, taking the unit that
/// makes it an IMU's: steps below 2 in seconds, whole-numbered steps and
/// steps up to 2000 in milliseconds, up to 1e5 in microseconds (10 Hz and
/// faster), beyond in nanoseconds.
fn guess_time_unit(raw: &[f64]) -> (f64, &'static str) {
    let first = raw.iter().copied().find(|v| v.is_finite()).unwrap_or(0.0).abs();
    for (lo, scale) in [(1e9, 1.0), (1e12, 1e-3), (1e15, 1e-6), (1e18, 1e-9)] {
        if (lo..lo * 10.0).contains(&first) {
            return (
                scale,
                "guessed from the magnitude of the stamps (Unix epoch time)",
            );
        }
    }
    let mut steps: Vec<f64> = raw.windows(2).map(|w| w[1] - w[0]).filter(|d| *d > 0.0).collect();
    steps.sort_unstable_by(f64::total_cmp);
    let Some(&m) = steps.get(steps.len() / 2) else {
        return (1.0, "guessed (too few steps to tell)");
    };
    let whole = raw.iter().take(1000).all(|v| !v.is_finite() || v.fract() == 0.0);
    let why = "guessed from the median step";
    if m < 2.0 && !whole {
        (1.0, why)
    } else if m < 2000.0 {
        (1e-3, why)
    } else if m < 1e5 {
        (1e-6, why)
    } else {
        (1e-9, why)
    }
}

/// Units of columns written in the metadata as `# unit.<column>: <unit>`.
fn metadata_units(meta: &Metadata) -> Vec<(String, String)> {
    meta.entries
        .iter()
        .filter_map(|(k, v)| Some((k.strip_prefix("unit.")?.to_string(), v.clone())))
        .collect()
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
         not m/s²; give --unit accel_x={looks} (and y, z) or write the unit in the header"
    ))
}

/// The format of a file with this metadata and these headers: imutherm's
/// log says so in its `# format:` line; the thesis's log has its own
/// header (its `mpu_gyro_` columns).
fn detected_format(meta: &Metadata, headers: &[String]) -> FileFormat {
    if meta.get("format").is_some_and(|f| f.starts_with("imutherm-log")) {
        FileFormat::ImuthermLog
    } else if headers.iter().any(|h| h.starts_with("mpu_gyro_")) {
        FileFormat::ThesisLog
    } else {
        FileFormat::Columns
    }
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
    let path = path.as_path();
    if let Some((column, unit)) = opts.units.iter().find(|(_, u)| parse_unit(u).is_none()) {
        return Err(ReadError::new(
            path,
            ReadErrorKind::UnknownUnit {
                column: column.clone(),
                unit: unit.clone(),
            },
        ));
    }
    let mut meta = parse_metadata(reader.comments());
    meta.source = Some(path.to_path_buf());
    let file_rate = metadata_rate(&meta);
    let bad_rate = bad_metadata_rate(&reader, file_rate);
    let headers: Vec<String> = reader.names().to_vec();
    let from_meta = metadata_units(&meta);
    let kinds: Vec<ColumnKind> = headers
        .iter()
        .map(|h| classify_with_sources(h, &opts.units, &from_meta))
        .collect();
    // A unit given for a column that is not there is a typo, not a no-op.
    if let Some((column, _)) = opts.units.iter().find(|(c, _)| {
        !headers
            .iter()
            .zip(&kinds)
            .any(|(h, k)| names_column(c, h, &k.name))
    }) {
        return Err(ReadError::new(
            path,
            ReadErrorKind::NoSuchColumn {
                wanted: format!("{column} (named by --unit)"),
                available: headers.join(", "),
            },
        ));
    }
    // A unit imutherm cannot read, on a column it knows the meaning of,
    // would otherwise leave the column out of every analysis in silence.
    if let Some((i, k)) = kinds.iter().enumerate().find(|(i, k)| {
        k.unknown_unit.is_some() && quantity_of_name(split_name_unit(&headers[*i]).0).is_some()
    }) {
        return Err(ReadError::new(
            path,
            ReadErrorKind::UnknownUnit {
                column: headers[i].clone(),
                unit: k.unknown_unit.clone().unwrap_or_default(),
            },
        )
        .at(1, Some(i + 1)));
    }
    let time_index = match &opts.time_column {
        Some(name) => Some(
            kinds
                .iter()
                .position(|k| k.name.eq_ignore_ascii_case(name))
                .map_or_else(|| reader.column_index(name), Ok)?,
        ),
        None => (0..headers.len()).find(|&i| is_time_header(&kinds[i], &headers[i])),
    };
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
    let rows = table_columns.first().map_or(0, Vec::len);
    let mut report = ReadReport {
        format: detected_format(&meta, &headers),
        lines: table.lines,
        rows,
        ..ReadReport::default()
    };
    if let Some(p) = bad_rate {
        report.push(p);
    }
    for e in &table.problems {
        report.push(Problem::from_read_error(e));
    }
    let line_of = |row: usize| table.line_of_row(row);
    let mut columns = Vec::with_capacity(headers.len());
    let mut time: Option<Vec<f64>> = None;
    for (i, data) in table_columns.into_iter().enumerate() {
        if Some(i) == time_index {
            time = Some(data);
        } else {
            columns.push((i, data));
        }
    }
    // Rows skipped as bad are reported as that already: a NaN run is
    // reported from its first row that is not one of them.
    let bad_lines: std::collections::HashSet<u64> = table.problems.iter().filter_map(|p| p.line).collect();
    let beyond_bad = |start: usize, count: usize| -> Option<(usize, usize)> {
        let first =
            (start..start + count).find(|&r| bad_lines.is_empty() || !bad_lines.contains(&line_of(r)))?;
        Some((first, count - (first - start)))
    };
    let whole_rows = whole_row_gaps(&columns);
    let is_whole_row = |start: usize, count: usize| whole_rows.binary_search(&(start, count)).is_ok();
    for &(start, count) in &whole_rows {
        let Some((start, count)) = beyond_bad(start, count) else {
            continue;
        };
        report.push(Problem {
            kind: ProblemKind::NanRun,
            line: Some(line_of(start)),
            column: None,
            channel: None,
            count,
            message: format!(
                "{count} row{} of NaN in every channel from here (a gap)",
                if count == 1 { "" } else { "s" }
            ),
        });
    }
    let mut channels = Vec::with_capacity(columns.len());
    for (i, mut data) in columns {
        let kind = &kinds[i];
        // Gaps: report runs of NaN (not each sample), make infinities gaps.
        // Most recordings have none, which a parallel look tells at once.
        let all_finite = data.par_chunks(1 << 16).all(|c| c.iter().all(|v| v.is_finite()));
        let mut row = if all_finite { data.len() } else { 0 };
        while row < data.len() {
            if data[row].is_finite() {
                row += 1;
                continue;
            }
            let infinite = data[row].is_infinite();
            let start = row;
            while row < data.len() && !data[row].is_finite() && data[row].is_infinite() == infinite {
                if infinite {
                    data[row] = f64::NAN;
                }
                row += 1;
            }
            let count = row - start;
            if !infinite && is_whole_row(start, count) {
                continue;
            }
            let Some((start, count)) = beyond_bad(start, count) else {
                continue;
            };
            report.push(Problem {
                kind: if infinite {
                    ProblemKind::Infinite
                } else {
                    ProblemKind::NanRun
                },
                line: Some(line_of(start)),
                column: Some(i + 1),
                channel: Some(kind.name.clone()),
                count,
                message: format!(
                    "{}: {count} {} sample{} from here{}",
                    kind.name,
                    if infinite { "infinite" } else { "NaN" },
                    if count == 1 { "" } else { "s" },
                    if infinite { ", treated as gaps" } else { " (gaps)" }
                ),
            });
        }
        if !kind.unit.is_identity() {
            data.iter_mut().for_each(|v| *v = kind.unit.to_si(*v));
        }
        channels.push(Channel {
            name: kind.name.clone(),
            source_name: headers[i].clone(),
            quantity: kind.quantity,
            axis: kind.axis,
            unit: kind.unit_label.clone(),
            unit_source: kind.unit_source,
            data,
        });
    }
    let mut rate_hz = opts.rate_hz.or(file_rate);
    let mut timestamps = None;
    if let (Some(ti), Some(raw)) = (time_index, time) {
        let header_unit = Some(kinds[ti].unit)
            .filter(|u| u.quantity == Quantity::Time && kinds[ti].unit_source != UnitSource::Assumed);
        let given = opts
            .time_unit
            .as_deref()
            .and_then(parse_unit)
            .filter(|u| u.quantity == Quantity::Time);
        let (scale, origin) = match (header_unit, given) {
            (Some(u), _) => (u.scale, None),
            (None, Some(u)) => (u.scale, None),
            (None, None) => {
                let (scale, why) = guess_time_unit(&raw);
                (scale, Some(why))
            }
        };
        if let Some(why) = origin {
            report.notes.push(format!(
                "time column '{}': unit {}, {why}; give --time-unit if that is wrong",
                headers[ti],
                match scale {
                    1.0 => "s",
                    1e-3 => "ms",
                    1e-6 => "us",
                    _ => "ns",
                }
            ));
        }
        let mut raw = raw;
        let wraps = crate::timing::unwrap_u32(&mut raw);
        if let Some(&first) = wraps.first() {
            report.notes.push(format!(
                "time column '{}': a 32-bit counter wrapping every 2^32 ticks ({:.3} s, {:.1} min), at line{} {}{}: unwrapped",
                headers[ti],
                crate::timing::U32_WRAP * scale,
                crate::timing::U32_WRAP * scale / 60.0,
                if wraps.len() == 1 { "" } else { "s" },
                line_of(first),
                wraps
                    .iter()
                    .skip(1)
                    .take(9)
                    .map(|&r| format!(", {}", line_of(r)))
                    .collect::<String>()
            ));
        }
        // A clock that mostly runs backwards is no clock to place samples
        // on (rows in reverse order, a countdown): refused at its first
        // step back, not read as a pile of out-of-order rows.
        let (back, forth) = raw.windows(2).fold((0usize, 0usize), |(b, f), w| {
            (b + usize::from(w[1] < w[0]), f + usize::from(w[1] > w[0]))
        });
        if back > forth
            && let Some(row) = raw.windows(2).position(|w| w[1] < w[0]).map(|k| k + 1)
        {
            return Err(ReadError::new(
                path,
                ReadErrorKind::TimeColumn(format!(
                    "'{}' runs backwards: {back} of its {} steps go back, from this line on; \
                     sort the rows by time, or name the true time column with --time-column",
                    headers[ti],
                    back + forth
                )),
            )
            .at(line_of(row), Some(ti + 1)));
        }
        // Epoch stamps (1.7e18 ns) are taken from the first one, so that
        // the steps keep their digits.
        let t0 = raw.iter().copied().find(|v| v.is_finite()).unwrap_or(0.0);
        let epoch = t0.abs() * scale > 1e8;
        let origin_raw = if epoch { t0 } else { 0.0 };
        let t: Vec<f64> = raw.iter().map(|v| (v - origin_raw) * scale).collect();
        if let Some(timing) = analyze_timestamps(&t) {
            let rate = *rate_hz.get_or_insert(timing.rate_hz);
            if (rate / timing.rate_hz - 1.0).abs() > 1e-3 {
                report.notes.push(format!(
                    "the time column's clock runs at {} Hz, not the {} Hz given; samples are placed \
                     by their order and gaps sized on {} Hz",
                    round_rate(timing.rate_hz),
                    round_rate(rate),
                    round_rate(rate)
                ));
            }
            let cols: Vec<Vec<f64>> = channels.iter_mut().map(|c| std::mem::take(&mut c.data)).collect();
            let factor = opts.max_grid_factor.unwrap_or(crate::timing::MAX_GRID_FACTOR);
            let Some((regular, dropped)) = regularize(&t, rate, &cols, factor) else {
                let finite = || t.iter().copied().filter(|v| v.is_finite());
                return Err(ReadError::new(
                    path,
                    ReadErrorKind::TimeColumn(format!(
                        "column {} spans {:.6e} s, more than {factor} times its {} samples at {rate} Hz: \
                         check the time unit (--time-unit) or the values; a duty-cycled log is read \
                         with its gaps by raising the limit (--max-grid-factor {})",
                        ti + 1,
                        finite().fold(f64::NEG_INFINITY, f64::max) - finite().fold(f64::INFINITY, f64::min),
                        t.len(),
                        ((finite().fold(f64::NEG_INFINITY, f64::max)
                            - finite().fold(f64::INFINITY, f64::min))
                            * rate
                            / t.len() as f64)
                            .ceil()
                            + 1.0
                    )),
                ));
            };
            for &(row, missing) in &timing.gaps {
                report.push(Problem {
                    kind: ProblemKind::TimeGap,
                    line: Some(line_of(row)),
                    column: Some(ti + 1),
                    channel: None,
                    count: missing,
                    message: format!(
                        "{missing} missing sample{} before this line (a step in time, filled as a gap)",
                        if missing == 1 { "" } else { "s" }
                    ),
                });
            }
            let action = |row: usize| {
                if dropped.binary_search(&row).is_ok() {
                    "the whole row repeats the previous one: dropped"
                } else {
                    "sample kept, in the slot after the previous one"
                }
            };
            for &row in &timing.duplicates {
                report.push(Problem {
                    kind: ProblemKind::DuplicateTime,
                    line: Some(line_of(row)),
                    column: Some(ti + 1),
                    channel: None,
                    count: 1,
                    message: format!("duplicate timestamp ({})", action(row)),
                });
            }
            for &row in &timing.backwards {
                report.push(Problem {
                    kind: ProblemKind::BackwardsTime,
                    line: Some(line_of(row)),
                    column: Some(ti + 1),
                    channel: None,
                    count: 1,
                    message: format!("timestamp earlier than the previous one ({})", action(row)),
                });
            }
            for (c, d) in channels.iter_mut().zip(regular) {
                c.data = d;
            }
            report.dropped_samples = dropped.len();
            report.timing = Some(timing);
        }
        timestamps = Some(t);
    }
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
