//! The `imutherm.info/1` JSON document of `imutherm info --json`, as
//! types: what a recording holds and what is wrong with it. Built from the
//! one [`Source`] a read gives; the command line renders it as text or
//! JSON. Field names, nesting and order are the schema's: it only gains
//! fields.

use serde::Serialize;

use crate::channel_checks::{self, Checks, Finding};
use crate::robot_logs::Stream;
use crate::source::Source;

/// The schema's name and version.
pub const SCHEMA: &str = "imutherm.info/1";

/// The whole document.
#[derive(Debug, Serialize)]
pub struct InfoDocument {
    /// [`SCHEMA`].
    pub schema: &'static str,
    /// The writing imutherm's version.
    pub imutherm_version: &'static str,
    /// One entry per input file.
    pub files: Vec<FileInfo>,
}

impl InfoDocument {
    /// The document of these files, written by imutherm `version`.
    pub fn new(imutherm_version: &'static str, files: Vec<FileInfo>) -> Self {
        InfoDocument {
            schema: SCHEMA,
            imutherm_version,
            files,
        }
    }
}

/// One recording.
#[derive(Debug, Serialize)]
pub struct FileInfo {
    /// Its path.
    pub file: String,
    /// The format found.
    pub format: &'static str,
    /// The device the file names.
    pub device: Option<String>,
    /// When the recording started, as the file gives it.
    pub start_time: Option<String>,
    /// Samples (slots on the clock for a robot log).
    pub samples: usize,
    /// Lines read (messages for a robot log).
    pub lines: u64,
    /// Sample rate, Hz.
    pub rate_hz: Option<f64>,
    /// Where the rate came from ([`crate::source::RateSource::name`]).
    pub rate_source: &'static str,
    /// The time stamps' jitter about the fitted clock, s.
    pub jitter_s: Option<f64>,
    /// The time column's clock: the rate fitted to its stamps, the median
    /// step (what a rate read off the steps would say), the samples fitted.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub clock: Option<Clock>,
    /// Length, s.
    pub duration_s: Option<f64>,
    /// The temperature channel's range, °C.
    pub temperature_c: Option<Range>,
    /// Every channel with its statistics.
    pub channels: Vec<ChannelInfo>,
    /// The reader's problems, the checks' findings, overflowing channels.
    pub problems: Vec<ProblemInfo>,
    /// Problems beyond those listed.
    pub problems_unlisted: usize,
    /// What the inertial channels rule out, with figures (each finding is
    /// also among `problems`, kinds `stuck`, `saturated`, `accel_norm`,
    /// `motion`).
    pub checks: Checks,
    /// Rows dropped as written twice.
    pub dropped_samples: usize,
    /// What the reader guessed or found suspicious (a time unit guessed, a
    /// clock that disagrees with the given rate, an accelerometer in g).
    pub notes: Vec<String>,
    /// What `imutherm record` counted (its `# trailer:` line), numbers as
    /// numbers. The trailer's keys are open-ended: a map, in key order.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub logger: Option<serde_json::Map<String, serde_json::Value>>,
    /// Every stream of a robot log (bag, ULog, DataFlash): topic or
    /// instance, messages, mean rate, temperature source.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub streams: Vec<Stream>,
    /// What a robot log's stream is read with: its metadata (stream, time
    /// source and why, device id).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub log_metadata: Vec<(String, String)>,
}

/// The time column's clock. The fields are in key order, as the document
/// has always given them.
#[derive(Debug, Serialize)]
pub struct Clock {
    /// Stamps going backwards.
    pub backward_stamps: usize,
    /// Stamps repeated.
    pub duplicate_stamps: usize,
    /// Samples the clock was fitted to.
    pub fitted_samples: usize,
    /// Gaps in the stamps.
    pub gaps: usize,
    /// Jitter about the fitted clock, s.
    pub jitter_s: f64,
    /// The median step, s.
    pub median_step_s: f64,
    /// An irregular publisher or a duty cycle, when the stamps show one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pattern: Option<ClockPattern>,
    /// The rate fitted to the stamps, Hz.
    pub rate_hz: f64,
}

/// The pattern of a clock's stamps: `irregular` (steps on several values
/// no one clock makes) or `bursts` (a regular duty cycle). Keys in order.
#[derive(Debug, Serialize)]
pub struct ClockPattern {
    /// Bursts in the recording.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub burst_count: Option<usize>,
    /// The median burst, first to last stamp, s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub burst_s: Option<f64>,
    /// A step longer than this is a gap, s.
    pub gap_above_s: f64,
    /// `irregular` or `bursts`.
    pub kind: &'static str,
    /// The median burst period, start to start, s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub period_s: Option<f64>,
    /// From the first stamp to the last, s.
    pub span_s: f64,
    /// Steps in each value, as `steps_s`.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub step_counts: Vec<usize>,
    /// The values the steps cluster on, s.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub steps_s: Vec<f64>,
}

