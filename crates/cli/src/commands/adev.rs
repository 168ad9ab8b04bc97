//! `imutherm adev`: Allan-family deviations of the columns of plain files.

use std::io::{IsTerminal, Write};

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rayon::prelude::*;

use allan::{Curve, DataType, Options, Stat};

use crate::args::AdevArgs;
use analysis::adev_document::AdevDocument;
use analysis::reading::unit_text;
use analysis::selection::SelectedChannel;

use crate::print::{read_channels, refuse_overflowing};

pub fn run(a: &AdevArgs) -> Result<()> {
    let opts = options(a)?;
    let read = a.read.recording_options()?;
    let mut channels: Vec<SelectedChannel> = Vec::new();
    let mut notes = Vec::new();
    for file in &a.files {
        let sel = read_channels(file, &a.channels, &read)?;
        notes.extend(sel.notes);
        channels.extend(sel.channels);
    }
    refuse_overflowing(&channels)?;
    // The samples are handed over and turned into phase in place.
    let data: Vec<Vec<f64>> = channels.iter_mut().map(|c| std::mem::take(&mut c.data)).collect();
    let operations: u64 = channels
        .iter()
        .zip(&data)
        .map(|(ch, d)| {
            let opts = Options {
                rate_hz: ch.rate_hz,
                ..opts.clone()
            };
            allan::work::workload(d.len(), &opts).operations
        })
        .sum();
    let seconds = estimated_seconds(opts.stat, operations);
    if let Some(note) = estimate_note(opts.stat, operations, seconds) {
        eprintln!("{note}");
    }
    let bar = progress_bar(operations, seconds);
    let report = |ops: u64| bar.inc(ops);
    let curves: Vec<Result<Curve>> = channels
        .par_iter()
        .zip(data)
        .map(|(ch, data)| {
            let opts = Options {
                rate_hz: ch.rate_hz,
                ..opts.clone()
            };
            let samples = data.len();
            allan::analyze_vec_with_progress(data, &opts, &report).with_context(|| {
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
    bar.finish_and_clear();
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
        write_json(&mut out, &opts, &channels, &curves, notes)?;
    } else {
        write_tables(&mut out, &opts, &channels, &curves)?;
    }
    out.flush()?;
    Ok(())
}

/// Estimates above this many seconds get a progress bar (on a terminal).
const BAR_SECONDS: f64 = 1.0;

fn estimated_seconds(stat: Stat, operations: u64) -> f64 {
    allan::work::estimated_seconds(stat, operations, rayon::current_num_threads())
}

fn estimate_note(stat: Stat, operations: u64, seconds: f64) -> Option<String> {
    allan::work::long_run_note(stat, operations, seconds, rayon::current_num_threads())
        .map(|n| format!("note: {n}"))
}

/// A bar on stderr for long runs when stderr is a terminal; hidden
/// otherwise, so logs and pipes get no control characters (and stdout,
/// where `--json` goes, never sees it).
fn progress_bar(operations: u64, seconds: f64) -> ProgressBar {
    if !(seconds > BAR_SECONDS && std::io::stderr().is_terminal()) {
        return ProgressBar::hidden();
    }
    ProgressBar::with_draw_target(Some(operations), ProgressDrawTarget::stderr()).with_style(
        ProgressStyle::with_template("{spinner} computing [{bar:40}] {percent:>3} %, {eta} left")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    )
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

fn write_json(
    out: &mut impl Write,
    opts: &Options,
    channels: &[SelectedChannel],
    curves: &[Curve],
    notes: Vec<String>,
) -> Result<()> {
    let doc = AdevDocument::new(env!("CARGO_PKG_VERSION"), opts, channels, curves).with_notes(notes);
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_runs_are_announced_in_a_readable_unit() {
        assert_eq!(estimate_note(Stat::Mtotdev, 1_000, 0.5), None);
        let note = estimate_note(Stat::Mtotdev, 2_500_000_000_000, 232.0).unwrap();
        assert!(
            note.contains("about 4 min") && note.contains("2.500e12 operations"),
            "{note}"
        );
        assert!(
            estimate_note(Stat::Htotdev, 1, 53.0 * 3600.0)
                .unwrap()
                .contains("about 53.0 h")
        );
        assert!(
            estimate_note(Stat::Theo1, 1, 10.0)
                .unwrap()
                .contains("about 10 s")
        );
    }

    #[test]
    fn the_estimate_scales_with_the_operations() {
        let one = estimated_seconds(Stat::Mtotdev, 1_000_000_000);
        assert!(one > 0.0 && one.is_finite(), "{one}");
        assert_eq!(estimated_seconds(Stat::Mtotdev, 0), 0.0);
    }
}
