//! `imutherm info`: what a recording holds and what is wrong with it.

use std::io::Write;

use anyhow::Result;

use analysis::info_document::{FileInfo, InfoDocument};
use analysis::reading::unit_text;
use analysis::source::read_source;

use crate::args::InfoArgs;

pub fn run(a: &InfoArgs) -> Result<()> {
    let mut opts = a.read.recording_options()?;
    // info lists every stream: with several and none chosen, it summarises
    // the first instead of refusing.
    opts.stream.first_if_several = true;
    let mut infos = Vec::new();
    for path in &a.files {
        infos.push(FileInfo::of(&read_source(path, &opts)?));
    }
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    if a.json {
        let doc = InfoDocument::new(env!("CARGO_PKG_VERSION"), infos);
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
            "", "stream", "kind", "messages", "rate"
        )?;
        for s in &f.streams {
            // The rate between messages, as the clock reads it; the mean
            // over the span is said below where gaps pull it down.
            writeln!(
                out,
                "  {:<4} {:<28} {:<12} {:>9} {:>12}  {}",
                if s.selected { "read" } else { "" },
                s.name,
                s.kind,
                s.messages,
                s.step_rate_hz.or(s.rate_hz).map_or("—".to_string(), |r| format!(
                    "{} Hz",
                    imu::log_file::round_rate(r)
                )),
                s.temperature_source
            )?;
        }
        for s in &f.streams {
            if let Some(line) = coverage(s) {
                writeln!(out, "  {line}")?;
            }
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
                .map(|c| c.median_step_s)
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

/// Where a stream's messages stop for part of the log: its rate between
/// messages, the share of the span it covers and its mean over the span.
fn coverage(s: &analysis::robot_logs::Stream) -> Option<String> {
    let (step, mean) = (s.step_rate_hz?, s.rate_hz?);
    let share = mean / step;
    (share < 0.95 && s.messages > 1).then(|| {
        let span = (s.messages - 1) as f64 / mean;
        format!(
            "{} logs at {} Hz for about {:.0} % of its {span:.1} s ({} Hz on average): the rest are gaps",
            s.name,
            imu::log_file::round_rate(step),
            100.0 * share,
            imu::log_file::round_rate(mean)
        )
    })
}
