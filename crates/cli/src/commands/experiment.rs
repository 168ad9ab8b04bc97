//! The parts of an experiment's report shared by `demo` and `report`: each
//! run's noise terms, the thesis's tables, the ADEV figures.

use std::f64::consts::PI;
use std::path::Path;

use anyhow::Result;
use rayon::prelude::*;

use allan::Point;
use allan::noise_terms::{NoiseTerms, Term, TermEstimate, analyze_terms};
use imu::{Quantity, RecordingOptions};
use report::html::Page;
use report::plots::{Asymptote, Curve, adev_plot, temperature_colour};

use crate::commands::selection::{Channel, read_channels};

/// The mark near the start of a log imutherm wrote.
pub const LOG_MARK: &str = "# format: imutherm-log/1";
/// The mark near the start of a page imutherm wrote.
pub const PAGE_MARK: &str = "<title>imutherm";

/// Refuses an output directory in which one of the names a command writes
/// (`(name, mark)`) holds a file imutherm did not write, before any work:
/// the command replaces its own files, never someone else's under the same
/// name. A file is imutherm's when `mark` is in its first 4 KiB.
pub fn refuse_foreign_files(dir: &Path, own: &[(&str, &str)]) -> Result<()> {
    use std::io::Read;
    for (name, mark) in own {
        let path = dir.join(name);
        let Ok(file) = std::fs::File::open(&path) else {
            continue;
        };
        let mut head = Vec::new();
        // A directory under the name, or an unreadable file, is not ours.
        let _ = file.take(4096).read_to_end(&mut head);
        if !String::from_utf8_lossy(&head).contains(mark) {
            anyhow::bail!(
                "{} exists and was not written by imutherm: move it, or choose another --out",
                path.display()
            );
        }
    }
    Ok(())
}

/// One channel of one run, analysed.
pub struct Analysed {
    /// The channel.
    pub channel: Channel,
    /// Its OADEV at octave taus, 95 % intervals.
    pub points: Vec<Point>,
    /// Its noise terms.
    pub terms: NoiseTerms,
}

