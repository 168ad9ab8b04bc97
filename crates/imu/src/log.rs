//! The thesis log and imutherm's own log: writing, and reading into a
//! [`Recording`].
//!
//! The thesis log is a header line
//! `mpu_accel_1[m/^2], …, mpu_gyro_3[rad/s], temp[degC]` and one
//! comma-separated row per sample, with no time column. imutherm's log is the
//! same body after `# key: value` metadata lines (format, sample rate,
//! device, configuration, start time, version): anything that reads the
//! thesis format after skipping `#` lines reads it.

use std::io::{self, Write};
use std::path::Path;

use rayon::prelude::*;

use crate::error::{ReadError, ReadErrorKind};
use crate::header::{split_name_unit, split_unit_suffix};
use crate::names::{is_time_name, quantity_of_name};
use crate::recording::{Axis, Channel, Metadata, Recording, standard_name};
use crate::report::{Problem, ProblemKind, ReadReport};
use crate::table::{ReadPolicy, TableReader};
use crate::timing::{analyze_timestamps, regularize};
use crate::units::{Quantity, Unit, UnitSource, parse_unit};

/// The thesis log's header, exactly as its logger wrote it (with the `m/^2`
/// misprint, which readers of that format expect).
pub const THESIS_HEADER: &str = "mpu_accel_1[m/^2], mpu_accel_2[m/^2], mpu_accel_3[m/^2], \
mpu_gyro_1[rad/s], mpu_gyro_2[rad/s], mpu_gyro_3[rad/s], temp[degC]";

/// The value of imutherm's `# format:` line.
pub const IMUTHERM_FORMAT: &str = "imutherm-log/1";

/// Metadata key of the sample rate.
pub const KEY_RATE: &str = "sample_rate_hz";

/// Which flavour to write.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LogFormat {
    /// Header and rows only.
    Thesis,
    /// `# key: value` metadata, then the thesis body.
    Imutherm,
}

/// Writes IMU samples row by row: accel x/y/z (m/s²), gyro x/y/z (rad/s),
/// temperature (°C). Numbers are written in their shortest exact form, so
/// reading the file back gives the same bits.
pub struct LogWriter<W: Write> {
    out: W,
    line: Vec<u8>,
    rows: u64,
    extra: usize,
    full: Vec<f64>,
}

impl<W: Write> LogWriter<W> {
    /// Starts a log: metadata (imutherm format only) and the header.
    /// `rate_hz` goes into the metadata as `sample_rate_hz`.
    pub fn new(out: W, format: LogFormat, meta: &Metadata, rate_hz: Option<f64>) -> io::Result<Self> {
        Self::with_columns(out, format, meta, rate_hz, &[])
    }

    /// [`LogWriter::new`] with more columns after the seven of the thesis
    /// (headers such as `host_time[s]`), written by
    /// [`LogWriter::write_row_with`].
    pub fn with_columns(
        mut out: W,
        format: LogFormat,
        meta: &Metadata,
        rate_hz: Option<f64>,
        extra: &[&str],
    ) -> io::Result<Self> {
        if format == LogFormat::Imutherm {
            writeln!(out, "# format: {IMUTHERM_FORMAT}")?;
            if let Some(r) = rate_hz {
                writeln!(out, "# {KEY_RATE}: {r}")?;
            }
            if let Some(d) = &meta.device {
                writeln!(out, "# device: {}", one_line(d))?;
            }
            if let Some(t) = &meta.start_time {
                writeln!(out, "# start_time: {}", one_line(t))?;
            }
            for (k, v) in &meta.entries {
                let reserved = ["format", KEY_RATE, "device", "start_time"];
                if !reserved.contains(&k.as_str()) {
                    writeln!(out, "# {}: {}", one_line(k).replace(':', "_"), one_line(v))?;
                }
            }
        }
        write!(out, "{THESIS_HEADER}")?;
        for h in extra {
            write!(out, ", {}", one_line(h).replace(',', "_"))?;
        }
        writeln!(out)?;
        Ok(LogWriter {
            out,
            line: Vec::with_capacity(192),
            rows: 0,
            extra: extra.len(),
            full: Vec::with_capacity(7 + extra.len()),
        })
    }

