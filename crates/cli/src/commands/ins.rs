//! `imutherm ins`: strapdown navigation of static recordings from many
//! start points, the error against the static truth beside its prediction
//! from the noise terms and a Monte Carlo of them; raw against compensated.

use std::io::Write;
use std::path::Path;

use anyhow::Result;
use serde_json::{Value, json};

use analysis::navigation::{CHANNELS, MONTE_CARLO_RUNS, Navigated, Plan, raw_and_compensated};
use ins::drift::{Spread, report_times};
use ins::prediction::AxisNoise;
use ins::strapdown::NavOptions;
use thermal::tcal::Model;

use crate::args::InsArgs;
use crate::flags::recording_options;
use crate::print::{notes, read_channels};

const SCHEMA: &str = "imutherm.ins/1";

pub fn run(a: &InsArgs) -> Result<()> {
    let read = recording_options(&a.read)?;
    let model = a.model.as_deref().map(Model::read).transpose()?;
    let plan = Plan {
        options: NavOptions {
            align_s: a.align,
            latitude_deg: a.latitude,
            remove_gyro_bias: true,
        },
        every_s: a.every,
        times: report_times(a.horizon),
    };
    let mut files = Vec::new();
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    for file in &a.files {
        let sel = read_channels(file, &[], &read)?;
        let rate = sel.rate_hz;
        // Levelling averages the samples of the alignment window: one
        // shorter than a sample holds none.
        if a.align * rate < 1.0 {
            return Err(crate::flags::UsageError(format!(
                "--align {} s is shorter than one sample of {} ({} Hz, {} s a sample)",
                a.align,
                file.display(),
                rate,
                1.0 / rate
            ))
            .into());
        }
        let mut noted = Vec::new();
        let navigated = raw_and_compensated(file, &sel, model.as_ref(), &plan, &mut noted);
        notes(&noted);
        let (raw, compensated) = navigated?;
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
