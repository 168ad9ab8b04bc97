//! `imutherm ins`: strapdown navigation of static recordings from many
//! start points, the error against the static truth beside its prediction
//! from the noise terms and a Monte Carlo of them; raw against compensated.

use std::io::Write;
use std::path::Path;

use anyhow::Result;
use serde_json::{Value, json};

use analysis::navigation::{AGREEMENT, CHANNELS, Navigated, Plan, raw_and_compensated};
use imu::output::{OutputPolicy, check_output, write_file};
use ins::drift::{Spread, report_times};
use ins::prediction::AxisNoise;
use ins::schuler::flat_earth_limit_s;
use ins::strapdown::NavOptions;
use report::navigation_plot::navigation_plot;
use report::plots::Target;
use thermal::tcal::Model;

use crate::args::InsArgs;
use crate::flags::{UsageError, recording_options};
use crate::print::{notes, read_static_channels};

const SCHEMA: &str = "imutherm.ins/1";

/// How a plot is written, from the name's extension.
enum PlotFormat {
    Svg,
    Png,
}

fn plot_format(path: &Path) -> Result<PlotFormat> {
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
    {
        Some(e) if e == "svg" => Ok(PlotFormat::Svg),
        Some(e) if e == "png" => Ok(PlotFormat::Png),
        _ => Err(UsageError(format!(
            "--plot {}: the name must end in .svg or .png",
            path.display()
        ))
        .into()),
    }
}

