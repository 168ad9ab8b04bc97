//! `imutherm info`: what a recording holds and what is wrong with it.

use std::io::Write;
use std::path::Path;

use anyhow::Result;
use serde::Serialize;

use analysis::channel_checks::{self, Checks, Finding};
use analysis::reading::unit_text;
use analysis::robot_logs::{self, Stream};
use imu::{ReadReport, Recording, RecordingOptions};

use crate::args::InfoArgs;
use crate::flags::recording_options;

const SCHEMA: &str = "imutherm.info/1";

#[derive(Serialize)]
struct JsonDoc {
    schema: &'static str,
    imutherm_version: &'static str,
    files: Vec<FileInfo>,
}

#[derive(Serialize)]
struct FileInfo {
    file: String,
    format: &'static str,
    device: Option<String>,
    start_time: Option<String>,
    samples: usize,
    lines: u64,
    rate_hz: Option<f64>,
    rate_source: &'static str,
    jitter_s: Option<f64>,
    /// The time column's clock: the rate fitted to its stamps, the median
    /// step (what a rate read off the steps would say), the samples fitted.
    #[serde(skip_serializing_if = "Option::is_none")]
    clock: Option<serde_json::Value>,
    duration_s: Option<f64>,
    temperature_c: Option<Range>,
    channels: Vec<ChannelInfo>,
    problems: Vec<ProblemInfo>,
    problems_unlisted: usize,
    /// What the inertial channels rule out, with figures (each finding is
    /// also among `problems`, kinds `stuck`, `saturated`, `accel_norm`,
    /// `motion`).
    checks: Checks,
    dropped_samples: usize,
    /// What the reader guessed or found suspicious (a time unit guessed, a
    /// clock that disagrees with the given rate, an accelerometer in g).
    notes: Vec<String>,
    /// What `imutherm record` counted (its `# trailer:` line), numbers as
    /// numbers.
    #[serde(skip_serializing_if = "Option::is_none")]
    logger: Option<serde_json::Map<String, serde_json::Value>>,
    /// Every stream of a robot log (bag, ULog, DataFlash): topic or
    /// instance, messages, mean rate, temperature source.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    streams: Vec<Stream>,
    /// What a robot log's stream is read with: its metadata (stream, time
    /// source and why, device id).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    log_metadata: Vec<(String, String)>,
}

#[derive(Serialize)]
struct Range {
    min: f64,
    mean: f64,
    max: f64,
}

#[derive(Serialize)]
struct ChannelInfo {
    name: String,
    source: String,
    quantity: &'static str,
    unit: String,
    /// Where the file's unit came from: header, flag, metadata or assumed.
    unit_source: &'static str,
    mean: Option<f64>,
    std: Option<f64>,
    min: Option<f64>,
    max: Option<f64>,
    nan_samples: usize,
}

