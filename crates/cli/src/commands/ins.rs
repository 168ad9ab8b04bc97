//! `imutherm ins`: strapdown navigation of static recordings from many
//! start points, the error against the static truth beside its prediction
//! from the noise terms and a Monte Carlo of them; raw against compensated.

use std::io::Write;
use std::path::Path;

use anyhow::{Context, Result};
use rayon::prelude::*;
use serde_json::{Value, json};

use allan::noise_terms::{Term, analyze_terms};
use ins::drift::{CurvePoint, Spread, drift_over_windows, report_times};
use ins::monte_carlo::{MonteCarloSetup, monte_carlo};
use ins::prediction::{AxisNoise, NoiseModel, Prediction, PredictionSetup, predict};
use ins::strapdown::{ImuData, NavOptions, align, align_samples};
use thermal::tcal::Model;

use crate::args::InsArgs;
use crate::commands::info::recording_options;
use crate::commands::selection::{Selection, read_channels};
use crate::commands::tcal::load;

const SCHEMA: &str = "imutherm.ins/1";

/// The six channels, in the order ins takes them.
pub(crate) const CHANNELS: [&str; 6] = ["accel_x", "accel_y", "accel_z", "gyro_x", "gyro_y", "gyro_z"];

/// Simulated runs of the Monte Carlo, and its seed (fixed: the same file
/// gives the same figures).
const MONTE_CARLO_RUNS: usize = 100;
const MONTE_CARLO_SEED: u64 = 1;

/// One recording navigated: the measured curve, the prediction and the
/// Monte Carlo at each time.
pub(crate) struct Navigated {
    pub(crate) windows: usize,
    pub(crate) windows_with_gaps: usize,
    pub(crate) noise: NoiseModel,
    pub(crate) rows: Vec<Row>,
}

pub(crate) struct Row {
    pub(crate) measured: CurvePoint,
    pub(crate) predicted: Prediction,
    pub(crate) monte_carlo: Spread,
}

pub fn run(a: &InsArgs) -> Result<()> {
    let read = recording_options(&a.read)?;
    let model = a.model.as_deref().map(load).transpose()?;
    let opts = NavOptions {
        align_s: a.align,
        latitude_deg: a.latitude,
        remove_gyro_bias: true,
    };
    let times = report_times(a.horizon);
    let mut files = Vec::new();
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    for file in &a.files {
        let sel = read_channels(file, &[], &read)?;
        let rate = sel.rate_hz;
        let (raw, compensated) = raw_and_compensated(file, &sel, model.as_ref(), &opts, a.every, &times)?;
        if a.json {
            let mut doc = file_json(&raw, a, rate);
            doc["file"] = json!(file.display().to_string());
            if let (Some(c), Some(path)) = (&compensated, &a.model) {
                let mut cj = file_json(c, a, rate);
                cj["model"] = json!(path.display().to_string());
                doc["compensated"] = cj;
            }
            files.push(doc);
        } else {
            print_file(&mut out, file, a, rate, &raw, compensated.as_ref())?;
        }
    }
    if a.json {
        let doc = json!({
            "schema": SCHEMA,
            "imutherm_version": env!("CARGO_PKG_VERSION"),
            "files": files,
        });
        serde_json::to_writer_pretty(&mut out, &doc)?;
        writeln!(out)?;
    }
    Ok(())
}

/// The six channels of a selection, in the order ins takes them.
pub(crate) fn six_channels(file: &Path, sel: &Selection) -> Result<Vec<Vec<f64>>> {
    CHANNELS
        .iter()
        .map(|name| {
            sel.channels
                .iter()
                .find(|c| c.name == *name)
                .map(|c| c.data.clone())
                .with_context(|| {
                    format!(
                        "{}: no {name} channel; ins needs the three accelerometer and three gyroscope axes",
                        file.display()
                    )
                })
        })
        .collect()
}

/// A recording navigated as it is and, with a model, compensated.
pub(crate) fn raw_and_compensated(
    file: &Path,
    sel: &Selection,
    model: Option<&Model>,
    opts: &NavOptions,
    every: f64,
    times: &[f64],
) -> Result<(Navigated, Option<Navigated>)> {
    let six = six_channels(file, sel)?;
    let raw = navigate(file, &six, sel.rate_hz, opts, every, times)?;
    let compensated = match model {
        Some(m) => {
            let comp = compensated_channels(file, sel, m, &six)?;
            Some(navigate(file, &comp, sel.rate_hz, opts, every, times)?)
        }
        None => None,
    };
    Ok((raw, compensated))
}

/// The six channels compensated with `model`, from the selection's
/// temperature.
pub(crate) fn compensated_channels(
    file: &Path,
    sel: &Selection,
    model: &Model,
    six: &[Vec<f64>],
) -> Result<Vec<Vec<f64>>> {
    let temp = sel
        .temperature
        .as_deref()
        .with_context(|| format!("{}: no temperature channel to compensate with", file.display()))?;
    compensate(file, model, six, temp, sel.rate_hz)
}