pub fn run(a: &InsArgs) -> Result<()> {
    let read = recording_options(&a.read)?;
    // Without the transport rate the navigation has no Schuler loop: past
    // 1/ω_s its figures are those of a flat Earth, and grow as t^{5/2} to
    // t^{7/2} where a navigator on the Earth oscillates.
    let limit = flat_earth_limit_s();
    if a.latitude.is_none() && a.horizon > limit {
        return Err(UsageError(format!(
            "--horizon {} s without --latitude: past {limit:.0} s (1/ω_s, the Schuler loop's) a flat, \
             non-rotating Earth no longer stands for the real one; give the latitude",
            a.horizon
        ))
        .into());
    }
    let plot = a
        .plot
        .as_deref()
        .map(|p| plot_format(p).map(|f| (p, f)))
        .transpose()?;
    // The plot replaces a file of its name, never one being read; checked
    // before the navigation, not after it.
    let inputs: Vec<std::path::PathBuf> = a.files.iter().chain(&a.model).cloned().collect();
    let policy = OutputPolicy {
        overwrite: true,
        inputs: &inputs,
    };
    if let Some((path, _)) = plot {
        check_output(path, &policy)?;
    }
    let model = a.model.as_deref().map(Model::read).transpose()?;
    let plan = Plan {
        options: NavOptions {
            align_s: a.align,
            latitude_deg: a.latitude,
            remove_gyro_bias: true,
        },
        every_s: a.every,
        times: report_times(a.horizon),
        monte_carlo_runs: a.runs as usize,
        monte_carlo_seed: a.seed,
    };
    let mut plotted: Vec<(String, Navigated)> = Vec::new();
    let mut files = Vec::new();
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    for file in &a.files {
        let sel = read_static_channels(file, &[], &read, a.motion.allow_motion)?;
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
        if plot.is_some() {
            let name = if a.files.len() > 1 {
                format!("{}: ", file.display())
            } else {
                String::new()
            };
            let comp = compensated.map(|c| (format!("{name}compensated"), c));
            plotted.push((format!("{name}raw"), raw));
            plotted.extend(comp);
        }
    }
    if let Some((path, format)) = plot {
        write_plot(path, format, &plotted, &policy)?;
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

/// The plot of every run navigated, to `path`: a PNG drawn beside it and
/// renamed onto it, an SVG likewise.
fn write_plot(
    path: &Path,
    format: PlotFormat,
    runs: &[(String, Navigated)],
    policy: &OutputPolicy,
) -> Result<()> {
    let runs: Vec<(&str, &Navigated)> = runs.iter().map(|(n, r)| (n.as_str(), r)).collect();
    let title = "Horizontal position error without aiding";
    match format {
        PlotFormat::Png => {
            navigation_plot(Target::Png(path), title, &runs)?;
        }
        PlotFormat::Svg => {
            let svg = navigation_plot(Target::Svg, title, &runs)?
                .into_svg()
                .unwrap_or_default();
            write_file(path, svg.as_bytes(), policy)?;
        }
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
                "vertical_position_m": spread_json(m.vertical_position_m),
                // The old name of the DRMS, kept: it is not a 1σ of the distance.
                "predicted_horizontal_position_1sigma_m": r.predicted.total_m,
                "predicted_horizontal_position_drms_m": r.predicted.total_m,
                "predicted_vertical_position_1sigma_m": r.predicted.vertical_m,
                "predicted_terms_m": terms,
                "prediction_within_monte_carlo": r.prediction_holds(),
                "monte_carlo_horizontal_position_m": spread_json(r.monte_carlo),
                "monte_carlo_horizontal_position_rms_95_m": r.monte_carlo_rms_95,
                "monte_carlo_vertical_position_m": spread_json(r.monte_carlo_vertical),
                "monte_carlo_vertical_position_rms_95_m": r.monte_carlo_vertical_rms_95,
                "vertical_prediction_within_monte_carlo": r.vertical_prediction_holds(),
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
        "schuler_loop": a.latitude.is_some(),
        "monte_carlo_runs": n.monte_carlo_runs,
        "monte_carlo_seed": n.monte_carlo_seed,
        "monte_carlo_agreement": AGREEMENT,
        "prediction_stops_at_s": n.prediction_stops_at(),
        "vertical_prediction_stops_at_s": n.vertical_prediction_stops_at(),
        "noise_from": n.noise_from.key(),
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
    let line = |out: &mut dyn Write, c: [&str; 14]| -> std::io::Result<()> {
        writeln!(
            out,
            "  {:>6}  {:>10} {:>10} {:>10}  {:>10} {:>10}  {:>9}  {:>9}  {:>11}  {:>11}  {:>21}  {:>10}  {:>11}  {:>11}",
            c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8], c[9], c[10], c[11], c[12], c[13]
        )
    };
    line(
        out,
        [
            "t [s]",
            "pos rms",
            "pos p50",
            "pos p95",
            "vel rms",
            "vel p95",
            "tilt rms",
            "hdg rms",
            "predicted",
            "Monte Carlo",
            "Monte Carlo rms",
            "height rms",
            "predicted",
            "Monte Carlo",
        ],
    )?;
    line(
        out,
        [
            "",
            "[m]",
            "[m]",
            "[m]",
            "[m/s]",
            "[m/s]",
            "[°]",
            "[°]",
            "DRMS [m]",
            "rms [m]",
            "95 % [m]",
            "[m]",
            "height [m]",
            "height [m]",
        ],
    )?;
    for r in &n.rows {
        let m = &r.measured;
        let [lo, hi] = r.monte_carlo_rms_95;
        let flag = if r.prediction_holds() { "" } else { "*" };
        let vflag = if r.vertical_prediction_holds() { "" } else { "†" };
        line(
            out,
            [
                &m.t_s.to_string(),
                &sig(m.horizontal_position_m.rms),
                &sig(m.horizontal_position_m.p50),
                &sig(m.horizontal_position_m.p95),
                &sig(m.horizontal_velocity_m_s.rms),
                &sig(m.horizontal_velocity_m_s.p95),
                &sig(m.tilt_rad.rms * deg),
                &sig(m.heading_rad.rms * deg),
                &format!("{}{flag}", sig(r.predicted.total_m)),
                &sig(r.monte_carlo.rms),
                &format!("{}…{}", sig(lo), sig(hi)),
                &sig(m.vertical_position_m.rms),
                &format!("{}{vflag}", sig(r.predicted.vertical_m)),
                &sig(r.monte_carlo_vertical.rms),
            ],
        )?;
    }
    if let Some(t) = n.prediction_stops_at() {
        writeln!(
            out,
            "  * from {t} s the closed form is more than {:.0} % outside the Monte Carlo's 95 % interval: read the Monte Carlo there",
            AGREEMENT * 100.0
        )?;
    }
    if let Some(t) = n.vertical_prediction_stops_at() {
        writeln!(
            out,
            "  † the height's closed form (the vertical accelerometer alone) leaves the Monte Carlo from {t} s: \
             the Coriolis acceleration of the horizontal velocity error takes over; read the Monte Carlo there"
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
        Some(l) => format!("latitude {l}°: normal gravity, Earth rate, Coriolis, the Schuler loop"),
        None => format!(
            "no latitude: standard gravity, no Earth rotation, no Schuler loop (holds to {:.0} s)",
            flat_earth_limit_s()
        ),
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
        "  heading 0 (levelled; a MEMS gyro cannot gyrocompass); gyro bias: the mean over each alignment window; \
         gravity: the mean specific force's magnitude over it"
    )?;
    writeln!(
        out,
        "  predicted from {} noise terms; Monte Carlo: {} runs from seed {}, its rms with a 95 % interval",
        raw.noise_from.describe(),
        raw.monte_carlo_runs,
        raw.monte_carlo_seed
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
