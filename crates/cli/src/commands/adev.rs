//! `imutherm adev`: Allan-family deviations of the columns of plain files.

use std::io::Write;

use anyhow::{Context, Result};
use rayon::prelude::*;
use serde::Serialize;

use allan::{Curve, DataType, Options, Stat};

use crate::args::AdevArgs;
use analysis::reading::unit_text;
use analysis::selection::SelectedChannel;

use crate::flags::recording_options;
use crate::print::read_channels;

/// The JSON schema name, versioned: scripts rely on its fields.
const SCHEMA: &str = "imutherm.adev/1";

pub fn run(a: &AdevArgs) -> Result<()> {
    let opts = options(a)?;
    let read = recording_options(&a.read)?;
    let mut channels: Vec<SelectedChannel> = Vec::new();
    for file in &a.files {
        channels.extend(read_channels(file, &a.channels, &read)?.channels);
    }
    // The samples are handed over and turned into phase in place.
    let data: Vec<Vec<f64>> = channels.iter_mut().map(|c| std::mem::take(&mut c.data)).collect();
    let curves: Vec<Result<Curve>> = channels
        .par_iter()
        .zip(data)
        .map(|(ch, data)| {
            let opts = Options {
                rate_hz: ch.rate_hz,
                ..opts.clone()
            };
            let samples = data.len();
            allan::analyze_vec(data, &opts).with_context(|| {
                format!(
                    "{}: column {} ({}): {} samples, data ends at line {}",
                    ch.file.display(),
                    ch.column,
                    ch.name,
                    samples,
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
    Ok(Options {
        stat: a.stat,
        data_type: a.data_type,
        rate_hz: a.read.rate.unwrap_or(1.0),
        taus: a.taus.clone(),
        confidence: a.confidence,
    })
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
    /// Where the file's unit came from: header, flag, metadata or assumed.
    unit_source: &'static str,
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

fn write_json(
    out: &mut impl Write,
    opts: &Options,
    channels: &[SelectedChannel],
    curves: &[Curve],
) -> Result<()> {
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
                unit_source: ch.unit_source.name(),
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

fn write_tables(
    out: &mut impl Write,
    opts: &Options,
    channels: &[SelectedChannel],
    curves: &[Curve],
) -> Result<()> {
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
                format!(
                    " [{}]",
                    unit_text(&ch.unit, ch.unit_source.name(), ch.quantity.name())
                )
            },
            opts.stat,
            opts.data_type,
            imu::log_file::round_rate(c.rate_hz),
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
