//! `imutherm thermal`: the Allan deviation over temperature.

use std::io::Write;

use anyhow::{Context, Result, bail};
use rayon::prelude::*;

use allan::noise_terms::{Term, TermEstimate};
use analysis::thermal_document::{SlicedChannel, ThermalDocument};
use thermal::surface::{Slicing, Surface, slices};

use crate::args::{SliceBy, ThermalArgs};
use crate::print::read_channels;

pub fn run(a: &ThermalArgs) -> Result<()> {
    let confidence = a.confidence;
    let slicing = match a.by {
        SliceBy::Temperature => Slicing::Temperature {
            bin_width_c: a.bin_width,
        },
        SliceBy::Time => Slicing::Time {
            window_s: a.window,
            step_s: a.step.unwrap_or(a.window / 2.0),
        },
    };
    let read = a.read.recording_options()?;
    let sel = read_channels(&a.file, &a.channels, &read)?;
    crate::print::refuse_overflow(&sel)?;
    let Some(temp) = &sel.temperature else {
        bail!(
            "{}: no temperature channel (a column named temp…, or with a °C/K unit)",
            a.file.display()
        );
    };
    let surfaces: Vec<(String, String, Surface)> = sel
        .channels
        .par_iter()
        .map(|ch| {
            slices(&ch.data, temp, sel.rate_hz, slicing, confidence)
                .with_context(|| format!("{}: {}", a.file.display(), ch.name))
                .map(|s| (ch.name.clone(), ch.unit.clone(), s))
        })
        .collect::<Result<_>>()?;
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    if a.json {
        let channels: Vec<SlicedChannel<'_>> = surfaces
            .iter()
            .map(|(name, unit, surface)| SlicedChannel { name, unit, surface })
            .collect();
        let doc = ThermalDocument::new(
            env!("CARGO_PKG_VERSION"),
            a.file.display().to_string(),
            slicing,
            sel.rate_hz,
            confidence,
            &channels,
        );
        serde_json::to_writer_pretty(&mut out, &doc)?;
        writeln!(out)?;
    } else {
        let (label, unit) = match slicing {
            Slicing::Temperature { .. } => ("bin [°C]", "°C"),
            Slicing::Time { .. } => ("window [s]", "s"),
        };
        for (name, ch_unit, surface) in &surfaces {
            let rows = &surface.rows;
            writeln!(
                out,
                "# {name} [{ch_unit}] — OADEV over {label}, N and B from the fit (n/i: not identified, the slice's data do not hold the term)"
            )?;
            let taus: Vec<f64> =
                rows.iter()
                    .flat_map(|r| r.points.iter().map(|p| p.tau))
                    .fold(Vec::new(), |mut v, t| {
                        if !v.iter().any(|x: &f64| (x - t).abs() < 1e-12) {
                            v.push(t);
                        }
                        v
                    });
            let mut head = format!("{:>16} {:>8} {:>8}", label, "T [°C]", "ΔT [°C]");
            for t in taus.iter().take(12) {
                head.push_str(&format!(" {:>10}", format!("τ={t:.3}")));
            }
            head.push_str(&format!(" {:>11} {:>11}", "N", "B"));
            writeln!(out, "{head}")?;
            for r in rows {
                let mut line = format!(
                    "{:>16} {:>8.2} {:>8.2}",
                    format!("{:.1}–{:.1} {unit}", r.start, r.end),
                    r.t_mean_c,
                    r.t_change_c
                );
                for t in taus.iter().take(12) {
                    match r.points.iter().find(|p| (p.tau - t).abs() < 1e-12) {
                        Some(p) => line.push_str(&format!(" {:>10.3e}", p.dev)),
                        None => line.push_str(&format!(" {:>10}", "—")),
                    }
                }
                for term in [Term::WhiteNoise, Term::BiasInstability] {
                    match r.terms.model.get(term) {
                        TermEstimate::Value(v) => line.push_str(&format!(" {:>11.3e}", v.value)),
                        TermEstimate::NotIdentifiable(_) => line.push_str(&format!(" {:>11}", "n/i")),
                    }
                }
                writeln!(out, "{line}")?;
            }
            match analysis::term_law::surface_laws(surface, slicing, confidence) {
                Some(laws) => {
                    for law in laws.iter().filter(|l| l.fit.is_some()) {
                        writeln!(out, "# {}", law.describe(name))?;
                    }
                    let named: Vec<(&str, analysis::term_law::Law)> =
                        laws.into_iter().map(|l| (name.as_str(), l)).collect();
                    if let Some(rest) = analysis::term_law::without_law(&named) {
                        writeln!(out, "# {rest}")?;
                    }
                }
                None => writeln!(
                    out,
                    "# no law over temperature: the windows overlap, their terms are not independent"
                )?,
            }
            for k in &surface.skipped {
                writeln!(
                    out,
                    "# no curve for {:.1}–{:.1} {unit}: {}",
                    k.start, k.end, k.reason
                )?;
            }
            writeln!(out)?;
        }
    }
    out.flush()?;
    Ok(())
}
