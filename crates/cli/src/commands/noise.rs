//! `imutherm noise`: the noise terms of each axis from its selected noise
//! model, with intervals and units, a thesis-style table over temperature,
//! the filters' parameters, and Kalibr's imu.yaml.

use std::fmt::Write as _;
use std::io::Write;
use std::path::Path;

use allan::noise_terms::{Chosen, Minimum, NoiseTerms, Term, TermEstimate, TermValue, analyze_terms_vec};
use anyhow::{Context, Result, bail};
use imu::Quantity;
use rayon::prelude::*;

use analysis::filters::filter_params;
use analysis::kalibr::{KalibrChannel, kalibr_yaml};
use analysis::noise_document::{ChannelInput, NoiseDocument};
use analysis::reading::unit_text;
use analysis::selection::SelectedChannel;
use analysis::thesis::ThesisTables;
use analysis::units::{Units, density_of, unit_of};

use crate::args::{NoiseArgs, TermUnits};
use crate::print::read_static_channels;

struct Analysed {
    file_index: usize,
    /// The channel, its samples gone into the analysis.
    channel: SelectedChannel,
    /// Number of samples the analysis took, gaps included.
    samples: usize,
    terms: NoiseTerms,
}

/// What every writer reads: the analysed channels and, per file, its
/// name, mean temperature and rate, with the confidence the intervals hold.
#[derive(Clone, Copy)]
struct Analysis<'a> {
    analysed: &'a [Analysed],
    files: &'a [std::path::PathBuf],
    temps: &'a [Option<f64>],
    rates: &'a [f64],
    confidence: f64,
    notes: &'a [Vec<String>],
}