/// The recording with the model's correction applied to the channels it
/// has; the others stay raw.
fn compensate(
    file: &Path,
    model: &Model,
    six: &[Vec<f64>],
    temp: &[f64],
    rate: f64,
) -> Result<Vec<Vec<f64>>> {
    let mut out = six.to_vec();
    let mut out_of_range = 0;
    for (name, data) in CHANNELS.iter().zip(out.iter_mut()) {
        if model.channel(name).is_some() {
            let r = model
                .apply(name, data, temp, rate)
                .with_context(|| format!("{}: compensating {name}", file.display()))?;
            out_of_range = out_of_range.max(r.out_of_range);
        } else {
            eprintln!("note: {}: the model has no {name}: navigated raw", file.display());
        }
    }
    if out_of_range > 0 {
        eprintln!(
            "warning: {}: {out_of_range} samples outside the fitted {:.1}…{:.1} °C were compensated at the range's edge, not extrapolated",
            file.display(),
            model.t_min_c,
            model.t_max_c
        );
    }
    Ok(out)
}

/// N, B and K of one channel from the model fit; a term it cannot identify
/// is 0. The slope method is not a fallback: it reads a bias instability
/// off the ADEV minimum of any curve, white noise alone included, and that
/// phantom B would enter the prediction as a bias.
fn axis_noise(file: &Path, name: &str, data: &[f64], rate: f64) -> Result<AxisNoise> {
    let (_, terms) = analyze_terms(data, rate, 0.683)
        .with_context(|| format!("{}: noise terms of {name}", file.display()))?;
    let get = |t: Term| terms.fit.get(t).value().map_or(0.0, |v| v.value);
    Ok(AxisNoise {
        n: get(Term::WhiteNoise),
        b: get(Term::BiasInstability),
        k: get(Term::RateRandomWalk),
    })
}

pub(crate) fn navigate(
    file: &Path,
    six: &[Vec<f64>],
    rate: f64,
    opts: &NavOptions,
    every: f64,
    times: &[f64],
) -> Result<Navigated> {
    let imu = ImuData {
        accel: [&six[0], &six[1], &six[2]],
        gyro: [&six[3], &six[4], &six[5]],
        rate_hz: rate,
    };
    let drift = drift_over_windows(&imu, opts, every, times).with_context(|| file.display().to_string())?;
    let axes: Vec<AxisNoise> = CHANNELS
        .par_iter()
        .zip(six.par_iter())
        .map(|(name, data)| axis_noise(file, name, data, rate))
        .collect::<Result<_>>()?;
    let noise = NoiseModel {
        accel: [axes[0], axes[1], axes[2]],
        gyro: [axes[3], axes[4], axes[5]],
    };
    // The prediction projects the noise with the attitude of the first
    // window that can be levelled (the sensor is static: one attitude).
    let na = align_samples(opts.align_s, rate);
    let first = (0..imu.len().saturating_sub(na))
        .step_by(na)
        .find(|&s| imu.finite(s..s + na))
        .unwrap_or(0);
    let alignment = align(&imu, first..first + na, opts);
    let setup =
        PredictionSetup::from_alignment(&alignment, opts.gravity(), opts.align_s, opts.remove_gyro_bias);
    let mc = monte_carlo(
        &noise,
        opts,
        &MonteCarloSetup {
            rate_hz: rate,
            runs: MONTE_CARLO_RUNS,
            seed: MONTE_CARLO_SEED,
            roll_deg: alignment.roll.to_degrees(),
            pitch_deg: alignment.pitch.to_degrees(),
        },
        times,
    )
    .with_context(|| format!("{}: Monte Carlo of the identified model", file.display()))?;
    let rows = drift
        .curve
        .iter()
        .zip(&mc)
        .map(|(m, c)| Row {
            measured: *m,
            predicted: predict(&noise, &setup, m.t_s),
            monte_carlo: c.horizontal_position_m,
        })
        .collect();
    Ok(Navigated {
        windows: drift.windows,
        windows_with_gaps: drift.windows_with_gaps,
        noise,
        rows,
    })
}

fn spread_json(s: Spread) -> Value {
    json!({ "rms": s.rms, "p50": s.p50, "p95": s.p95 })
}

fn file_json(n: &Navigated, a: &InsArgs, rate: f64) -> Value {
    let deg = 180.0 / std::f64::consts::PI;
    let curve: Vec<Value> = n
        .rows
        .iter()
        .map(|r| {
            let m = &r.measured;
            let terms: serde_json::Map<String, Value> = r
                .predicted
                .terms
                .iter()
                .map(|(t, v)| (t.key().to_string(), json!(v)))
                .collect();
            json!({
                "t_s": m.t_s,
                "horizontal_position_m": spread_json(m.horizontal_position_m),
                "horizontal_velocity_m_s": spread_json(m.horizontal_velocity_m_s),
                "tilt_deg": spread_json(m.tilt_rad.scaled(deg)),
                "heading_deg": spread_json(m.heading_rad.scaled(deg)),
                "predicted_horizontal_position_1sigma_m": r.predicted.total_m,
                "predicted_terms_m": terms,
                "monte_carlo_horizontal_position_m": spread_json(r.monte_carlo),
            })
        })
        .collect();
    let axis = |x: &AxisNoise| json!({ "n": x.n, "b": x.b, "k": x.k });
    let mut noise = serde_json::Map::new();
    for (k, name) in CHANNELS.iter().enumerate() {
        let x = if k < 3 {
            &n.noise.accel[k]
        } else {
            &n.noise.gyro[k - 3]
        };
        noise.insert(name.to_string(), axis(x));
    }
    json!({
        "rate_hz": rate,
        "align_s": a.align,
        "every_s": a.every,
        "horizon_s": a.horizon,
        "latitude_deg": a.latitude,
        "windows": n.windows,
        "windows_with_gaps": n.windows_with_gaps,
        "monte_carlo_runs": MONTE_CARLO_RUNS,
        "noise_si": noise,
        "curve": curve,
    })
}