    /// Writes one sample: `[ax, ay, az, gx, gy, gz, temp]` in SI (and NaN
    /// in any extra column).
    pub fn write_row(&mut self, row: &[f64; 7]) -> io::Result<()> {
        self.write_row_with(row, &[])
    }

    /// Writes one sample and the values of the extra columns (missing ones
    /// as NaN, surplus ones ignored).
    pub fn write_row_with(&mut self, row: &[f64; 7], extra: &[f64]) -> io::Result<()> {
        self.line.clear();
        if self.extra == 0 {
            format_row(row, &mut self.line);
        } else {
            self.full.clear();
            self.full.extend_from_slice(row);
            self.full
                .extend((0..self.extra).map(|i| extra.get(i).copied().unwrap_or(f64::NAN)));
            format_row(&self.full, &mut self.line);
        }
        self.rows += 1;
        self.out.write_all(&self.line)
    }

    /// Writes a `# key: value` comment line among the rows (a gap's cause,
    /// say), which readers skip.
    pub fn write_comment(&mut self, key: &str, value: &str) -> io::Result<()> {
        self.write_trailer(key, value)
    }

    /// Writes rows formatted beforehand with [`format_row`] (so that long
    /// runs can be formatted on all cores); `rows` is how many they are.
    pub fn write_formatted(&mut self, text: &[u8], rows: u64) -> io::Result<()> {
        self.rows += rows;
        self.out.write_all(text)
    }

    /// The underlying writer (to sync a file to disk, say).
    pub fn get_mut(&mut self) -> &mut W {
        &mut self.out
    }

    /// Writes a `# key: value` line after the rows: a trailer that readers
    /// skip as a comment.
    pub fn write_trailer(&mut self, key: &str, value: &str) -> io::Result<()> {
        writeln!(self.out, "# {}: {}", one_line(key), one_line(value))
    }

    /// Rows written so far.
    pub fn rows(&self) -> u64 {
        self.rows
    }

    /// Flushes the underlying writer.
    pub fn flush(&mut self) -> io::Result<()> {
        self.out.flush()
    }

    /// Gives the writer back.
    pub fn into_inner(self) -> W {
        self.out
    }
}

/// Appends one log row (`v, v, …, v\n`) to `out`, each number in its
/// shortest form that reads back to the same bits; non-finite values as `nan`.
pub fn format_row(row: &[f64], out: &mut Vec<u8>) {
    let mut buf = ryu::Buffer::new();
    for (i, v) in row.iter().enumerate() {
        if i > 0 {
            out.extend_from_slice(b", ");
        }
        let text = if v.is_finite() {
            buf.format_finite(*v)
        } else {
            "nan"
        };
        out.extend_from_slice(text.as_bytes());
    }
    out.push(b'\n');
}

fn one_line(s: &str) -> String {
    s.replace(['\n', '\r'], " ")
}

/// Writes a whole recording that has the six inertial channels and the
/// temperature. Missing channels are an error, not zeros.
pub fn write_recording<W: Write>(out: W, rec: &Recording, format: LogFormat) -> io::Result<W> {
    let order = [
        (Quantity::Acceleration, Axis::X),
        (Quantity::Acceleration, Axis::Y),
        (Quantity::Acceleration, Axis::Z),
        (Quantity::AngularRate, Axis::X),
        (Quantity::AngularRate, Axis::Y),
        (Quantity::AngularRate, Axis::Z),
    ];
    let mut cols: Vec<&[f64]> = Vec::with_capacity(7);
    for (q, a) in order {
        let ch = rec
            .channels
            .iter()
            .find(|c| c.quantity == q && c.axis == Some(a))
            .ok_or_else(|| {
                io::Error::new(
                    io::ErrorKind::InvalidInput,
                    format!("the recording has no {} channel", standard_name(q, Some(a))),
                )
            })?;
        cols.push(&ch.data);
    }
    let temp = rec.temperature().ok_or_else(|| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            "the recording has no temperature channel",
        )
    })?;
    cols.push(&temp.data);
    let mut w = LogWriter::new(out, format, &rec.meta, rec.rate_hz)?;
    for i in 0..rec.len() {
        let mut row = [0.0; 7];
        for (dst, col) in row.iter_mut().zip(&cols) {
            *dst = col.get(i).copied().unwrap_or(f64::NAN);
        }
        w.write_row(&row)?;
    }
    w.flush()?;
    Ok(w.into_inner())
}

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
}