impl ClockPattern {
    fn of(t: &imu::timing::Timing) -> Option<ClockPattern> {
        use imu::clock_pattern::Pattern;
        let mut p = ClockPattern {
            burst_count: None,
            burst_s: None,
            gap_above_s: t.gap_above_s,
            kind: "irregular",
            period_s: None,
            span_s: t.span_s,
            step_counts: Vec::new(),
            steps_s: Vec::new(),
        };
        match t.pattern.as_ref()? {
            Pattern::Irregular { steps } => {
                p.steps_s = steps.iter().map(|s| s.step_s).collect();
                p.step_counts = steps.iter().map(|s| s.count).collect();
            }
            Pattern::Bursts {
                burst_s,
                period_s,
                bursts,
            } => {
                p.kind = "bursts";
                p.burst_count = Some(*bursts);
                p.burst_s = Some(*burst_s);
                p.period_s = Some(*period_s);
            }
        }
        Some(p)
    }
}

/// A channel's range.
#[derive(Debug, Serialize)]
pub struct Range {
    /// Smallest value.
    pub min: f64,
    /// Mean.
    pub mean: f64,
    /// Largest value.
    pub max: f64,
}

/// One channel.
#[derive(Debug, Serialize)]
pub struct ChannelInfo {
    /// imutherm's name.
    pub name: String,
    /// The file's name for it (header, field).
    pub source: String,
    /// What it measures.
    pub quantity: &'static str,
    /// Its unit.
    pub unit: String,
    /// Where the file's unit came from: header, flag, metadata or assumed.
    pub unit_source: &'static str,
    /// Mean of the finite samples.
    pub mean: Option<f64>,
    /// Sample standard deviation.
    pub std: Option<f64>,
    /// Smallest sample.
    pub min: Option<f64>,
    /// Largest sample.
    pub max: Option<f64>,
    /// NaN samples (gaps).
    pub nan_samples: usize,
}

/// One problem of the file.
#[derive(Debug, Serialize)]
pub struct ProblemInfo {
    /// Its kind (`bad_line`, `time_gap`, `stuck`, `overflow`, …).
    pub kind: &'static str,
    /// 1-based line, when it is a line's.
    pub line: Option<u64>,
    /// 1-based column, when it is a column's.
    pub column: Option<usize>,
    /// The channel, when it is a channel's.
    pub channel: Option<String>,
    /// How many times it occurs.
    pub count: usize,
    /// The sentence.
    pub message: String,
}