/// Four significant figures, without an exponent in the usual range.
fn sig(v: f64) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if !(1e-3..1e6).contains(&a) {
        format!("{v:.3e}")
    } else {
        let decimals = (3 - a.log10().floor() as i32).max(0) as usize;
        format!("{v:.decimals$}")
    }
}

fn print_curve(out: &mut impl Write, n: &Navigated) -> Result<()> {
    let deg = 180.0 / std::f64::consts::PI;
    writeln!(
        out,
        "  {:>6}  {:>10} {:>10} {:>10}  {:>10} {:>10}  {:>9}  {:>9}  {:>11}  {:>11}",
        "t [s]",
        "pos rms",
        "pos p50",
        "pos p95",
        "vel rms",
        "vel p95",
        "tilt rms",
        "hdg rms",
        "predicted",
        "Monte Carlo"
    )?;
    writeln!(
        out,
        "  {:>6}  {:>10} {:>10} {:>10}  {:>10} {:>10}  {:>9}  {:>9}  {:>11}  {:>11}",
        "", "[m]", "[m]", "[m]", "[m/s]", "[m/s]", "[°]", "[°]", "1σ [m]", "rms [m]"
    )?;
    for r in &n.rows {
        let m = &r.measured;
        writeln!(
            out,
            "  {:>6}  {:>10} {:>10} {:>10}  {:>10} {:>10}  {:>9}  {:>9}  {:>11}  {:>11}",
            m.t_s,
            sig(m.horizontal_position_m.rms),
            sig(m.horizontal_position_m.p50),
            sig(m.horizontal_position_m.p95),
            sig(m.horizontal_velocity_m_s.rms),
            sig(m.horizontal_velocity_m_s.p95),
            sig(m.tilt_rad.rms * deg),
            sig(m.heading_rad.rms * deg),
            sig(r.predicted.total_m),
            sig(r.monte_carlo.rms),
        )?;
    }
    Ok(())
}

fn print_file(
    out: &mut impl Write,
    file: &Path,
    a: &InsArgs,
    rate: f64,
    raw: &Navigated,
    compensated: Option<&Navigated>,
) -> Result<()> {
    let earth = match a.latitude {
        Some(l) => format!("latitude {l}°: normal gravity, Earth rate, Coriolis"),
        None => "standard gravity, Earth rotation not modelled".to_string(),
    };
    writeln!(
        out,
        "{}: {rate} Hz, {} windows ({} s alignment + {} s, one every {} s{}); {earth}",
        file.display(),
        raw.windows,
        a.align,
        a.horizon,
        a.every,
        if raw.windows_with_gaps > 0 {
            format!(", {} across gaps left out", raw.windows_with_gaps)
        } else {
            String::new()
        }
    )?;
    writeln!(
        out,
        "  heading 0 (levelled; a MEMS gyro cannot gyrocompass); gyro bias: the mean over each alignment window"
    )?;
    match compensated {
        None => print_curve(out, raw)?,
        Some(c) => {
            writeln!(out, "  raw")?;
            print_curve(out, raw)?;
            writeln!(
                out,
                "  compensated ({})",
                a.model
                    .as_deref()
                    .map_or(String::new(), |p| p.display().to_string())
            )?;
            print_curve(out, c)?;
            let at = |n: &Navigated| {
                n.rows
                    .iter()
                    .find(|r| r.measured.t_s == 60.0)
                    .or(n.rows.last())
                    .map(|r| (r.measured.t_s, r.measured.horizontal_position_m.rms))
            };
            if let (Some((t, r)), Some((_, cm))) = (at(raw), at(c)) {
                writeln!(
                    out,
                    "  {t} s without GNSS: raw {} m, compensated {} m (RMS over the windows)",
                    sig(r),
                    sig(cm)
                )?;
            }
        }
    }
    if raw.windows < 10 {
        few_windows_note(out, raw.windows)?;
    }
    writeln!(out)?;
    Ok(())
}

/// Few windows make the percentiles rough; say so rather than hide it.
fn few_windows_note(out: &mut impl Write, windows: usize) -> Result<()> {
    writeln!(
        out,
        "  note: {windows} windows only: the 95th percentile is rough (a longer recording or a smaller --every gives more)"
    )?;
    Ok(())
}
