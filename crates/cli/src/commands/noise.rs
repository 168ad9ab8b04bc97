//! `imutherm noise`: the IEEE 952 noise terms of each axis, with intervals
//! and units, a thesis-style table over temperature, and Kalibr's imu.yaml.

use std::fmt::Write as _;
use std::io::Write;
use std::path::Path;

use anyhow::{Context, Result, bail};
use rayon::prelude::*;
use serde::Serialize;

use allan::noise_terms::{Chosen, Minimum, NoiseTerms, Term, TermEstimate, TermValue, analyze_terms_vec};
use imu::Quantity;

use analysis::kalibr::{KalibrChannel, kalibr_yaml};
use analysis::reading::unit_text;
use analysis::selection::SelectedChannel;
use analysis::thesis::ThesisTables;
use analysis::units::{Units, density_of, unit_of};

use crate::args::{NoiseArgs, TermUnits};
use crate::flags::recording_options;
use crate::print::read_channels;

const SCHEMA: &str = "imutherm.noise/1";

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
    let read = recording_options(&a.read)?;
    let mut temps = Vec::new();
    let mut rates = Vec::new();
    let mut work = Vec::new();
    for (i, file) in a.files.iter().enumerate() {
        let sel = read_channels(file, &a.channels, &read)?;
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
        temps.push(sel.temperature_mean_c);
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
        for (_, why) in &r.terms.disagreements {
            eprintln!("warning: {}: {}: {why}", r.channel.file.display(), r.channel.name);
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

/// The cell of a term in the compact table, and whether it needs the
/// footnote of a disagreement (`*`) or of a fallback (`†`).
fn compact_cell(r: &Analysed, term: Term, units: Units) -> String {
    let ch = &r.channel;
    let (f, _) = unit_of(term, ch.quantity, &ch.unit, units);
    let choice = r.terms.choose(term);
    let mark = if choice.disagree { "*" } else { "" };
    match choice.chosen {
        Chosen::Fit(v) => format!(
            "{} [{}, {}]{mark}",
            sig3(v.value * f),
            sig3(v.lo * f),
            sig3(v.hi * f)
        ),
        Chosen::Slope(v) => format!("{} [{}, {}]†", sig3(v.value * f), sig3(v.lo * f), sig3(v.hi * f)),
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
        let (mut any_disagree, mut any_fallback, mut any_bound) = (false, false, false);
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
                            .any(|r| matches!(r.terms.choose(*t).chosen, Chosen::Fit(_) | Chosen::Slope(_)))
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
                    any_disagree |= c.ends_with('*');
                    any_fallback |= c.ends_with('†');
                    any_bound |= c.starts_with('≤');
                }
                writeln!(out, "{}", line.trim_end())?;
            }
            // Why a term is only bounded: the first axis's reason says
            // what the record would need.
            for &t in &terms {
                if let Some(r) = members
                    .iter()
                    .find(|r| matches!(r.terms.choose(t).chosen, Chosen::Bound(_) | Chosen::Nothing))
                    && let TermEstimate::NotIdentifiable(why) = r.terms.fit.get(t)
                {
                    writeln!(out, "  {} ({}): {why}", t.symbol(), r.channel.name)?;
                }
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
        if any_disagree {
            writeln!(
                out,
                "  * the slope method and the fit disagree beyond their intervals; the fit is shown (--verbose for both)"
            )?;
        }
        if any_fallback {
            writeln!(
                out,
                "  † the slope method's reading: the fit cannot separate this term, or found K beside no B"
            )?;
        }
        if any_bound {
            writeln!(
                out,
                "  ≤ not identifiable: an upper bound at {:.1} % (no term's share of σ² exceeds σ's upper bound)",
                100.0 * analysis.confidence
            )?;
        }
        writeln!(out)?;
    }
    Ok(())
}

#[derive(Serialize)]
struct JsonTerm {
    term: &'static str,
    name: &'static str,
    method: &'static str,
    identified: bool,
    #[serde(skip_serializing_if = "Option::is_none")]
    si: Option<JsonValue>,
    #[serde(skip_serializing_if = "Option::is_none")]
    datasheet: Option<JsonValue>,
    /// White noise as the datasheets quote it: a density per √Hz.
    #[serde(skip_serializing_if = "Option::is_none")]
    density: Option<JsonValue>,
    #[serde(skip_serializing_if = "Option::is_none")]
    tau: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    reason: Option<String>,
}

#[derive(Serialize)]
struct JsonValue {
    value: f64,
    lo: f64,
    hi: f64,
    unit: String,
}

fn json_value(v: &TermValue, term: Term, ch: &SelectedChannel, units: Units) -> JsonValue {
    let (f, unit) = unit_of(term, ch.quantity, &ch.unit, units);
    JsonValue {
        value: v.value * f,
        lo: v.lo * f,
        hi: v.hi * f,
        unit,
    }
}

fn density(v: &TermValue, term: Term, ch: &SelectedChannel) -> Option<JsonValue> {
    let (f, unit) = density_of(ch.quantity).filter(|_| term == Term::WhiteNoise)?;
    Some(JsonValue {
        value: v.value * f,
        lo: v.lo * f,
        hi: v.hi * f,
        unit: unit.to_string(),
    })
}

fn json_term(term: Term, est: &TermEstimate, method: &'static str, ch: &SelectedChannel) -> JsonTerm {
    match est {
        TermEstimate::Value(v) => JsonTerm {
            term: term.symbol(),
            name: term.name(),
            method,
            identified: true,
            si: Some(json_value(v, term, ch, Units::Si)),
            datasheet: Some(json_value(v, term, ch, Units::Datasheet)),
            density: density(v, term, ch),
            tau: v.tau,
            reason: None,
        },
        TermEstimate::NotIdentifiable(why) => JsonTerm {
            term: term.symbol(),
            name: term.name(),
            method,
            identified: false,
            si: None,
            datasheet: None,
            density: None,
            tau: None,
            reason: Some(why.clone()),
        },
    }
}

fn write_json(out: &mut impl Write, analysis: Analysis, units: Units) -> Result<()> {
    let files_json: Vec<serde_json::Value> = analysis.files
        .iter()
        .enumerate()
        .map(|(i, f)| {
            let channels: Vec<serde_json::Value> = analysis.analysed
                .iter()
                .filter(|r| r.file_index == i)
                .map(|r| {
                    let ch = &r.channel;
                    let slope: Vec<JsonTerm> = Term::ALL
                        .iter()
                        .map(|&t| json_term(t, r.terms.slope.get(t), "slope", ch))
                        .collect();
                    let fit: Vec<JsonTerm> = Term::ALL
                        .iter()
                        .map(|&t| json_term(t, r.terms.fit.get(t), "fit", ch))
                        .collect();
                    let sigma_min = r.terms.slope.sigma_min.map(|v| {
                        serde_json::json!({
                            "si": json_value(&v, Term::BiasInstability, ch, Units::Si),
                            "datasheet": json_value(&v, Term::BiasInstability, ch, Units::Datasheet),
                            "tau": v.tau,
                        })
                    });
                    let chosen: Vec<serde_json::Value> = Term::ALL
                        .iter()
                        .map(|&t| {
                            let c = r.terms.choose(t);
                            let (method, value) = match c.chosen {
                                Chosen::Fit(v) => ("fit", Some(json_value(&v, t, ch, Units::Si))),
                                Chosen::Slope(v) => ("slope", Some(json_value(&v, t, ch, Units::Si))),
                                Chosen::Bound(b) => (
                                    "upper_bound",
                                    Some(json_value(
                                        &TermValue { value: b, lo: 0.0, hi: b, tau: None },
                                        t,
                                        ch,
                                        Units::Si,
                                    )),
                                ),
                                Chosen::Nothing => ("none", None),
                            };
                            serde_json::json!({
                                "term": t.symbol(),
                                "method": method,
                                "si": value,
                                "disagree": c.disagree,
                                "note": c.note,
                            })
                        })
                        .collect();
                    serde_json::json!({
                        "name": ch.name,
                        "quantity": ch.quantity.name(),
                        "unit": ch.unit,
                        "unit_source": ch.unit_source.name(),
                        "minimum": match r.terms.slope.minimum {
                            Minimum::Found => "found",
                            Minimum::StillFalling => "still_falling",
                            Minimum::RisesFromStart => "rises_from_start",
                            Minimum::Unknown => "unknown",
                        },
                        "sigma_min_min_edf": allan::noise_terms::MIN_EDF,
                        "slope_stretches": r.terms.slope.stretches.iter().map(|(t, a, b)| serde_json::json!({"term": t.symbol(), "tau_from": a, "tau_to": b})).collect::<Vec<_>>(),
                        "fit_left_out_taus": r.terms.fit.left_out,
                        "thesis_reading": {
                            "method": "analyzeAllan.m: N on the -1/2 line through the slope nearest -1/2; B = sigma at the first positive slope / 0.664",
                            "N": r.terms.slope.thesis.n.map(|v| serde_json::json!({"si": json_value(&v, Term::WhiteNoise, ch, Units::Si), "tau": v.tau})),
                            "B": r.terms.slope.thesis.b.map(|v| serde_json::json!({"si": json_value(&v, Term::BiasInstability, ch, Units::Si), "tau": v.tau})),
                        },
                        "chosen": chosen,
                        "samples": r.samples,
                        "sigma_min": sigma_min,
                        "slope": slope,
                        "fit": fit,
                        "fit_chi2_reduced": r.terms.fit.chi2_reduced,
                        "fit_points": r.terms.fit.points,
                        "disagreements": r.terms.disagreements.iter().map(|(_, w)| w.clone()).collect::<Vec<_>>(),
                    })
                })
                .collect();
            serde_json::json!({
                "file": f.display().to_string(),
                "mean_temperature_c": analysis.temps[i],
                "rate_hz": analysis.rates[i],
                "channels": channels,
            })
        })
        .collect();
    let doc = serde_json::json!({
        "schema": SCHEMA,
        "imutherm_version": env!("CARGO_PKG_VERSION"),
        "confidence": analysis.confidence,
        "units": match units { Units::Si => "si", _ => "datasheet" },
        "files": files_json,
    });
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
                && let Some(d) = density(v, term, ch)
            {
                text.push_str(&format!(" = {:.4e} {}", d.value, d.unit));
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
            writeln!(
                out,
                "{} [{}]",
                ch.name,
                unit_text(&ch.unit, ch.unit_source.name(), ch.quantity.name())
            )?;
            if let Some(m) = &r.terms.slope.sigma_min {
                let (fct, unit) = unit_of(Term::BiasInstability, ch.quantity, &ch.unit, units);
                let where_ = match r.terms.slope.minimum {
                    Minimum::Found => String::new(),
                    _ => format!(
                        " — no minimum within the record; B ≤ {:.4e} {unit}",
                        r.terms.slope.bound(Term::BiasInstability).unwrap_or(f64::NAN) * fct
                    ),
                };
                writeln!(
                    out,
                    "  σ_min (ADEV minimum among points with ≥ {} degrees of freedom) {:.4e} [{:.4e}, {:.4e}] {unit} \
                     at τ = {:.4} s{where_}",
                    allan::noise_terms::MIN_EDF,
                    m.value * fct,
                    m.lo * fct,
                    m.hi * fct,
                    m.tau.unwrap_or(f64::NAN)
                )?;
            }
            for (t, a, b) in &r.terms.slope.stretches {
                writeln!(
                    out,
                    "  slope method read {} where slope {:+} holds, τ {a:.4} … {b:.4} s",
                    t.symbol(),
                    t.slope()
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
            if !r.terms.fit.left_out.is_empty() {
                writeln!(
                    out,
                    "  fit left out, as no power-law term (a bump, a tone): τ = {} s",
                    r.terms
                        .fit
                        .left_out
                        .iter()
                        .map(|t| format!("{t:.4}"))
                        .collect::<Vec<_>>()
                        .join(", ")
                )?;
            }
            for term in Term::ALL {
                writeln!(
                    out,
                    "  {}  slope {}",
                    term.symbol(),
                    fmt_est(r.terms.slope.get(term), term, ch, units)
                )?;
                writeln!(
                    out,
                    "     fit   {}",
                    fmt_est(r.terms.fit.get(term), term, ch, units)
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

/// The thesis's layout: one table per term, rows = axes, columns = the
/// files' mean temperatures; slope-method values as the thesis read them,
/// the fit's where the slope method cannot read the term or disagrees with
/// the fit (marked), in the thesis's units (°/√s, °/s) or the datasheet's.
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
                "Bias instability: σ_min (at τ) → B = σ_min/0.664",
            ),
        ] {
            let (_, unit) = unit_of(term, q, group.data_unit(), units);
            let mut line = format!("{title} — {what} [{unit}] (slope method)\n{:<10}", "");
            for h in &header {
                let _ = write!(line, " {h:>26}");
            }
            writeln!(out, "{line}")?;
            let mut marked = false;
            for row in &group.rows {
                let mut line = format!("{:<10}", row.name);
                for cell in &row.cells {
                    let cell = cell.map_or_else(
                        || "—".to_string(),
                        |c| thesis_cell(c.channel, c.terms, term, units),
                    );
                    marked |= cell.ends_with('*');
                    let _ = write!(line, " {cell:>26}");
                }
                writeln!(out, "{line}")?;
            }
            if marked {
                writeln!(
                    out,
                    "* the fit's value: the slope method disagrees with it beyond their intervals, or cannot read the term"
                )?;
            }
            writeln!(out)?;
        }
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
    let fit_or = |fallback: String| match terms.fit.get(term) {
        TermEstimate::Value(v) => format!("{}*", digits(v.value * f)),
        TermEstimate::NotIdentifiable(_) => fallback,
    };
    let disagree = terms.disagreements.iter().any(|(t, _)| *t == term);
    match term {
        Term::BiasInstability => match (&terms.slope.sigma_min, terms.slope.get(term)) {
            (Some(m), TermEstimate::Value(b)) if !disagree => format!(
                "{} (at {:.1}s) → {}",
                digits(m.value * f),
                m.tau.unwrap_or(f64::NAN),
                digits(b.value * f)
            ),
            _ => fit_or(match terms.slope.bound(term) {
                Some(b) => format!("no minimum; B ≤ {}", digits(b * f)),
                None => "not identifiable".to_string(),
            }),
        },
        _ => match terms.slope.get(term) {
            TermEstimate::Value(v) if !disagree => digits(v.value * f),
            _ => fit_or("not identifiable".to_string()),
        },
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
