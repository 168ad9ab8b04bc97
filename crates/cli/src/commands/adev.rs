//! `imutherm adev`: Allan-family deviations of the columns of plain files.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use rayon::prelude::*;
use serde::Serialize;

use allan::{Curve, DataType, Options, Stat, TauSpec};
use imu::Quantity;
use imu::log::{ColumnKind, classify_with_overrides};
use imu::table::TableReader;
use imu::{RecordingOptions, read_recording_with_report};

use crate::args::AdevArgs;
use crate::commands::info::recording_options;

/// The JSON schema name, versioned: scripts rely on its fields.
const SCHEMA: &str = "imutherm.adev/1";

/// One column to analyse.
struct Channel {
    file: PathBuf,
    /// 1-based column number in the file.
    column: usize,
    name: String,
    unit: String,
    /// Sample rate, Hz.
    rate_hz: f64,
    /// Lines in the file, to say where the data ended.
    lines: u64,
    data: Vec<f64>,
}

pub fn run(a: &AdevArgs) -> Result<()> {
    let opts = options(a)?;
    let read = recording_options(&a.read)?;
    let mut channels = Vec::new();
    for file in &a.files {
        channels.extend(read_channels(file, &a.channels, &read)?);
    }
    let curves: Vec<Result<Curve>> = channels
        .par_iter()
        .map(|ch| {
            let opts = Options {
                rate_hz: ch.rate_hz,
                ..opts.clone()
            };
            allan::analyze(&ch.data, &opts).with_context(|| {
                format!(
                    "{}: column {} ({}): {} samples, data ends at line {}",
                    ch.file.display(),
                    ch.column,
                    ch.name,
                    ch.data.len(),
                    ch.lines
                )
            })
        })
        .collect();
    let curves = curves.into_iter().collect::<Result<Vec<_>>>()?;

    for (ch, curve) in channels.iter().zip(&curves) {
        if curve.nan_samples > 0 {
            eprintln!(
                "note: {}: {}: {} NaN samples treated as gaps (terms across them skipped)",
                ch.file.display(),
                ch.name,
                curve.nan_samples
            );
        }
    }
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    if a.json {
        write_json(&mut out, &opts, &channels, &curves)?;
    } else {
        write_tables(&mut out, &opts, &channels, &curves)?;
    }
    out.flush()?;
    Ok(())
}

fn options(a: &AdevArgs) -> Result<Options> {
    let stat: Stat = a.stat.parse()?;
    let taus: TauSpec = a.taus.parse()?;
    let data_type: DataType = a.data_type.parse()?;
    // "68.3" is as natural to type as "0.683"; anything else is a mistake.
    let confidence = if a.confidence >= 1.0 && a.confidence < 100.0 {
        a.confidence / 100.0
    } else {
        a.confidence
    };
    if !(confidence > 0.0 && confidence < 1.0) {
        bail!(
            "--confidence {}: give a level between 0 and 1 (0.683) or a percentage (68.3)",
            a.confidence
        );
    }
    Ok(Options {
        stat,
        data_type,
        rate_hz: a.read.rate.unwrap_or(1.0),
        taus,
        confidence,
    })
}

/// Reads the wanted channels of one file, converted to SI, with gaps where
/// the file has them.
fn read_channels(file: &Path, wanted: &[String], read: &RecordingOptions) -> Result<Vec<Channel>> {
    // The header alone decides what is selected, before the body is read.
    let reader = TableReader::open(file)?;
    let headers = reader.names().to_vec();
    let kinds: Vec<ColumnKind> = headers
        .iter()
        .map(|h| classify_with_overrides(h, &read.units))
        .collect();
    let inertial: Vec<usize> = (0..kinds.len()).filter(|&i| kinds[i].axis.is_some()).collect();
    let of = |q: Quantity| -> Vec<usize> {
        (0..kinds.len())
            .filter(|&i| kinds[i].quantity == q && kinds[i].axis.is_some())
            .collect()
    };
    let mut select: Vec<usize> = Vec::new();
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
        let group = match w.trim().to_ascii_lowercase().as_str() {
            "gyro" | "gyros" => Some(of(Quantity::AngularRate)),
            "accel" | "accels" | "acc" => Some(of(Quantity::Acceleration)),
            "inertial" | "imu" => Some(inertial.clone()),
            "all" => Some(
                (0..kinds.len())
                    .filter(|&i| kinds[i].quantity != Quantity::Time)
                    .collect(),
            ),
            _ => None,
        };
        let found = match group {
            Some(g) if !g.is_empty() => g,
            Some(_) => bail!(
                "{}: no '{}' channels (columns: {})",
                file.display(),
                w.trim(),
                headers.join(", ")
            ),
            None => match kinds.iter().position(|k| k.name.eq_ignore_ascii_case(w.trim())) {
                Some(i) => vec![i],
                None => vec![reader.column_index(w)?],
            },
        };
        for i in found {
            if !select.contains(&i) {
                select.push(i);
            }
        }
    }
    drop(reader);
    let (mut rec, report) = read_recording_with_report(file, read)?;
    for p in &report.problems {
        match p.line {
            Some(line) => eprintln!("warning: {}:{line}: {}", file.display(), p.message),
            None => eprintln!("warning: {}: {}", file.display(), p.message),
        }
    }
    if report.unlisted > 0 {
        eprintln!(
            "warning: {}: {} more problems not listed",
            file.display(),
            report.unlisted
        );
    }
    let rate_hz = match rec.rate_hz {
        Some(r) => r,
        None => {
            eprintln!(
                "note: {}: no sample rate given (--rate), recorded (# sample_rate_hz:) or timed; assuming 1 Hz",
                file.display()
            );
            1.0
        }
    };
    let mut out = Vec::with_capacity(select.len());
    for idx in select {
        let Some(pos) = rec.channels.iter().position(|c| c.source_name == headers[idx]) else {
            bail!(
                "{}: column {} ({}) is the time column, not a channel to analyse",
                file.display(),
                idx + 1,
                headers[idx]
            );
        };
        let ch = &mut rec.channels[pos];
        out.push(Channel {
            file: file.to_path_buf(),
            column: idx + 1,
            name: ch.name.clone(),
            unit: ch.unit.clone(),
            rate_hz,
            lines: report.lines,
            data: std::mem::take(&mut ch.data),
        });
    }
    Ok(out)
}