pub fn run(a: &NoiseArgs) -> Result<()> {
    // Refused before the analysis, not after it.
    if let Some(path) = &a.kalibr {
        imu::output::check_output(
            path,
            &imu::output::OutputPolicy {
                overwrite: a.overwrite,
                inputs: &a.files,
            },
        )?;
    }
    let units = match a.units {
        TermUnits::Si => Units::Si,
        TermUnits::Datasheet => Units::Datasheet,
    };
    let confidence = a.confidence;
    let read = a.read.recording_options()?;
    let mut temps = Vec::new();
    let mut rates = Vec::new();
    let mut work = Vec::new();
    let mut notes = Vec::new();
    for (i, file) in a.files.iter().enumerate() {
        let sel = read_static_channels(file, &a.channels, &read, a.motion.allow_motion)?;
        notes.push(sel.notes.clone());
        // Noise terms are an inertial sensor's: without a recognised axis
        // (and no explicit choice) the header is not one imutherm knows.
        if a.channels.is_empty()
            && !sel
                .channels
                .iter()
                .any(|c| matches!(c.quantity, Quantity::Acceleration | Quantity::AngularRate))
        {
            bail!(
                "{}: no accelerometer or gyroscope column recognised in the header ({}); name them \
                 accel_x…gyro_z or mpu_gyro_1…, give units in brackets (gyro_x[deg/s]), or pick \
                 columns with --channels",
                file.display(),
                sel.channels
                    .iter()
                    .map(|c| c.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            );
        }
        // A channel stuck at one value has no noise to read: said as such,
        // not as a fit short of points.
        let names: Vec<&str> = sel.channels.iter().map(|c| c.name.as_str()).collect();
        if let Err(e) = sel.checks.require_static(&names, true) {
            bail!("{}: {e}; leave the channel out with --channels", file.display());
        }
        // The temperature column's mean, measured; else what the metadata states.
        temps.push(sel.temperature_mean_c.or(sel.recording.temperature_c));
        rates.push(sel.rate_hz);
        work.extend(sel.channels.into_iter().map(|c| (i, c)));
    }
    let analysed: Vec<Analysed> = work
        .into_par_iter()
        .map(|(file_index, mut channel)| {
            // Turned into phase in place: no second copy of a long channel.
            let data = std::mem::take(&mut channel.data);
            let samples = data.len();
            let (_, terms) = analyze_terms_vec(data, channel.rate_hz, confidence)
                .with_context(|| format!("{}: {}", channel.file.display(), channel.name))?;
            Ok(Analysed {
                file_index,
                channel,
                samples,
                terms,
            })
        })
        .collect::<Result<Vec<_>>>()?;

    for r in &analysed {
        let m = &r.terms.model;
        if !m.fits {
            eprintln!(
                "warning: {}: {}: no candidate noise model fits the curve{}; its terms are given as upper bounds{}",
                r.channel.file.display(),
                r.channel.name,
                m.quality
                    .map(|q| format!(
                        " (best {}: χ²/dof {:.2}, p = {:.1e})",
                        m.label, q.chi2_reduced, q.p_value
                    ))
                    .unwrap_or_default(),
                m.defeat
                    .as_ref()
                    .map(|d| format!("; {}", d.describe()))
                    .unwrap_or_default()
            );
        }
    }
    // The analysis is printed first, whatever becomes of the yaml.
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    let analysis = Analysis {
        analysed: &analysed,
        files: &a.files,
        temps: &temps,
        rates: &rates,
        confidence,
        notes: &notes,
    };
    if a.json {
        write_json(&mut out, analysis, units)?;
    } else if a.verbose {
        write_text(&mut out, analysis, units)?;
    } else {
        write_compact(&mut out, analysis, units)?;
        if a.files.len() > 1 {
            write_thesis_tables(&mut out, analysis, units)?;
        }
    }
    out.flush()?;
    if let Some(path) = &a.kalibr {
        write_kalibr(path, analysis, a.overwrite)?;
        eprintln!("wrote {}", path.display());
    }
    Ok(())
}

/// A number to three significant figures, fixed between 0.01 and 10 000,
/// in scientific notation outside.
fn sig3(v: f64) -> String {
    let a = v.abs();
    if !v.is_finite() {
        return format!("{v}");
    }
    if a == 0.0 || (0.01..10_000.0).contains(&a) {
        let digits = if a == 0.0 {
            2
        } else {
            (2 - a.log10().floor() as i32).max(0) as usize
        };
        format!("{v:.digits$}")
    } else {
        format!("{v:.2e}")
    }
}

/// The cell of a term in the compact table: the model's value with its
/// interval, or "≤ bound".
fn compact_cell(r: &Analysed, term: Term, units: Units) -> String {
    let ch = &r.channel;
    let (f, _) = unit_of(term, ch.quantity, &ch.unit, units);
    match r.terms.choose(term).chosen {
        Chosen::Model(v) => format!("{} [{}, {}]", sig3(v.value * f), sig3(v.lo * f), sig3(v.hi * f)),
        Chosen::Bound(b) => format!("≤ {}", sig3(b * f)),
        Chosen::Nothing => "—".to_string(),
    }
}

/// One compact table per file: rows are axes, columns the terms, each
/// cell the estimate that holds with its interval; units in the header.
fn write_compact(out: &mut impl Write, analysis: Analysis, units: Units) -> Result<()> {
    for (i, f) in analysis.files.iter().enumerate() {
        let rows: Vec<&Analysed> = analysis.analysed.iter().filter(|r| r.file_index == i).collect();
        let t = analysis.temps[i]
            .map(|t| format!(", mean temperature {t:.1} °C"))
            .unwrap_or_default();
        let samples = rows.first().map_or(0, |r| r.samples);
        writeln!(
            out,
            "# {} — {} Hz, {:.0} s{t}; intervals at {:.1} %",
            f.display(),
            imu::log_file::round_rate(analysis.rates[i]),
            samples as f64 / analysis.rates[i],
            100.0 * analysis.confidence
        )?;
        let mut groups: Vec<(Quantity, String)> = Vec::new();
        for r in &rows {
            if !groups
                .iter()
                .any(|(q, u)| *q == r.channel.quantity && *u == r.channel.unit)
            {
                groups.push((r.channel.quantity, r.channel.unit.clone()));
            }
        }
        let mut any_bound = false;
        for (q, unit) in groups {
            let members: Vec<&&Analysed> = rows
                .iter()
                .filter(|r| r.channel.quantity == q && r.channel.unit == unit)
                .collect();
            // Q and R get a column only where some axis shows them.
            let terms: Vec<Term> = Term::ALL
                .into_iter()
                .filter(|t| {
                    matches!(t, Term::WhiteNoise | Term::BiasInstability | Term::RateRandomWalk)
                        || members
                            .iter()
                            .any(|r| matches!(r.terms.choose(*t).chosen, Chosen::Model(_)))
                })
                .collect();
            let assumed = members
                .iter()
                .any(|r| r.channel.unit_source == imu::UnitSource::Assumed);
            let data_unit = if unit.is_empty() {
                "-".to_string()
            } else {
                unit.clone()
            };
            let label = format!(
                "{} [{data_unit}{}]",
                match q {
                    Quantity::AngularRate => "gyro",
                    Quantity::Acceleration => "accel",
                    _ => "channel",
                },
                if assumed { ", assumed" } else { "" }
            );
            let cells: Vec<Vec<String>> = members
                .iter()
                .map(|r| terms.iter().map(|&t| compact_cell(r, t, units)).collect())
                .collect();
            let heads: Vec<String> = terms
                .iter()
                .map(|&t| format!("{} [{}]", t.symbol(), unit_of(t, q, &unit, units).1))
                .collect();
            let width: Vec<usize> = (0..terms.len())
                .map(|k| {
                    cells
                        .iter()
                        .map(|c| c[k].chars().count())
                        .chain([heads[k].chars().count()])
                        .max()
                        .unwrap_or(0)
                })
                .collect();
            let name_w = members
                .iter()
                .map(|r| r.channel.name.chars().count())
                .chain([label.chars().count()])
                .max()
                .unwrap_or(8);
            let pad = |text: &str, w: usize| {
                format!("{text}{}", " ".repeat(w.saturating_sub(text.chars().count())))
            };
            let mut line = pad(&label, name_w);
            for (k, h) in heads.iter().enumerate() {
                line.push_str("  ");
                line.push_str(&pad(h, width[k]));
            }
            writeln!(out, "{}", line.trim_end())?;
            for (r, row) in members.iter().zip(&cells) {
                let mut line = pad(&r.channel.name, name_w);
                for (k, c) in row.iter().enumerate() {
                    line.push_str("  ");
                    line.push_str(&pad(c, width[k]));
                    any_bound |= c.starts_with('≤');
                }
                writeln!(out, "{}", line.trim_end())?;
            }
            // Each axis's model, and its Gauss–Markov terms.
            for r in &members {
                let m = &r.terms.model;
                let quality = m.quality.map_or_else(
                    || "no admissible candidate".to_string(),
                    |q| format!("χ²/dof {:.2}, p = {:.2}", q.chi2_reduced, q.p_value),
                );
                let verdict = if m.fits {
                    model_notes(m, &r.channel.unit)
                        .iter()
                        .map(|n| format!("; {n}"))
                        .collect()
                } else {
                    format!(
                        " — does not fit: terms are bounds{}",
                        m.defeat
                            .as_ref()
                            .map(|d| format!("; {}", d.describe()))
                            .unwrap_or_default()
                    )
                };
                let gm: Vec<String> = m
                    .gauss_markov
                    .iter()
                    .map(|g| {
                        format!(
                            "; GM σ = {} [{}, {}] {unit}, T = {} [{}, {}] s",
                            sig3(g.sigma.value),
                            sig3(g.sigma.lo),
                            sig3(g.sigma.hi),
                            sig3(g.tau_c.value),
                            sig3(g.tau_c.lo),
                            sig3(g.tau_c.hi)
                        )
                    })
                    .collect();
                writeln!(
                    out,
                    "  model ({}): {} ({quality}){verdict}{}",
                    r.channel.name,
                    m.label,
                    gm.concat()
                )?;
            }
            if let Some(r) = members.first()
                && r.terms.slope.minimum == Minimum::StillFalling
            {
                writeln!(
                    out,
                    "  σ_min ({}): no minimum within the record; the ADEV still falls at the longest τ \
                     with ≥ {} degrees of freedom",
                    r.channel.name,
                    allan::noise_terms::MIN_EDF
                )?;
            }
        }
        if any_bound {
            writeln!(
                out,
                "  ≤ not in the selected model: an upper bound (no term's share of σ² exceeds the upper end of \
                 σ²'s {:.0} % interval at any τ)",
                100.0 * allan::noise_model::CEILING_CONFIDENCE
            )?;
        }
        writeln!(out)?;
    }
    Ok(())
}

fn write_json(out: &mut impl Write, analysis: Analysis, units: Units) -> Result<()> {
    let channels: Vec<ChannelInput> = analysis
        .analysed
        .iter()
        .map(|r| ChannelInput {
            file_index: r.file_index,
            channel: &r.channel,
            samples: r.samples,
            terms: &r.terms,
        })
        .collect();
    let doc = NoiseDocument::new(
        analysis.files,
        analysis.temps,
        analysis.rates,
        &channels,
        analysis.confidence,
        units,
    )
    .with_notes(analysis.notes.to_vec());
    serde_json::to_writer_pretty(&mut *out, &doc)?;
    writeln!(out)?;
    Ok(())
}

fn fmt_est(est: &TermEstimate, term: Term, ch: &SelectedChannel, units: Units) -> String {
    match est {
        TermEstimate::Value(v) => {
            let (f, unit) = unit_of(term, ch.quantity, &ch.unit, units);
            let mut text = format!("{:.4e} [{:.3e}, {:.3e}] {unit}", v.value * f, v.lo * f, v.hi * f);
            if units == Units::Datasheet
                && term == Term::WhiteNoise
                && let Some((d, du)) = density_of(ch.quantity)
            {
                text.push_str(&format!(" = {:.4e} {du}", v.value * d));
            }
            text
        }
        TermEstimate::NotIdentifiable(why) => why.clone(),
    }
}

fn write_text(out: &mut impl Write, analysis: Analysis, units: Units) -> Result<()> {
    for (i, f) in analysis.files.iter().enumerate() {
        let t = analysis.temps[i]
            .map(|t| format!(", mean temperature {t:.1} °C"))
            .unwrap_or_default();
        writeln!(
            out,
            "# {}{t} — intervals at {:.1} %",
            f.display(),
            100.0 * analysis.confidence
        )?;
        for r in analysis.analysed.iter().filter(|r| r.file_index == i) {
            let ch = &r.channel;
            let m = &r.terms.model;
            writeln!(
                out,
                "{} [{}]",
                ch.name,
                unit_text(&ch.unit, ch.unit_source.name(), ch.quantity.name())
            )?;
            match m.quality {
                Some(q) => writeln!(
                    out,
                    "  model {}: χ² = {:.2} on {} degrees of freedom (χ²/dof {:.2}, p = {:.3}), criterion {:.1}; {}",
                    m.label,
                    q.chi2,
                    q.dof,
                    q.chi2_reduced,
                    q.p_value,
                    q.criterion,
                    if m.within_noise {
                        "it fits the curve"
                    } else if m.fits {
                        "it describes the curve to within 5 %, not within the points' noise: the misfit widens the intervals"
                    } else {
                        "no candidate fits the curve: every term is given as its upper bound"
                    }
                )?,
                None => writeln!(out, "  model: none admissible on {} points", m.points)?,
            }
            for note in model_notes(m, &ch.unit) {
                writeln!(out, "  {note}")?;
            }
            if let Some(d) = &m.defeat {
                writeln!(out, "  where no candidate fits: {}", d.describe())?;
            }
            if !m.evidence.is_empty() {
                writeln!(
                    out,
                    "  kept because the criterion is worse without it by: {}",
                    m.evidence
                        .iter()
                        .map(|(l, d)| if d.is_finite() {
                            format!("{l} {d:.1}")
                        } else {
                            format!("{l} (no admissible model without it)")
                        })
                        .collect::<Vec<_>>()
                        .join(", ")
                )?;
            }
            if m.candidates.len() > 1 {
                writeln!(
                    out,
                    "  next candidates: {}",
                    m.candidates
                        .iter()
                        .skip(1)
                        .map(|c| format!("{} ({:.1})", c.label, c.criterion))
                        .collect::<Vec<_>>()
                        .join(", ")
                )?;
            }
            if !m.outside.is_empty() {
                writeln!(
                    out,
                    "  the model's curve leaves the measured interval at τ = {} s",
                    taus_text(&m.outside)
                )?;
            }
            if !m.left_out.is_empty() {
                writeln!(
                    out,
                    "  left out of the fit, as no candidate process (a bump, a tone): τ = {} s",
                    taus_text(&m.left_out)
                )?;
            }
            for term in Term::ALL {
                writeln!(
                    out,
                    "  {}  {}",
                    term.symbol(),
                    fmt_est(m.get(term), term, ch, units)
                )?;
            }
            for g in &m.gauss_markov {
                writeln!(
                    out,
                    "  GM σ = {:.4e} [{:.3e}, {:.3e}] {}, T = {:.4e} [{:.3e}, {:.3e}] s",
                    g.sigma.value, g.sigma.lo, g.sigma.hi, ch.unit, g.tau_c.value, g.tau_c.lo, g.tau_c.hi
                )?;
            }
            if let Some(sm) = &r.terms.slope.sigma_min {
                let (fct, unit) = unit_of(Term::BiasInstability, ch.quantity, &ch.unit, units);
                writeln!(
                    out,
                    "  σ_min (ADEV minimum among points with ≥ {} degrees of freedom) {:.4e} [{:.4e}, {:.4e}] {unit} \
                     at τ = {:.4} s{}",
                    allan::noise_terms::MIN_EDF,
                    sm.value * fct,
                    sm.lo * fct,
                    sm.hi * fct,
                    sm.tau.unwrap_or(f64::NAN),
                    if r.terms.slope.minimum == Minimum::Found {
                        ""
                    } else {
                        " (no minimum within the record)"
                    }
                )?;
            }
            let th = &r.terms.slope.thesis;
            let reading = |v: Option<TermValue>, term: Term| {
                let (f, u) = unit_of(term, ch.quantity, &ch.unit, units);
                v.map_or_else(
                    || "—".to_string(),
                    |v| {
                        format!(
                            "{:.4e} {u} (at τ = {:.4} s)",
                            v.value * f,
                            v.tau.unwrap_or(f64::NAN)
                        )
                    },
                )
            };
            writeln!(
                out,
                "  the thesis's reading (analyzeAllan.m: slope nearest −1/2; σ at the first τ where the slope turns \
                 positive): N {}, B {}",
                reading(th.n, Term::WhiteNoise),
                reading(th.b, Term::BiasInstability),
            )?;
            for fp in filter_params(ch.quantity, &r.terms).unwrap_or_default() {
                let params: Vec<String> = fp
                    .params
                    .iter()
                    .map(|p| {
                        format!(
                            "{} = {:.4e} {} ({}; {})",
                            p.name, p.value, p.unit, p.formula, p.source
                        )
                    })
                    .collect();
                writeln!(
                    out,
                    "  {}: {}{}",
                    fp.filter,
                    params.join(", "),
                    if fp.left_out.is_empty() {
                        String::new()
                    } else {
                        format!("; not in its model: {}", fp.left_out.join(", "))
                    }
                )?;
            }
        }
        writeln!(out)?;
    }
    if analysis.files.len() > 1 {
        write_thesis_tables(out, analysis, units)?;
    }
    Ok(())
}

/// Averaging times in seconds, as the text report lists them.
fn taus_text(taus: &[f64]) -> String {
    taus.iter()
        .map(|t| format!("{t:.4}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The thesis's layout: one table per term, rows = axes, columns = the
/// files' mean temperatures; N from the selected model, σ_min as the thesis
/// quotes it beside the model's B, in the thesis's units (°/√s, °/s) or
/// the datasheet's.
fn write_thesis_tables(out: &mut impl Write, analysis: Analysis, units: Units) -> Result<()> {
    let units = if units == Units::Datasheet {
        Units::Datasheet
    } else {
        Units::Thesis
    };
    let tables = ThesisTables::new(
        analysis.temps.to_vec(),
        analysis
            .analysed
            .iter()
            .map(|r| (r.file_index, &r.channel, &r.terms)),
    );
    let header: Vec<String> = tables
        .columns
        .iter()
        .enumerate()
        .map(|(i, t)| t.map_or_else(|| format!("file {}", i + 1), |t| format!("{t:.0}°C")))
        .collect();
    for group in &tables.groups {
        let (q, title) = (group.quantity, group.title);
        for (term, what) in [
            (
                Term::WhiteNoise,
                if q == Quantity::AngularRate {
                    "Angle random walk N"
                } else {
                    "Velocity random walk N"
                },
            ),
            (
                Term::BiasInstability,
                "Bias instability: σ_min (at τ), as the thesis quotes it; B of the selected model",
            ),
        ] {
            let (_, unit) = unit_of(term, q, group.data_unit(), units);
            let mut line = format!("{title} — {what} [{unit}] (selected noise model)\n{:<10}", "");
            for h in &header {
                let _ = write!(line, " {h:>26}");
            }
            writeln!(out, "{line}")?;
            for row in &group.rows {
                let mut line = format!("{:<10}", row.name);
                for cell in &row.cells {
                    let cell = cell.map_or_else(
                        || "—".to_string(),
                        |c| thesis_cell(c.channel, c.terms, term, units),
                    );
                    let _ = write!(line, " {cell:>26}");
                }
                writeln!(out, "{line}")?;
            }
            writeln!(out)?;
        }
    }
    if tables.over_temperature() {
        writeln!(
            out,
            "Over temperature: ln(term) linear in T, each run weighted by its interval ({:.0} %); a dependence or \
             a difference is called at p < {}",
            100.0 * analysis.confidence,
            analysis::term_law::SIGNIFICANCE
        )?;
        let laws = tables.laws(analysis.confidence);
        for (name, law) in laws.iter().filter(|(_, l)| l.fit.is_some()) {
            writeln!(
                out,
                "  {}\n    {}",
                law.describe(name),
                law.describe_differences()
            )?;
        }
        if let Some(rest) = analysis::term_law::without_law(&laws) {
            writeln!(out, "  {rest}")?;
        }
        writeln!(out)?;
    }
    Ok(())
}

fn thesis_cell(ch: &SelectedChannel, terms: &NoiseTerms, term: Term, units: Units) -> String {
    let (f, _) = unit_of(term, ch.quantity, &ch.unit, units);
    let digits = |v: f64| {
        if units == Units::Thesis {
            format!("{v:.4}")
        } else {
            sig3(v)
        }
    };
    let held = match terms.choose(term).chosen {
        Chosen::Model(v) => digits(v.value * f),
        Chosen::Bound(b) => format!("≤ {}", digits(b * f)),
        Chosen::Nothing => "—".to_string(),
    };
    match (term, &terms.slope.sigma_min) {
        (Term::BiasInstability, Some(m)) => format!(
            "{} (at {:.1}s); B {held}",
            digits(m.value * f),
            m.tau.unwrap_or(f64::NAN)
        ),
        _ => held,
    }
}

/// Kalibr's `imu.yaml` ([`kalibr_yaml`]) written to `path`.
fn write_kalibr(path: &Path, analysis: Analysis, overwrite: bool) -> Result<()> {
    let channels: Vec<KalibrChannel> = analysis
        .analysed
        .iter()
        .map(|r| KalibrChannel {
            channel: &r.channel,
            terms: &r.terms,
        })
        .collect();
    let rate = analysis.rates.first().copied().unwrap_or(1.0);
    let text = kalibr_yaml(&channels, analysis.files, rate, analysis.confidence)?;
    imu::output::write_file(
        path,
        text.as_bytes(),
        &imu::output::OutputPolicy {
            overwrite,
            inputs: analysis.files,
        },
    )?;
    Ok(())
}

/// What a reader must know of a model beyond its terms: the τ range it
/// was fitted over where that is not the whole curve, and the filter its
/// white noise passes through, and a periodic disturbance beside the noise
/// (its amplitude in the data's `unit`).
fn model_notes(m: &allan::noise_model::NoiseModel, unit: &str) -> Vec<String> {
    let mut notes = Vec::new();
    if let Some(r) = m.fit_range.as_ref().filter(|r| !r.whole) {
        notes.push(r.describe());
    }
    if let Some(f) = &m.low_pass {
        notes.push(format!(
            "N is the white noise before a first-order low-pass the curve shows at its shortest τ: \
             Tc = {:.3e} s [{:.3e}, {:.3e}], −3 dB at {:.2} Hz",
            f.tau_c.value, f.tau_c.lo, f.tau_c.hi, f.cutoff_hz
        ));
    }
    if let Some(t) = &m.periodic {
        notes.push(t.describe(unit));
    }
    notes
}