/// What a column is, judged from its header.
#[derive(Debug, Clone, PartialEq)]
pub struct ColumnKind {
    /// imutherm's name (`gyro_x`, `temp`) or the header's name.
    pub name: String,
    /// What it measures.
    pub quantity: Quantity,
    /// The axis of an inertial channel.
    pub axis: Option<Axis>,
    /// The conversion of its values to SI.
    pub unit: Unit,
    /// The unit of the converted values.
    pub unit_label: String,
    /// Where the unit came from.
    pub unit_source: UnitSource,
    /// A unit text that was given but is not one imutherm knows.
    pub unknown_unit: Option<String>,
}

/// Judges a column from its header (`name[unit]`, `name(unit)`,
/// `name_unit`), or from `unit_override` when given: the unit decides the
/// quantity when imutherm knows it; a name imutherm recognises
/// ([`crate::names`]) with no unit is taken as already in SI, and the unit
/// is marked [`UnitSource::Assumed`]; the last character `1/2/3` or `x/y/z`
/// gives the axis.
pub fn classify_header(header: &str, unit_override: Option<&str>) -> ColumnKind {
    classify(header, unit_override.map(|u| (u, UnitSource::Flag)))
}

/// [`classify_header`] with the unit from `overrides` (`(column, unit)`
/// pairs) when one names this column by its header, its header without the
/// unit, or its imutherm name (`gyro_x`).
pub fn classify_with_overrides(header: &str, overrides: &[(String, String)]) -> ColumnKind {
    classify_with_sources(header, overrides, &[])
}

/// [`classify_with_overrides`], with units from the file's metadata
/// (`# unit.gyro_x: deg/s`) below those of the command line.
pub fn classify_with_sources(
    header: &str,
    flags: &[(String, String)],
    metadata: &[(String, String)],
) -> ColumnKind {
    let plain = classify(header, None);
    let find = |list: &[(String, String)]| {
        list.iter()
            .find(|(c, _)| names_column(c, header, &plain.name))
            .map(|(_, u)| u.clone())
    };
    if let Some(u) = find(flags) {
        return classify(header, Some((&u, UnitSource::Flag)));
    }
    if let Some(u) = find(metadata) {
        return classify(header, Some((&u, UnitSource::Metadata)));
    }
    plain
}