#[derive(Serialize)]
struct ProblemInfo {
    kind: &'static str,
    line: Option<u64>,
    column: Option<usize>,
    channel: Option<String>,
    count: usize,
    message: String,
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

fn file_info(
    path: &Path,
    rec: &Recording,
    report: &ReadReport,
    opts: &RecordingOptions,
    streams: Vec<Stream>,
) -> FileInfo {
    let robot = robot_logs::format_of(path);
    // The reader says which format it found.
    let format = robot.unwrap_or_else(|| report.format.name());
    let rate_source = if opts.rate_hz.is_some() {
        "given"
    } else if report.timing.is_some() && robot.is_some() {
        "derived from the message times"
    } else if report.timing.is_some() {
        "derived from the time column"
    } else if rec.rate_hz.is_some() {
        "file metadata"
    } else {
        "unknown"
    };
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
        file: path.display().to_string(),
        format,
        device: rec.meta.device.clone(),
        start_time: rec.meta.start_time.clone(),
        samples: rec.len(),
        lines: report.lines,
        rate_hz: rec.rate_hz,
        rate_source,
        jitter_s: report.timing.as_ref().map(|t| t.jitter_s),
        clock: report.timing.as_ref().map(|t| {
            serde_json::json!({
                "rate_hz": t.rate_hz,
                "jitter_s": t.jitter_s,
                "median_step_s": t.median_step_s,
                "fitted_samples": t.fitted_samples,
                "gaps": t.gaps.len(),
                "duplicate_stamps": t.duplicates.len(),
                "backward_stamps": t.backwards.len(),
            })
        }),
        duration_s: rec.duration_s(),
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
        logger: rec.meta.get(imu::log_file::TRAILER_KEY).map(|t| {
            imu::log_file::trailer_fields(t)
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
        }),
        log_metadata: if robot.is_some() {
            rec.meta.entries.clone()
        } else {
            Vec::new()
        },
        streams,
    }
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

pub fn run(a: &InfoArgs) -> Result<()> {
    let mut opts = recording_options(&a.read)?;
    // info lists every stream: with several and none chosen, it summarises
    // the first instead of refusing.
    opts.stream.first_if_several = true;
    let mut infos = Vec::new();
    for path in &a.files {
        let (rec, report, streams) = robot_logs::read_recording_with_report(path, &opts)?;
        infos.push(file_info(path, &rec, &report, &opts, streams));
    }
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    if a.json {
        let doc = JsonDoc {
            schema: SCHEMA,
            imutherm_version: env!("CARGO_PKG_VERSION"),
            files: infos,
        };
        serde_json::to_writer_pretty(&mut out, &doc)?;
        writeln!(out)?;
    } else {
        for (i, f) in infos.iter().enumerate() {
            if i > 0 {
                writeln!(out)?;
            }
            write_text(&mut out, f)?;
        }
    }
    out.flush()?;
    Ok(())
}

fn opt(v: Option<f64>, digits: usize) -> String {
    v.map_or_else(|| "—".to_string(), |v| format!("{v:.digits$e}"))
}

fn write_text(out: &mut impl Write, f: &FileInfo) -> Result<()> {
    writeln!(out, "{} ({})", f.file, f.format)?;
    if let Some(d) = &f.device {
        writeln!(out, "  device       {d}")?;
    }
    if let Some(t) = &f.start_time {
        writeln!(out, "  start        {t}")?;
    }
    if f.streams.is_empty() {
        writeln!(out, "  samples      {} ({} lines)", f.samples, f.lines)?;
    } else {
        let finite = f.channels.first().map_or(0, |c| f.samples - c.nan_samples);
        writeln!(
            out,
            "  samples      {} slots on the clock, {finite} of them messages ({} messages read)",
            f.samples, f.lines
        )?;
        writeln!(
            out,
            "  {:<4} {:<28} {:<12} {:>9} {:>12}  temperature",
            "", "stream", "kind", "messages", "mean rate"
        )?;
        for s in &f.streams {
            writeln!(
                out,
                "  {:<4} {:<28} {:<12} {:>9} {:>12}  {}",
                if s.selected { "read" } else { "" },
                s.name,
                s.kind,
                s.messages,
                s.rate_hz.map_or("—".to_string(), |r| format!(
                    "{} Hz",
                    imu::log_file::round_rate(r)
                )),
                s.temperature_source
            )?;
        }
        for (k, v) in &f.log_metadata {
            if let Some(label) = match k.as_str() {
                "device_id" => Some("device id"),
                "instance" => Some("instance"),
                "frame_id" => Some("frame id"),
                _ => None,
            } {
                writeln!(out, "  {label:<12} {v}")?;
            }
        }
    }
    match f.rate_hz {
        Some(r) => {
            let jitter = f
                .jitter_s
                .map(|j| format!(", jitter {:.3e} s", j))
                .unwrap_or_default();
            // A fitted rate to the digits that mean something, not
            // 99.99999999781721.
            let shown = imu::log_file::round_rate(r);
            writeln!(out, "  rate         {shown} Hz ({}{jitter})", f.rate_source)?;
            // Where the clock and the median step part, say so: that is
            // the case a rate read off the steps gets wrong.
            if let Some(step) = f
                .clock
                .as_ref()
                .and_then(|c| c["median_step_s"].as_f64())
                .filter(|s| (r * s - 1.0).abs() > 1e-3)
            {
                writeln!(
                    out,
                    "  clock        fitted to the stamps; the median step ({step:.6} s) would say {} Hz",
                    imu::log_file::round_rate(1.0 / step)
                )?;
            }
        }
        None => writeln!(
            out,
            "  rate         unknown (give --rate or record # sample_rate_hz:)"
        )?,
    }
    if let Some(d) = f.duration_s {
        writeln!(out, "  duration     {d:.3} s ({:.2} h)", d / 3600.0)?;
    }
    if let Some(t) = &f.temperature_c {
        writeln!(
            out,
            "  temperature  min {:.2} °C, mean {:.2} °C, max {:.2} °C",
            t.min, t.mean, t.max
        )?;
    }
    // A robot log's source names (`sensor_combined.gyro_rad[0]`) are
    // longer than a text header's: the column widens to the longest.
    let w = f
        .channels
        .iter()
        .map(|c| c.source.chars().count())
        .max()
        .unwrap_or(0)
        .max(22);
    writeln!(
        out,
        "  {:<10} {:<w$} {:<17} {:>14} {:>12} {:>13} {:>13} {:>7}",
        "channel", "column", "unit", "mean", "std", "min", "max", "NaN"
    )?;
    for c in &f.channels {
        writeln!(
            out,
            "  {:<10} {:<w$} {:<17} {:>14} {:>12} {:>13} {:>13} {:>7}",
            c.name,
            c.source,
            unit_text(&c.unit, c.unit_source, c.quantity),
            opt(c.mean, 6),
            opt(c.std, 4),
            opt(c.min, 5),
            opt(c.max, 5),
            c.nan_samples
        )?;
    }
    if let Some(l) = &f.logger {
        let get = |k: &str| {
            l.get(k)
                .map_or_else(|| "?".to_string(), |v| v.to_string().replace('"', ""))
        };
        writeln!(
            out,
            "  logger       {} samples read, {} lost in {} gaps ({} overflows, {} resyncs), {} bus errors; \
             stopped by {}; chip rate {}",
            get("samples"),
            get("gap_samples"),
            get("gaps"),
            get("overflows"),
            get("resyncs"),
            get("bus_errors"),
            get("stopped_by"),
            match l.get("rate_measured_hz").and_then(serde_json::Value::as_f64) {
                Some(r) => format!("measured {} Hz", imu::log_file::round_rate(r)),
                None => "not measured (under 5 s without a loss)".to_string(),
            },
        )?;
    }
    if f.problems.is_empty() {
        writeln!(out, "  problems     none")?;
    } else {
        writeln!(out, "  problems     {}", f.problems.len() + f.problems_unlisted)?;
        for p in &f.problems {
            let line = p.line.map(|l| format!("line {l}: ")).unwrap_or_default();
            writeln!(out, "    {line}{}", p.message)?;
        }
        if f.problems_unlisted > 0 {
            writeln!(out, "    … and {} more not listed", f.problems_unlisted)?;
        }
    }
    if f.dropped_samples > 0 {
        writeln!(
            out,
            "  dropped      {} rows written twice (stamp and values repeat the previous row)",
            f.dropped_samples
        )?;
    }
    for n in &f.notes {
        writeln!(out, "  note         {n}")?;
    }
    Ok(())
}
