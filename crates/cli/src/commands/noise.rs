//! `imutherm noise`: the IEEE 952 noise terms of each axis, with intervals
//! and units, a thesis-style table over temperature, and Kalibr's imu.yaml.

use std::f64::consts::PI;
use std::fmt::Write as _;
use std::io::Write;
use std::path::Path;

use anyhow::{Context, Result, bail};
use rayon::prelude::*;
use serde::Serialize;

use allan::noise_terms::{NoiseTerms, Term, TermEstimate, TermValue, analyze_terms};
use imu::Quantity;
use imu::units::STANDARD_GRAVITY;

use crate::args::NoiseArgs;
use crate::commands::info::recording_options;
use crate::commands::selection::{Channel, read_channels};

const SCHEMA: &str = "imutherm.noise/1";

/// The unit systems terms are printed in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Units {
    Si,
    Datasheet,
    /// The thesis tables: °/√s and °/s for gyros, SI for accelerometers.
    Thesis,
}

/// The factor from the SI value of `term` to `units`, and the unit's label.
/// The SI unit of `term` for a channel of `quantity` in `data_unit`.
pub fn si_unit(term: Term, quantity: Quantity, data_unit: &str) -> String {
    unit_of(term, quantity, data_unit, Units::Si).1
}

fn unit_of(term: Term, quantity: Quantity, data_unit: &str, units: Units) -> (f64, String) {
    let deg = 180.0 / PI;
    let ug = 1.0 / (STANDARD_GRAVITY * 1e-6);
    let (f, label): (f64, &str) = match (quantity, units, term) {
        (Quantity::AngularRate, Units::Si, t) => match t {
            Term::Quantization => (1.0, "rad"),
            Term::WhiteNoise => (1.0, "rad/√s"),
            Term::BiasInstability => (1.0, "rad/s"),
            Term::RateRandomWalk => (1.0, "rad/s/√s"),
            Term::RateRamp => (1.0, "rad/s²"),
        },
        (Quantity::AngularRate, Units::Datasheet, t) => match t {
            Term::Quantization => (deg, "°"),
            Term::WhiteNoise => (deg * 60.0, "°/√h"),
            Term::BiasInstability => (deg * 3600.0, "°/h"),
            Term::RateRandomWalk => (deg * 216_000.0, "°/h/√h"),
            Term::RateRamp => (deg * 3600.0 * 3600.0, "°/h²"),
        },
        (Quantity::AngularRate, Units::Thesis, t) => match t {
            Term::Quantization => (deg, "°"),
            Term::WhiteNoise => (deg, "°/√s"),
            Term::BiasInstability => (deg, "°/s"),
            Term::RateRandomWalk => (deg, "°/s/√s"),
            Term::RateRamp => (deg, "°/s²"),
        },
        (Quantity::Acceleration, Units::Datasheet, t) => match t {
            Term::Quantization => (1.0, "m/s"),
            Term::WhiteNoise => (60.0, "m/s/√h"),
            Term::BiasInstability => (ug, "µg"),
            Term::RateRandomWalk => (ug, "µg/√s"),
            Term::RateRamp => (ug, "µg/s"),
        },
        (Quantity::Acceleration, _, t) => match t {
            Term::Quantization => (1.0, "m/s"),
            Term::WhiteNoise => (1.0, "m/s/√s"),
            Term::BiasInstability => (1.0, "m/s²"),
            Term::RateRandomWalk => (1.0, "m/s²/√s"),
            Term::RateRamp => (1.0, "m/s³"),
        },
        (_, _, t) => {
            let u = if data_unit.is_empty() { "1" } else { data_unit };
            let label = match t {
                Term::Quantization => format!("{u}·s"),
                Term::WhiteNoise => format!("{u}·√s"),
                Term::BiasInstability => u.to_string(),
                Term::RateRandomWalk => format!("{u}/√s"),
                Term::RateRamp => format!("{u}/s"),
            };
            return (1.0, label);
        }
    };
    (f, label.to_string())
}