/// Whether `wanted` names the column of `header` (imutherm name `name`):
/// by the whole header, the header without its unit, or imutherm's name.
fn names_column(wanted: &str, header: &str, name: &str) -> bool {
    let w = wanted.trim();
    let (bare, _) = split_name_unit(header);
    let stem = split_unit_suffix(bare).map_or(bare, |(s, _)| s);
    [header, bare, stem, name]
        .iter()
        .any(|n| n.eq_ignore_ascii_case(w))
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

fn classify(header: &str, unit_override: Option<(&str, UnitSource)>) -> ColumnKind {
    let (mut name, mut unit_text) = split_name_unit(header);
    // A number in brackets is an index, not a unit: PX4's ulog2csv writes
    // `gyro_rad[0]` … `gyro_rad[2]` (pyulog, core.py flattening of arrays).
    let index_axis = unit_text.parse::<usize>().ok().map(|i| match i {
        0 => Some(Axis::X),
        1 => Some(Axis::Y),
        2 => Some(Axis::Z),
        _ => None,
    });
    if index_axis.is_some() {
        unit_text = "";
    }
    // A suffix is a unit only when what is left is a name that says the
    // same quantity: `acc_x_g` is in g, `gyro_x_s` is no time column.
    if unit_text.is_empty()
        && let Some((stem, suffix)) = split_unit_suffix(name)
        && let (Some((q, _)), Some(u)) = (quantity_of_name(stem), parse_unit(suffix))
        && q == u.quantity
    {
        name = stem;
        unit_text = suffix;
    }
    let mut source = if unit_text.is_empty() {
        UnitSource::Assumed
    } else {
        UnitSource::Header
    };
    if let Some((u, from)) = unit_override {
        unit_text = u;
        source = from;
    }
    let by_name = quantity_of_name(name);
    let parsed = parse_unit(unit_text);
    let unknown_unit = (!unit_text.is_empty() && parsed.is_none()).then(|| unit_text.to_string());
    // The unit decides the quantity when it is known; the name only when the
    // header carries no unit (imutherm's names are in SI).
    let unit = match (parsed, by_name) {
        (Some(u), _) => u,
        (None, Some((q, _))) if unit_text.is_empty() && q != Quantity::Time => Unit::si(q),
        (None, Some((Quantity::Time, _))) if unit_text.is_empty() => Unit {
            quantity: Quantity::Time,
            scale: 1.0,
            offset: 0.0,
        },
        _ => Unit {
            quantity: Quantity::Other,
            scale: 1.0,
            offset: 0.0,
        },
    };
    let quantity = unit.quantity;
    let axis = match (by_name, index_axis) {
        _ if !matches!(quantity, Quantity::Acceleration | Quantity::AngularRate) => None,
        (_, Some(a)) => a,
        (Some((_, a)), None) => a.or_else(|| trailing_axis(name)),
        (None, None) => trailing_axis(name),
    };
    let imu_name = match (quantity, axis) {
        (Quantity::Acceleration | Quantity::AngularRate, Some(_)) | (Quantity::Temperature, _) => {
            standard_name(quantity, axis)
        }
        _ => name.to_string(),
    };
    let unit_label = match quantity {
        Quantity::Other => unit_text.to_string(),
        q => q.si_unit().to_string(),
    };
    if quantity == Quantity::Other {
        source = if unit_text.is_empty() {
            UnitSource::Assumed
        } else {
            source
        };
    }
    ColumnKind {
        name: imu_name,
        quantity,
        axis,
        unit,
        unit_label,
        unit_source: source,
        unknown_unit,
    }
}

/// The axis a name's last character gives (`1/2/3`, `x/y/z`).
fn trailing_axis(name: &str) -> Option<Axis> {
    match name.to_ascii_lowercase().chars().last() {
        Some('1' | 'x') => Some(Axis::X),
        Some('2' | 'y') => Some(Axis::Y),
        Some('3' | 'z') => Some(Axis::Z),
        _ => None,
    }
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

/// Metadata key under which readers keep the logger's `# trailer:` line.
pub const TRAILER_KEY: &str = "trailer";

/// How far from the end of a file the trailer is looked for.
const TRAILER_WINDOW: u64 = 64 * 1024;

/// The value of the last `# trailer:` line in the file's last 64 KiB (what
/// `imutherm record` counted: samples, gaps, overflows, bus errors…), or
/// `None` (no trailer, a gzip file, not a regular file, unreadable). Reads
/// only that tail, of a regular file only: a pipe or a device cannot be read
/// again (the readers take the trailer from the stream, [`crate::table::Table::trailer`]).
pub fn read_trailer(path: &Path) -> Option<String> {
    use std::io::{Read, Seek, SeekFrom};
    if !std::fs::metadata(path).ok()?.is_file() {
        return None;
    }
    let mut f = std::fs::File::open(path).ok()?;
    let len = f.metadata().ok()?.len();
    let mut magic = [0u8; 2];
    if f.read_exact(&mut magic).is_ok() && magic == [0x1f, 0x8b] {
        return None;
    }
    f.seek(SeekFrom::Start(len.saturating_sub(TRAILER_WINDOW))).ok()?;
    let mut tail = Vec::new();
    f.take(TRAILER_WINDOW).read_to_end(&mut tail).ok()?;
    String::from_utf8_lossy(&tail)
        .lines()
        .rev()
        .find_map(|l| l.trim().strip_prefix("# trailer:").map(|v| v.trim().to_string()))
}

/// The `key=value` fields of a trailer.
pub fn trailer_fields(trailer: &str) -> Vec<(&str, &str)> {
    trailer
        .split_whitespace()
        .filter_map(|f| f.split_once('='))
        .collect()
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
            let Some((regular, dropped)) = regularize(&t, rate, &cols) else {
                let finite = || t.iter().copied().filter(|v| v.is_finite());
                return Err(ReadError::new(
                    path,
                    ReadErrorKind::TimeColumn(format!(
                        "column {} spans {:.6e} s, far more than its {} samples at {rate} Hz: \
                         check the time unit (--time-unit) or the values",
                        ti + 1,
                        finite().fold(f64::NEG_INFINITY, f64::max) - finite().fold(f64::INFINITY, f64::min),
                        t.len()
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The first rows of the thesis's own log (slides, "Software Design").
    const THESIS_ROWS: &str = "mpu_accel_1[m/^2], mpu_accel_2[m/^2], mpu_accel_3[m/^2], mpu_gyro_1[rad/s], mpu_gyro_2[rad/s], mpu_gyro_3[rad/s], temp[degC]
0.8786720092773437, 0.19632453613281248, 9.344569079589844, -0.03677179134860051, 0.022649291772688717, 0.01891882018659881, 4.062269745709408
0.8810662109374999, 0.22026655273437498, 9.363722692871093, -0.036238866836301946, 0.023182216284987275, 0.01945174469889737, 4.074250456764609
";

    #[test]
    fn rates_are_printed_to_sensible_digits() {
        assert_eq!(round_rate(99.99999999781721), "100");
        assert_eq!(round_rate(200.60180541624874), "200.602");
        assert_eq!(round_rate(248.53871), "248.539");
        assert_eq!(round_rate(0.5), "0.5");
        assert_eq!(round_rate(1000.0), "1000");
    }

    #[test]
    fn reads_the_thesis_log() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("thesis.txt");
        std::fs::write(&p, THESIS_ROWS).unwrap();
        let rec = read_recording(&p, &RecordingOptions::default()).unwrap();
        let names: Vec<&str> = rec.channels.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "accel_x", "accel_y", "accel_z", "gyro_x", "gyro_y", "gyro_z", "temp"
            ]
        );
        assert_eq!(rec.inertial().len(), 6);
        assert_eq!(rec.channel("gyro_x").unwrap().data[1], -0.036238866836301946);
        assert_eq!(rec.channel("mpu_gyro_1[rad/s]").unwrap().unit, "rad/s");
        assert_eq!(rec.channel("accel_z").unwrap().unit, "m/s^2");
        assert_eq!(rec.rate_hz, None);
        assert_eq!(rec.len(), 2);
    }

    #[test]
    fn imutherm_log_round_trips_bit_for_bit() {
        let mut meta = Metadata {
            device: Some("sim:mpu9250-thesis".into()),
            start_time: Some("2026-11-22T10:00:00Z".into()),
            ..Metadata::default()
        };
        meta.set("gyro_full_scale_dps", "250");
        let mut rec = Recording {
            rate_hz: Some(200.0),
            meta,
            ..Recording::default()
        };
        let vals = |k: f64| {
            (0..5)
                .map(|i| (i as f64 + k) * 0.1 + 1e-9 / 3.0)
                .collect::<Vec<_>>()
        };
        for (i, q) in [Quantity::Acceleration, Quantity::AngularRate]
            .into_iter()
            .enumerate()
        {
            for (j, a) in Axis::ALL.into_iter().enumerate() {
                rec.channels
                    .push(Channel::inertial(q, a, vals((3 * i + j) as f64)));
            }
        }
        rec.channels.push(Channel::temperature(vals(40.0)));
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("log.txt");
        write_recording(std::fs::File::create(&p).unwrap(), &rec, LogFormat::Imutherm).unwrap();
        let back = read_recording(&p, &RecordingOptions::default()).unwrap();
        assert_eq!(back.rate_hz, Some(200.0));
        assert_eq!(back.meta.device.as_deref(), Some("sim:mpu9250-thesis"));
        assert_eq!(back.meta.get("gyro_full_scale_dps"), Some("250"));
        for (a, b) in rec.channels.iter().zip(&back.channels) {
            assert_eq!(a.name, b.name);
            assert_eq!(a.data, b.data);
        }
        // Still a thesis file once the comments are skipped.
        let text = std::fs::read_to_string(&p).unwrap();
        let body: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
        assert_eq!(body[0], THESIS_HEADER);
    }

    #[test]
    fn a_host_time_column_is_kept_but_never_the_time_axis_unless_named() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("host.txt");
        let mut w = LogWriter::with_columns(
            Vec::new(),
            LogFormat::Imutherm,
            &Metadata::default(),
            Some(100.0),
            &["host_time[s]"],
        )
        .unwrap();
        // Host times jitter by more than half a period; a gap of two rows.
        let times = [0.0, 0.016, 0.019, f64::NAN, f64::NAN, 0.052];
        for (i, t) in times.iter().enumerate() {
            let v = if t.is_nan() { f64::NAN } else { i as f64 };
            w.write_row_with(&[v; 7], &[*t]).unwrap();
            if i == 2 {
                w.write_comment("gap", "2 samples lost (FIFO overflow)").unwrap();
            }
        }
        w.write_trailer("trailer", "samples=4 gap_samples=2").unwrap();
        std::fs::write(&p, w.into_inner()).unwrap();
        let text = std::fs::read_to_string(&p).unwrap();
        assert!(text.contains("temp[degC], host_time[s]\n"), "{text}");
        let (rec, report) = read_recording_with_report(&p, &RecordingOptions::default()).unwrap();
        // Six rows, in file order: the host time did not move any.
        assert_eq!(rec.len(), 6);
        assert!(report.timing.is_none());
        assert_eq!(rec.rate_hz, Some(100.0));
        assert_eq!(rec.channel("gyro_x").unwrap().data[5], 5.0);
        assert_eq!(rec.channel("host_time").unwrap().data[2], 0.019);
        // The NaN run is named at its line (after the gap comment).
        let gap = report
            .problems
            .iter()
            .find(|p| p.kind == ProblemKind::NanRun)
            .unwrap();
        assert_eq!(gap.line, Some(8));
        // Named, it is the time axis.
        let opts = RecordingOptions {
            time_column: Some("host_time".into()),
            ..RecordingOptions::default()
        };
        let (_, report) = read_recording_with_report(&p, &opts).unwrap();
        assert!(report.timing.is_some());
    }

    #[test]
    fn a_gap_after_a_bad_line_is_still_reported() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("bad_then_gap.txt");
        let mut w =
            LogWriter::new(Vec::new(), LogFormat::Imutherm, &Metadata::default(), Some(100.0)).unwrap();
        for _ in 0..3 {
            w.write_row(&[1.0; 7]).unwrap();
        }
        let mut text = w.into_inner();
        text.extend_from_slice(b"1, 2, garbled\n");
        let mut w = LogWriter::new(Vec::new(), LogFormat::Thesis, &Metadata::default(), None).unwrap();
        w.write_comment("gap", "5 samples lost").unwrap();
        for _ in 0..5 {
            w.write_row(&[f64::NAN; 7]).unwrap();
        }
        w.write_row(&[2.0; 7]).unwrap();
        let tail = w.into_inner();
        // Without the second writer's header line.
        let tail = &tail[tail.iter().position(|&b| b == b'\n').unwrap() + 1..];
        text.extend_from_slice(tail);
        std::fs::write(&p, &text).unwrap();
        let opts = RecordingOptions {
            skip_bad_lines: true,
            ..RecordingOptions::default()
        };
        let (rec, report) = read_recording_with_report(&p, &opts).unwrap();
        assert_eq!(rec.len(), 10);
        assert_eq!(report.count(ProblemKind::BadLine), 1);
        let gaps: Vec<_> = report
            .problems
            .iter()
            .filter(|p| p.kind == ProblemKind::NanRun)
            .collect();
        // Lines: 2 metadata, header, 3 rows (4-6), the bad line 7, the
        // comment 8, the gap from line 9.
        assert_eq!(gaps.len(), 1, "{:?}", report.problems);
        assert_eq!((gaps[0].line, gaps[0].count), (Some(9), 5));
    }

    #[test]
    fn many_logger_gaps_are_each_listed_once() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("gaps.txt");
        let mut w =
            LogWriter::new(Vec::new(), LogFormat::Imutherm, &Metadata::default(), Some(100.0)).unwrap();
        for i in 0..600 {
            let v = if i % 3 == 1 { f64::NAN } else { 1.0 };
            w.write_row(&[v; 7]).unwrap();
        }
        std::fs::write(&p, w.into_inner()).unwrap();
        let (_, report) = read_recording_with_report(&p, &RecordingOptions::default()).unwrap();
        assert_eq!(report.count(ProblemKind::NanRun), 200);
        assert_eq!(report.unlisted, 0);
        assert!(
            report
                .problems
                .iter()
                .all(|p| p.channel.is_none() && p.count == 1)
        );
    }

    #[test]
    fn units_convert_and_can_be_overridden() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("g.csv");
        std::fs::write(&p, "gyro_x[deg/s],acc_z[g],gyro_y,pressure[hPa]\n180,1,90,1013\n").unwrap();
        let opts = RecordingOptions {
            units: vec![("gyro_y".into(), "deg/s".into())],
            ..RecordingOptions::default()
        };
        let rec = read_recording(&p, &opts).unwrap();
        assert!((rec.channel("gyro_x").unwrap().data[0] - std::f64::consts::PI).abs() < 1e-15);
        assert!((rec.channel("accel_z").unwrap().data[0] - 9.80665).abs() < 1e-15);
        assert!((rec.channel("gyro_y").unwrap().data[0] - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        let p_ch = rec.channel("pressure").unwrap();
        assert_eq!((p_ch.quantity, p_ch.unit.as_str()), (Quantity::Other, "hPa"));
        let bad = RecordingOptions {
            units: vec![("gyro_y".into(), "parsec".into())],
            ..RecordingOptions::default()
        };
        let e = read_recording(&p, &bad).unwrap_err();
        assert!(e.to_string().contains("parsec"), "{e}");
    }

    #[test]
    fn report_names_every_problem_with_its_line() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("t.csv");
        // 100 Hz in nanoseconds: a gap of 2 samples after line 4, a
        // duplicate at line 6, a step back at line 8, NaN and inf cells.
        let body = "time_ns,gyro_x[deg/s],temp\n\
                    0,1,20\n10000000,2,20\n20000000,nan,20\n50000000,4,20\n\
                    50000000,5,20\n60000000,inf,20\n55000000,7,20\n70000000,8,20\n";
        std::fs::write(&p, body).unwrap();
        let (rec, report) = read_recording_with_report(&p, &RecordingOptions::default()).unwrap();
        assert!((rec.rate_hz.unwrap() - 100.0).abs() < 1e-9);
        let timing = report.timing.as_ref().unwrap();
        assert_eq!(timing.gaps, vec![(3, 2)]);
        let found: Vec<(ProblemKind, Option<u64>)> =
            report.problems.iter().map(|p| (p.kind, p.line)).collect();
        for want in [
            (ProblemKind::NanRun, Some(4)),
            (ProblemKind::Infinite, Some(7)),
            (ProblemKind::TimeGap, Some(5)),
            (ProblemKind::DuplicateTime, Some(6)),
            (ProblemKind::BackwardsTime, Some(8)),
        ] {
            assert!(found.contains(&want), "{want:?} not in {found:?}");
        }
        // Every sample keeps a slot: the gap of two before line 5 is
        // filled, the duplicate (line 6, another value) and the step back
        // (line 8) are kept in the slots after their predecessors. Slot 2
        // (NaN) and 7 (inf) are gaps of the file itself.
        let g = &rec.channel("gyro_x").unwrap().data;
        assert_eq!(g.len(), 10);
        assert_eq!(report.dropped_samples, 0);
        assert!((g[1] - 2.0f64.to_radians()).abs() < 1e-15);
        assert!(g[2].is_nan() && g[3].is_nan() && g[4].is_nan() && g[7].is_nan());
        for (slot, deg) in [(5, 4.0), (6, 5.0), (8, 7.0), (9, 8.0)] {
            assert!((g[slot] - f64::to_radians(deg)).abs() < 1e-15, "slot {slot}");
        }
        assert_eq!(rec.timestamps.as_ref().unwrap()[1], 0.01);
    }

    #[test]
    fn an_unusable_rate_in_the_metadata_is_a_problem_naming_its_line() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("meta.txt");
        for (value, bad) in [
            ("abc", true),
            ("-5", true),
            ("nan", true),
            ("", true),
            ("200", false),
        ] {
            std::fs::write(
                &p,
                format!("# device: bench\n\n# sample_rate_hz: {value}\na,b\n1,2\n3,4\n"),
            )
            .unwrap();
            let (rec, report) = read_recording_with_report(&p, &RecordingOptions::default()).unwrap();
            let found = report
                .problems
                .iter()
                .find(|p| p.kind == ProblemKind::BadMetadata);
            if bad {
                let found = found.unwrap_or_else(|| panic!("{value}: {:?}", report.problems));
                assert_eq!(found.line, Some(3), "{value}");
                assert!(
                    found.message.contains(&format!("sample_rate_hz: {value}'")),
                    "{}",
                    found.message
                );
                assert_eq!(rec.rate_hz, None);
            } else {
                assert!(found.is_none(), "{:?}", report.problems);
                assert_eq!(rec.rate_hz, Some(200.0));
            }
        }
    }
}