/// Reads the inertial channels of a run and identifies their noise terms.
pub fn analyse_run(path: &Path, read: &RecordingOptions) -> Result<(Vec<Analysed>, Option<f64>)> {
    let sel = read_channels(path, &[], read)?;
    let temp = sel.temperature_mean_c;
    let rate = sel.rate_hz;
    let out = sel
        .channels
        .into_par_iter()
        .map(|channel| {
            let (points, terms) = analyze_terms(&channel.data, rate, 0.95)?;
            Ok(Analysed {
                channel,
                points,
                terms,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    Ok((out, temp))
}

/// The page's "Command" section: the command line that made it and the
/// version, so that a report can be made again.
pub fn command_section(page: &mut Page) {
    page.heading("Command");
    page.code(&format!(
        "{} (imutherm {})",
        std::env::args().collect::<Vec<_>>().join(" "),
        env!("CARGO_PKG_VERSION")
    ));
}

/// Where PNG copies of the figures go, when asked for.
pub struct PngDir(pub Option<std::path::PathBuf>);

impl PngDir {
    /// From `--format svg|png` and the output folder (PNGs in DIR/figures).
    pub fn new(format: &str, out: &Path) -> Result<PngDir> {
        match format.to_ascii_lowercase().as_str() {
            "svg" => Ok(PngDir(None)),
            "png" => {
                let dir = out.join("figures");
                std::fs::create_dir_all(&dir)?;
                Ok(PngDir(Some(dir)))
            }
            other => anyhow::bail!("--format {other}: expected svg or png"),
        }
    }

    /// The file for a figure called `name`, if PNGs are wanted.
    pub fn path(&self, name: &str) -> Option<std::path::PathBuf> {
        let safe: String = name
            .chars()
            .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
            .collect();
        self.0.as_ref().map(|d| d.join(format!("{safe}.png")))
    }
}

/// The fitted noise terms of a channel as ADEV asymptotes (IEEE 952
/// Annex C), and its ADEV minimum as a marker.
fn guides(r: &Analysed, run: &str) -> (Vec<Asymptote>, Option<(f64, f64, String)>) {
    let u = &r.channel.unit;
    let units = |t: Term| crate::commands::noise::si_unit(t, r.channel.quantity, u);
    let lines = Term::ALL
        .iter()
        .filter_map(|&t| {
            let v = r.terms.fit.get(t).value()?.value;
            // σ(τ) of the term alone, as σ(1 s)·τ^slope.
            let at_1s = t.variance_basis(1.0).sqrt() * v;
            Some(Asymptote {
                label: format!("{} = {:.3e} {} ({run}, fit)", t.symbol(), v, units(t)),
                at_1s,
                slope: t.slope(),
            })
        })
        .collect();
    let marker = r.terms.slope.sigma_min.and_then(|m| {
        m.tau.map(|tau| {
            (
                tau,
                m.value,
                format!("σ_min = {:.3e} {u} at τ = {tau:.1} s", m.value),
            )
        })
    });
    (lines, marker)
}

/// The value of `term` that holds ([`NoiseTerms::choose`]), in the
/// thesis's units, to four decimals: the fit's, the slope method's marked
/// "(slope)" where the fit cannot separate the term, an upper bound as
/// "≤ …", a "*" where the methods disagree.
pub fn held_value(r: &Analysed, term: Term) -> String {
    use allan::noise_terms::Chosen;
    let f = deg(r.channel.quantity);
    let c = r.terms.choose(term);
    match c.chosen {
        Chosen::Fit(v) => format!("{:.4}{}", v.value * f, if c.disagree { "*" } else { "" }),
        Chosen::Slope(v) => format!("{:.4} (slope)", v.value * f),
        Chosen::Bound(b) => format!("≤ {:.4}", b * f),
        Chosen::Nothing => "—".to_string(),
    }
}

/// Radians to degrees for angular rates, 1 otherwise: the thesis quotes
/// gyro terms in degrees.
pub fn deg(q: Quantity) -> f64 {
    if q == Quantity::AngularRate {
        180.0 / PI
    } else {
        1.0
    }
}

/// The thesis's tables: one per term and sensor, rows = axes, columns = the
/// runs' mean temperatures.
pub fn noise_tables(page: &mut Page, analysed: &[(Vec<Analysed>, Option<f64>)]) {
    // Rows are the first run's channels.
    let first: &[Analysed] = analysed.first().map_or(&[], |a| a.0.as_slice());
    page.heading("Noise parameters (thesis layout)");
    let header: Vec<String> = std::iter::once("axis".to_string())
        .chain(
            analysed
                .iter()
                .map(|(_, t)| t.map_or("—".into(), |t| format!("{t:.0} °C"))),
        )
        .collect();
    for (q, nunit, bunit) in [
        (Quantity::Acceleration, "m/s/√s", "m/s²"),
        (Quantity::AngularRate, "°/√s", "°/s"),
    ] {
        let names: Vec<String> = first
            .iter()
            .filter(|r| r.channel.quantity == q)
            .map(|r| r.channel.name.clone())
            .collect();
        let row = |name: &str, cell: &dyn Fn(&Analysed) -> String| -> Vec<String> {
            std::iter::once(name.to_string())
                .chain(analysed.iter().map(|(rs, _)| {
                    rs.iter()
                        .find(|r| r.channel.name == name)
                        .map_or("—".into(), cell)
                }))
                .collect()
        };
        let n_rows: Vec<Vec<String>> = names
            .iter()
            .map(|n| {
                row(n, &|r| {
                    let disagree = r.terms.disagreements.iter().any(|(t, _)| *t == Term::WhiteNoise);
                    match r.terms.slope.get(Term::WhiteNoise) {
                        TermEstimate::Value(v) if !disagree => format!("{:.4}", v.value * deg(q)),
                        // A slope the method cannot read, or one the fit
                        // contradicts, is not printed as if it held.
                        _ => format!("{} (fit)", held_value(r, Term::WhiteNoise)),
                    }
                })
            })
            .collect();
        page.table(
            &format!(
                "{} random walk N [{nunit}] (slope method at τ = 1 s)",
                if q == Quantity::AngularRate {
                    "Angle"
                } else {
                    "Velocity"
                }
            ),
            &header,
            &n_rows,
        );
        let b_rows: Vec<Vec<String>> = names
            .iter()
            .map(|n| {
                row(n, &|r| match r.terms.slope.sigma_min {
                    Some(m) if r.terms.slope.minimum == allan::noise_terms::Minimum::Found => {
                        format!("{:.4} (at {:.1} s)", m.value * deg(q), m.tau.unwrap_or(f64::NAN))
                    }
                    Some(m) => format!(
                        "no minimum within the record; σ ≤ {:.4} at {:.1} s",
                        m.hi * deg(q),
                        m.tau.unwrap_or(f64::NAN)
                    ),
                    None => "—".into(),
                })
            })
            .collect();
        page.table(
            &format!("Bias instability as the thesis quotes it: σ_min [{bunit}] (at τ); B = σ_min/0.664"),
            &header,
            &b_rows,
        );
        let fit_rows: Vec<Vec<String>> = names
            .iter()
            .map(|n| {
                row(n, &|r| match r.terms.fit.get(Term::BiasInstability) {
                    TermEstimate::Value(v) => format!(
                        "{:.4} [{:.4}, {:.4}]",
                        v.value * deg(q),
                        v.lo * deg(q),
                        v.hi * deg(q)
                    ),
                    TermEstimate::NotIdentifiable(_) => "not identifiable".into(),
                })
            })
            .collect();
        page.table(
            &format!("Bias instability B from the model fit [{bunit}], 95 % interval"),
            &header,
            &fit_rows,
        );
    }
}

/// The ADEV of each channel with one curve per run.
pub fn adev_figures(page: &mut Page, analysed: &[(Vec<Analysed>, Option<f64>)], png: &PngDir) -> Result<()> {
    // Curves coloured on a cold-to-hot scale by the runs' temperatures.
    let (t_lo, t_hi) = analysed
        .iter()
        .filter_map(|a| a.1)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), t| {
            (a.min(t), b.max(t))
        });
    // One plot per sensor and run: its three axes together.
    for (rs, t) in analysed {
        let run = t.map_or("—".to_string(), |t| format!("{t:.0} °C"));
        for q in [Quantity::Acceleration, Quantity::AngularRate] {
            let curves: Vec<Curve> = rs
                .iter()
                .filter(|r| r.channel.quantity == q)
                .map(|r| Curve::plain(r.channel.name.clone(), &r.points))
                .collect();
            let Some(unit) = rs
                .iter()
                .find(|r| r.channel.quantity == q)
                .map(|r| r.channel.unit.clone())
            else {
                continue;
            };
            let what = if q == Quantity::AngularRate {
                "gyroscope"
            } else {
                "accelerometer"
            };
            let title = format!("{what} at {run}");
            page.figure(
                &adev_plot(&title, &unit, &curves)?,
                &format!("{title}: the three axes, 95 % bands"),
            );
            if let Some(p) = png.path(&format!("adev_{title}")) {
                report::plots::adev_plot_png(&p, &title, &unit, &curves)?;
            }
        }
    }
    let first: &[Analysed] = analysed.first().map_or(&[], |a| a.0.as_slice());
    page.heading("Allan deviation at each temperature");
    for name in first.iter().map(|r| r.channel.name.clone()).collect::<Vec<_>>() {
        let curves: Vec<Curve> = analysed
            .iter()
            .enumerate()
            .filter_map(|(i, (rs, t))| {
                rs.iter().find(|r| r.channel.name == name).map(|r| {
                    let label = t.map_or("—".into(), |t| format!("{t:.0} °C"));
                    // The fitted terms of the first run, drawn as dashed
                    // asymptotes; more would hide the curves.
                    let (asymptotes, marker) = if i == 0 {
                        guides(r, &label)
                    } else {
                        (Vec::new(), None)
                    };
                    Curve {
                        label,
                        points: &r.points,
                        asymptotes,
                        marker,
                        colour: t.map(|t| temperature_colour((t - t_lo) / (t_hi - t_lo).max(1e-9))),
                    }
                })
            })
            .collect();
        let unit = first
            .iter()
            .find(|r| r.channel.name == name)
            .map_or(String::new(), |r| r.channel.unit.clone());
        page.figure(
            &adev_plot(&name, &unit, &curves)?,
            &format!("{name}: overlapping ADEV, 95 % bands"),
        );
        if let Some(p) = png.path(&format!("adev_{name}")) {
            report::plots::adev_plot_png(&p, &name, &unit, &curves)?;
        }
    }
    Ok(())
}

/// The raw samples of a run against time, accelerometers and gyroscopes
/// apart, each with the temperature below.
pub fn time_figures(
    page: &mut Page,
    sel: &crate::commands::selection::Selection,
    title: &str,
    png: &PngDir,
) -> Result<()> {
    for (q, what) in [
        (Quantity::Acceleration, "accelerometer"),
        (Quantity::AngularRate, "gyroscope"),
    ] {
        let chans: Vec<(String, &[f64])> = sel
            .channels
            .iter()
            .filter(|c| c.quantity == q)
            .map(|c| (c.name.clone(), c.data.as_slice()))
            .collect();
        let Some(unit) = sel
            .channels
            .iter()
            .find(|c| c.quantity == q)
            .map(|c| c.unit.clone())
        else {
            continue;
        };
        let heading = format!("{title}: {what}");
        let svg = report::plots::time_plot(&heading, &unit, &chans, sel.rate_hz, sel.temperature.as_deref())?;
        if let Some(p) = png.path(&format!("time_{heading}")) {
            report::plots::time_plot_png(
                &p,
                &heading,
                &unit,
                &chans,
                sel.rate_hz,
                sel.temperature.as_deref(),
            )?;
        }
        page.figure(
            &svg,
            &format!("{title}: {what} samples (min/max per pixel column) and temperature"),
        );
    }
    Ok(())
}
