//! `imutherm ins`: strapdown navigation of static recordings from many
//! start points, the error against the static truth beside its prediction
//! from the noise terms and a Monte Carlo of them; raw against compensated.

use std::io::Write;
use std::path::Path;

use anyhow::Result;

use analysis::navigation::{AGREEMENT, Navigated, Plan, raw_and_compensated};
use analysis::navigation_document::{NavigationDocument, NavigationEntry};
use imu::output::{OutputPolicy, check_output, write_file};
use ins::drift::report_times;
use ins::schuler::flat_earth_limit_s;
use ins::strapdown::NavOptions;
use report::navigation_plot::navigation_plot;
use report::plots::Target;
use thermal::tcal::Model;

use crate::args::InsArgs;
use crate::flags::UsageError;
use crate::print::{notes, read_static_channels};

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
    let read = a.read.recording_options()?;
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
            let mut entry = NavigationEntry::of(&raw, rate, &plan, a.horizon);
            entry.file = Some(file.display().to_string());
            if let (Some(c), Some(path)) = (&compensated, &a.model) {
                let mut comp = NavigationEntry::of(c, rate, &plan, a.horizon);
                comp.model = Some(path.display().to_string());
                entry.compensated = Some(Box::new(comp));
            }
            files.push(entry);
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
        let doc = NavigationDocument::new(env!("CARGO_PKG_VERSION"), files);
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