/// Mean, sample standard deviation, min, max and NaN count, skipping NaN.
/// Welford's update keeps the deviation right for a large mean (a gravity
/// axis, a temperature) with small fluctuations.
fn describe(data: &[f64]) -> (Option<(f64, f64, f64, f64)>, usize) {
    let (mut n, mut mean, mut m2) = (0usize, 0.0, 0.0);
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    let mut nan = 0;
    for &v in data {
        if v.is_nan() {
            nan += 1;
            continue;
        }
        n += 1;
        let d = v - mean;
        mean += d / n as f64;
        m2 += d * (v - mean);
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if n == 0 {
        return (None, nan);
    }
    let std = if n > 1 { (m2 / (n - 1) as f64).sqrt() } else { 0.0 };
    (Some((mean, std, lo, hi)), nan)
}

/// A problem for each channel whose values are finite but whose mean or
/// standard deviation is not: sums of values near ±1.8e308 overflow f64,
/// and a NaN statistic must not pass for a clean file.
fn overflows(channels: &[ChannelInfo]) -> Vec<ProblemInfo> {
    channels
        .iter()
        .filter(|c| {
            let finite = |v: Option<f64>| v.is_some_and(f64::is_finite);
            finite(c.min) && finite(c.max) && !(finite(c.mean) && finite(c.std))
        })
        .map(|c| ProblemInfo {
            kind: "overflow",
            line: None,
            column: None,
            channel: Some(c.name.clone()),
            count: 1,
            message: format!(
                "{}: its values ({:e} to {:e}) overflow double precision: the mean and standard deviation cannot be computed",
                c.name,
                c.min.unwrap_or(f64::NAN),
                c.max.unwrap_or(f64::NAN)
            ),
        })
        .collect()
}

/// A finding of the checks as a problem of the file (no line: it is the
/// whole channel's).
fn check_problem(f: &Finding) -> ProblemInfo {
    let (kind, channel, count) = match f {
        Finding::Stuck { channel, samples, .. } => ("stuck", Some(channel.clone()), *samples),
        Finding::Saturated { channel, samples, .. } => ("saturated", Some(channel.clone()), *samples),
        Finding::AccelNorm { .. } => ("accel_norm", None, 0),
        Finding::Motion(m) => ("motion", Some(m.channel.clone()), m.stretches.len()),
    };
    ProblemInfo {
        kind,
        line: None,
        column: None,
        channel,
        count,
        message: f.to_string(),
    }
}

/// A `# trailer:` line's fields, numbers as numbers (a count as an
/// integer, a finite decimal as a number), the rest as text.
fn logger_fields(trailer: &str) -> serde_json::Map<String, serde_json::Value> {
    imu::log_file::trailer_fields(trailer)
        .into_iter()
        .map(|(k, v)| {
            let number = v
                .parse::<u64>()
                .ok()
                .map(serde_json::Number::from)
                .or_else(|| v.parse::<f64>().ok().and_then(serde_json::Number::from_f64));
            let value = number.map_or_else(
                || serde_json::Value::String(v.to_string()),
                serde_json::Value::Number,
            );
            (k.to_string(), value)
        })
        .collect()
}

impl FileInfo {
    /// What `source` holds and what is wrong with it.
    pub fn of(source: &Source) -> FileInfo {
        let rec = &source.recording;
        let report = &source.report;
        let channels: Vec<ChannelInfo> = rec
            .channels
            .iter()
            .map(|c| {
                let (d, nan) = describe(&c.data);
                ChannelInfo {
                    name: c.name.clone(),
                    source: c.source_name.clone(),
                    quantity: c.quantity.name(),
                    unit: c.unit.clone(),
                    unit_source: c.unit_source.name(),
                    mean: d.map(|d| d.0),
                    std: d.map(|d| d.1),
                    min: d.map(|d| d.2),
                    max: d.map(|d| d.3),
                    nan_samples: nan,
                }
            })
            .collect();
        let checks = channel_checks::check(rec);
        let temperature_c = rec.temperature().and_then(|t| {
            let (d, _) = describe(&t.data);
            d.map(|(mean, _, min, max)| Range { min, mean, max })
        });
        let overflow = overflows(&channels);
        FileInfo {
            file: source.file_name(),
            format: source.format,
            device: rec.meta.device.clone(),
            start_time: rec.meta.start_time.clone(),
            samples: rec.len(),
            lines: report.lines,
            rate_hz: rec.rate_hz,
            rate_source: source.rate_source.name(),
            jitter_s: report.timing.as_ref().map(|t| t.jitter_s),
            clock: report.timing.as_ref().map(|t| Clock {
                backward_stamps: t.backwards.len(),
                duplicate_stamps: t.duplicates.len(),
                fitted_samples: t.fitted_samples,
                gaps: t.gaps.len(),
                jitter_s: t.jitter_s,
                median_step_s: t.median_step_s,
                pattern: ClockPattern::of(t),
                rate_hz: t.rate_hz,
            }),
            // An irregular publisher's samples are not one period apart:
            // its duration is the stamps' span.
            duration_s: match report.timing.as_ref() {
                Some(t) if matches!(t.pattern, Some(imu::clock_pattern::Pattern::Irregular { .. })) => {
                    Some(t.span_s)
                }
                _ => rec.duration_s(),
            },
            temperature_c,
            channels,
            problems: report
                .problems
                .iter()
                .map(|p| ProblemInfo {
                    kind: p.kind.name(),
                    line: p.line,
                    column: p.column,
                    channel: p.channel.clone(),
                    count: p.count,
                    message: p.message.clone(),
                })
                .chain(checks.findings.iter().map(check_problem))
                .chain(overflow)
                .collect(),
            problems_unlisted: report.unlisted,
            checks,
            dropped_samples: report.dropped_samples,
            notes: report.notes.clone(),
            logger: rec.meta.get(imu::log_file::TRAILER_KEY).map(logger_fields),
            log_metadata: if source.robot_log {
                rec.meta.entries.clone()
            } else {
                Vec::new()
            },
            streams: source.streams.clone(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_deviation_holds_for_a_large_mean() {
        // Welford's update: 1e9 + {1, 2, 3} has the deviation of {1, 2, 3}.
        let (d, nan) = describe(&[1e9 + 1.0, f64::NAN, 1e9 + 2.0, 1e9 + 3.0]);
        let (mean, std, lo, hi) = d.unwrap();
        assert_eq!((nan, mean, lo, hi), (1, 1e9 + 2.0, 1e9 + 1.0, 1e9 + 3.0));
        assert!((std - 1.0).abs() < 1e-9, "{std}");
        assert_eq!(describe(&[f64::NAN]).0, None);
    }

    #[test]
    fn trailer_numbers_stay_numbers_and_the_rest_text() {
        let m = logger_fields("samples=12 rate_measured_hz=99.5 stopped_by=signal odd=inf");
        assert_eq!(m["samples"], serde_json::json!(12));
        assert_eq!(m["rate_measured_hz"], serde_json::json!(99.5));
        assert_eq!(m["stopped_by"], serde_json::json!("signal"));
        // Not a finite number: JSON has none, so it stays the file's text.
        assert_eq!(m["odd"], serde_json::json!("inf"));
    }
}