struct Analysed {
    file_index: usize,
    channel: Channel,
    terms: NoiseTerms,
}

pub fn run(a: &NoiseArgs) -> Result<()> {
    let units = match a.units.to_ascii_lowercase().as_str() {
        "si" => Units::Si,
        "datasheet" => Units::Datasheet,
        other => bail!("--units {other}: expected si or datasheet"),
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
        temps.push(sel.temperature_mean_c);
        rates.push(sel.rate_hz);
        work.extend(sel.channels.into_iter().map(|c| (i, c)));
    }
    let analysed: Vec<Analysed> = work
        .into_par_iter()
        .map(|(file_index, channel)| {
            let (_, terms) = analyze_terms(&channel.data, channel.rate_hz, confidence)
                .with_context(|| format!("{}: {}", channel.file.display(), channel.name))?;
            Ok(Analysed {
                file_index,
                channel,
                terms,
            })
        })
        .collect::<Result<Vec<_>>>()?;

    for r in &analysed {
        for (_, why) in &r.terms.disagreements {
            eprintln!("warning: {}: {}: {why}", r.channel.file.display(), r.channel.name);
        }
    }
    if let Some(path) = &a.kalibr {
        write_kalibr(path, &analysed, &rates, &a.files)?;
        eprintln!("wrote {}", path.display());
    }
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    if a.json {
        write_json(&mut out, &analysed, &a.files, &temps, &rates, units, confidence)?;
    } else {
        write_text(&mut out, &analysed, &a.files, &temps, units, confidence)?;
    }
    out.flush()?;
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

fn json_value(v: &TermValue, term: Term, ch: &Channel, units: Units) -> JsonValue {
    let (f, unit) = unit_of(term, ch.quantity, &ch.unit, units);
    JsonValue {
        value: v.value * f,
        lo: v.lo * f,
        hi: v.hi * f,
        unit,
    }
}

/// N as the datasheets quote it (PS-MPU-9250A-01: °/s/√Hz for the gyro,
/// µg/√Hz for the accelerometer): the same number as N in per-√s units.
fn density_of(quantity: Quantity) -> Option<(f64, &'static str)> {
    match quantity {
        Quantity::AngularRate => Some((180.0 / PI, "°/s/√Hz")),
        Quantity::Acceleration => Some((1.0 / (STANDARD_GRAVITY * 1e-6), "µg/√Hz")),
        _ => None,
    }
}

fn density(v: &TermValue, term: Term, ch: &Channel) -> Option<JsonValue> {
    let (f, unit) = density_of(ch.quantity).filter(|_| term == Term::WhiteNoise)?;
    Some(JsonValue {
        value: v.value * f,
        lo: v.lo * f,
        hi: v.hi * f,
        unit: unit.to_string(),
    })
}

fn json_term(term: Term, est: &TermEstimate, method: &'static str, ch: &Channel) -> JsonTerm {
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

fn write_json(
    out: &mut impl Write,
    analysed: &[Analysed],
    files: &[std::path::PathBuf],
    temps: &[Option<f64>],
    rates: &[f64],
    units: Units,
    confidence: f64,
) -> Result<()> {
    let files_json: Vec<serde_json::Value> = files
        .iter()
        .enumerate()
        .map(|(i, f)| {
            let channels: Vec<serde_json::Value> = analysed
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
                    serde_json::json!({
                        "name": ch.name,
                        "quantity": ch.quantity.name(),
                        "unit": ch.unit,
                        "samples": ch.data.len(),
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
                "mean_temperature_c": temps[i],
                "rate_hz": rates[i],
                "channels": channels,
            })
        })
        .collect();
    let doc = serde_json::json!({
        "schema": SCHEMA,
        "imutherm_version": env!("CARGO_PKG_VERSION"),
        "confidence": confidence,
        "units": match units { Units::Si => "si", _ => "datasheet" },
        "files": files_json,
    });
    serde_json::to_writer_pretty(&mut *out, &doc)?;
    writeln!(out)?;
    Ok(())
}

fn fmt_est(est: &TermEstimate, term: Term, ch: &Channel, units: Units) -> String {
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

fn write_text(
    out: &mut impl Write,
    analysed: &[Analysed],
    files: &[std::path::PathBuf],
    temps: &[Option<f64>],
    units: Units,
    confidence: f64,
) -> Result<()> {
    for (i, f) in files.iter().enumerate() {
        let t = temps[i]
            .map(|t| format!(", mean temperature {t:.1} °C"))
            .unwrap_or_default();
        writeln!(
            out,
            "# {}{t} — intervals at {:.1} %",
            f.display(),
            100.0 * confidence
        )?;
        for r in analysed.iter().filter(|r| r.file_index == i) {
            let ch = &r.channel;
            writeln!(out, "{} [{}]", ch.name, ch.unit)?;
            if let Some(m) = &r.terms.slope.sigma_min {
                let (fct, unit) = unit_of(Term::BiasInstability, ch.quantity, &ch.unit, units);
                writeln!(
                    out,
                    "  σ_min (ADEV minimum) {:.4e} {unit} at τ = {:.4} s",
                    m.value * fct,
                    m.tau.unwrap_or(f64::NAN)
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
    if files.len() > 1 {
        write_thesis_tables(out, analysed, files, temps)?;
    }
    Ok(())
}

/// The thesis's layout: one table per term, rows = axes, columns = the
/// files' mean temperatures; slope-method values as the thesis read them.
fn write_thesis_tables(
    out: &mut impl Write,
    analysed: &[Analysed],
    files: &[std::path::PathBuf],
    temps: &[Option<f64>],
) -> Result<()> {
    let mut names: Vec<(String, Quantity, String)> = Vec::new();
    for r in analysed {
        if !names.iter().any(|(n, _, _)| *n == r.channel.name) {
            names.push((r.channel.name.clone(), r.channel.quantity, r.channel.unit.clone()));
        }
    }
    let header: Vec<String> = (0..files.len())
        .map(|i| temps[i].map_or_else(|| format!("file {}", i + 1), |t| format!("{t:.0}°C")))
        .collect();
    let groups = [
        (Quantity::Acceleration, "Accelerometer"),
        (Quantity::AngularRate, "Gyroscope"),
        (Quantity::Other, "Other"),
    ];
    for (q, title) in groups {
        let rows: Vec<&(String, Quantity, String)> = names
            .iter()
            .filter(|(_, nq, _)| {
                *nq == q
                    || (q == Quantity::Other && !matches!(nq, Quantity::Acceleration | Quantity::AngularRate))
            })
            .collect();
        let Some((_, _, unit0)) = rows.first() else {
            continue;
        };
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
            let (_, unit) = unit_of(term, q, unit0, Units::Thesis);
            let mut line = format!("{title} — {what} [{unit}] (slope method)\n{:<10}", "");
            for h in &header {
                let _ = write!(line, " {h:>26}");
            }
            writeln!(out, "{line}")?;
            for (name, _, _) in &rows {
                let mut line = format!("{name:<10}");
                for i in 0..files.len() {
                    let cell = analysed
                        .iter()
                        .find(|r| r.file_index == i && r.channel.name == *name)
                        .map_or_else(|| "—".to_string(), |r| thesis_cell(r, term));
                    let _ = write!(line, " {cell:>26}");
                }
                writeln!(out, "{line}")?;
            }
            writeln!(out)?;
        }
    }
    Ok(())
}

fn thesis_cell(r: &Analysed, term: Term) -> String {
    let ch = &r.channel;
    let (f, _) = unit_of(term, ch.quantity, &ch.unit, Units::Thesis);
    match term {
        Term::BiasInstability => match (&r.terms.slope.sigma_min, r.terms.slope.get(term)) {
            (Some(m), TermEstimate::Value(b)) => format!(
                "{:.4} (at {:.1}s) → {:.4}",
                m.value * f,
                m.tau.unwrap_or(f64::NAN),
                b.value * f
            ),
            _ => "not identifiable".to_string(),
        },
        _ => match r.terms.slope.get(term) {
            TermEstimate::Value(v) => format!("{:.4}", v.value * f),
            TermEstimate::NotIdentifiable(_) => "not identifiable".to_string(),
        },
    }
}

/// The value for Kalibr: the fit's. The slope method would read a +1/2
/// wiggle of noise at long τ as a random walk; the fit only keeps a term
/// that shows beyond the scatter.
fn best(r: &Analysed, term: Term) -> Option<f64> {
    r.terms.fit.get(term).value().map(|v| v.value)
}

fn write_kalibr(
    path: &Path,
    analysed: &[Analysed],
    rates: &[f64],
    files: &[std::path::PathBuf],
) -> Result<()> {
    let mut text = String::new();
    let _ = writeln!(
        text,
        "# Kalibr IMU noise model written by imutherm {} from {}.",
        env!("CARGO_PKG_VERSION"),
        files
            .iter()
            .map(|f| f.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    let _ = writeln!(
        text,
        "# Continuous-time values (IEEE 952 on the overlapping ADEV): *_noise_density = N, \
         *_random_walk = K; the worst axis of each sensor is used."
    );
    let mut values = Vec::new();
    for (q, sensor, n_unit, k_unit) in [
        (
            Quantity::Acceleration,
            "accelerometer",
            "m/s^2/sqrt(Hz)",
            "m/s^3/sqrt(Hz)",
        ),
        (
            Quantity::AngularRate,
            "gyroscope",
            "rad/s/sqrt(Hz)",
            "rad/s^2/sqrt(Hz)",
        ),
    ] {
        let axes: Vec<&Analysed> = analysed.iter().filter(|r| r.channel.quantity == q).collect();
        if axes.is_empty() {
            bail!("--kalibr: no {sensor} channels in the input");
        }
        for (term, key, unit) in [
            (Term::WhiteNoise, "noise_density", n_unit),
            (Term::RateRandomWalk, "random_walk", k_unit),
        ] {
            let per_axis: Vec<(String, Option<f64>)> = axes
                .iter()
                .map(|r| {
                    (
                        format!("{} ({})", r.channel.name, r.channel.file.display()),
                        best(r, term),
                    )
                })
                .collect();
            let worst = per_axis.iter().filter_map(|(_, v)| *v).fold(f64::NAN, f64::max);
            if !worst.is_finite() {
                let why = axes
                    .first()
                    .map(|r| match r.terms.fit.get(term) {
                        TermEstimate::NotIdentifiable(w) => w.clone(),
                        TermEstimate::Value(_) => String::new(),
                    })
                    .unwrap_or_default();
                bail!(
                    "--kalibr: {sensor} {} is not identifiable on any axis ({why})",
                    term.symbol()
                );
            }
            let _ = writeln!(
                text,
                "# {sensor}_{key} per axis [{unit}]: {}",
                per_axis
                    .iter()
                    .map(|(n, v)| format!(
                        "{n} {}",
                        v.map_or_else(|| "not identifiable".to_string(), |v| format!("{v:.6e}"))
                    ))
                    .collect::<Vec<_>>()
                    .join(", ")
            );
            values.push((format!("{sensor}_{key}"), worst, unit));
        }
    }
    for (key, v, unit) in values {
        let _ = writeln!(text, "{key}: {v:.6e}  # {unit}");
    }
    let rate = rates.first().copied().unwrap_or(1.0);
    let _ = writeln!(text, "rostopic: /imu0\nupdate_rate: {rate}  # Hz");
    std::fs::write(path, text).with_context(|| format!("writing {}", path.display()))?;
    Ok(())
}