#[derive(Serialize)]
struct JsonDoc<'a> {
    schema: &'static str,
    imutherm_version: &'static str,
    stat: &'static str,
    data_type: &'static str,
    rate_hz: f64,
    confidence: f64,
    channels: Vec<JsonChannel<'a>>,
}

#[derive(Serialize)]
struct JsonChannel<'a> {
    name: &'a str,
    unit: &'a str,
    file: String,
    column: usize,
    rate_hz: f64,
    samples: usize,
    nan_samples: usize,
    points: Vec<JsonPoint>,
}

#[derive(Serialize)]
struct JsonPoint {
    tau: f64,
    m: usize,
    dev: f64,
    n: usize,
    edf: f64,
    dev_lo: f64,
    dev_hi: f64,
    alpha: i32,
    noise_id: &'static str,
}

fn write_json(out: &mut impl Write, opts: &Options, channels: &[Channel], curves: &[Curve]) -> Result<()> {
    let doc = JsonDoc {
        schema: SCHEMA,
        imutherm_version: env!("CARGO_PKG_VERSION"),
        stat: opts.stat.name(),
        data_type: opts.data_type.name(),
        // Every channel carries its own rate; this is the first file's.
        rate_hz: curves.first().map_or(opts.rate_hz, |c| c.rate_hz),
        confidence: opts.confidence,
        channels: channels
            .iter()
            .zip(curves)
            .map(|(ch, c)| JsonChannel {
                name: &ch.name,
                unit: &ch.unit,
                file: ch.file.display().to_string(),
                column: ch.column,
                rate_hz: c.rate_hz,
                samples: c.samples,
                nan_samples: c.nan_samples,
                points: c
                    .points
                    .iter()
                    .map(|p| JsonPoint {
                        tau: p.tau,
                        m: p.m,
                        dev: p.dev,
                        n: p.n,
                        edf: p.edf,
                        dev_lo: p.dev_lo,
                        dev_hi: p.dev_hi,
                        alpha: p.alpha,
                        noise_id: p.noise_id.name(),
                    })
                    .collect(),
            })
            .collect(),
    };
    serde_json::to_writer(&mut *out, &doc)?;
    writeln!(out)?;
    Ok(())
}

/// The unit of the deviation: the data's own, or its integral for the time
/// deviations (rad/s → rad, m/s² → m/s, fractional frequency → s).
fn deviation_unit(stat: Stat, data_type: DataType, unit: &str) -> String {
    let integral = stat.is_time_deviation();
    match (integral, data_type, unit) {
        (false, DataType::Freq, u) => u.to_string(),
        (true, DataType::Phase, u) => u.to_string(),
        (true, DataType::Freq, "") => "s".to_string(),
        (true, DataType::Freq, u) => format!("({u})·s"),
        (false, DataType::Phase, "") => String::new(),
        (false, DataType::Phase, u) => format!("({u})/s"),
    }
}

fn write_tables(out: &mut impl Write, opts: &Options, channels: &[Channel], curves: &[Curve]) -> Result<()> {
    for (i, (ch, c)) in channels.iter().zip(curves).enumerate() {
        if i > 0 {
            writeln!(out)?;
        }
        let unit = deviation_unit(opts.stat, opts.data_type, &ch.unit);
        let unit_label = if unit.is_empty() {
            String::new()
        } else {
            format!(" [{unit}]")
        };
        writeln!(
            out,
            "# {} — column {} '{}'{}: {} of {} data at {} Hz, {} samples, {} NaN gaps, {:.1} % intervals",
            ch.file.display(),
            ch.column,
            ch.name,
            if ch.unit.is_empty() {
                String::new()
            } else {
                format!(" [{}]", ch.unit)
            },
            opts.stat,
            opts.data_type,
            c.rate_hz,
            c.samples,
            c.nan_samples,
            100.0 * opts.confidence
        )?;
        let dev_head = format!("{}{}", opts.stat, unit_label);
        writeln!(
            out,
            "{:>12} {:>9} {:>14} {:>10} {:>10} {:>12} {:>12} {:>6}",
            "tau [s]", "m", dev_head, "n", "edf", "dev_lo", "dev_hi", "alpha"
        )?;
        for p in &c.points {
            writeln!(
                out,
                "{:>12.6e} {:>9} {:>14.6e} {:>10} {:>10.2} {:>12.5e} {:>12.5e} {:>6}",
                p.tau, p.m, p.dev, p.n, p.edf, p.dev_lo, p.dev_hi, p.alpha
            )?;
        }
    }
    Ok(())
}
