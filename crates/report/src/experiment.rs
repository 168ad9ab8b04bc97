//! The parts of an experiment's page shared by `imutherm demo` and
//! `imutherm report`: the output folder, the command, each run's noise
//! terms in the thesis's tables, the ADEV figures, the raw data.

use std::path::{Path, PathBuf};

use allan::Point;
use allan::noise_terms::{Chosen, Minimum, NoiseTerms, Term, TermEstimate};
use analysis::AnalysisError;
use analysis::dynamic_adev::DynamicAdev;
use analysis::experiment::{COMPARED_AT_S, Experiment};
use analysis::navigation::{Navigated, Plan, Row};
use analysis::noise::{ChannelNoise, FIGURE_CONFIDENCE, RunNoise};
use analysis::selection::Selection;
use analysis::term_law::{SIGNIFICANCE, without_law};
use analysis::thesis::ThesisTables;
use imu::Quantity;
use thermal::evaluation::{BinMean, spread};

use crate::PlotError;
use crate::ReportError;
use crate::charts::{Chart, adev_chart, time_chart};
use crate::html::{Page, significant};
use crate::model_plot::{ModelAxis, evidence, model_plot};
use crate::navigation_plot::navigation_plot;
use crate::page_units::{self, Kind, Units, kind_of, scaled, unit_or};
use crate::plots::{
    Asymptote, Curve, Drawn, Target, adev_heatmap_bins, adev_heatmap_slices, adev_plot, bias_plot,
    temperature_colour, time_plot,
};
use analysis::units::unit_of;

/// The mark near the start of a log imutherm wrote.
pub const LOG_MARK: &str = "# format: imutherm-log/1";
/// The mark near the start of a page imutherm wrote.
pub const PAGE_MARK: &str = "<title>imutherm";

/// Refuses an output directory in which one of the names a command writes
/// (`(name, mark)`) holds a file imutherm did not write, before any work:
/// the command replaces its own files, never someone else's under the same
/// name. A file is imutherm's when `mark` is in its first 4 KiB.
pub fn refuse_foreign_files(dir: &Path, own: &[(&str, &str)]) -> Result<(), ReportError> {
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
            return Err(ReportError::Foreign(path));
        }
    }
    Ok(())
}

/// The page's "Command" section: the command line that made it and the
/// version, so that a report can be made again.
pub fn command_section(page: &mut Page, command_line: &str) {
    page.heading("Command");
    page.code(&format!(
        "{command_line} (imutherm {})",
        env!("CARGO_PKG_VERSION")
    ));
}

/// Where PNG copies of the figures go, when asked for.
pub struct PngDir(pub Option<PathBuf>);

impl PngDir {
    /// PNG copies in `out/figures` when `png`, none otherwise.
    pub fn new(png: bool, out: &Path) -> Result<PngDir, ReportError> {
        if !png {
            return Ok(PngDir(None));
        }
        let dir = out.join("figures");
        std::fs::create_dir_all(&dir).map_err(|cause| ReportError::Io {
            path: dir.clone(),
            cause,
        })?;
        Ok(PngDir(Some(dir)))
    }

    /// The file for a figure called `name`, if PNGs are wanted.
    pub fn path(&self, name: &str) -> Option<PathBuf> {
        let safe: String = name
            .chars()
            .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
            .collect();
        self.0.as_ref().map(|d| d.join(format!("{safe}.png")))
    }
}

/// A figure on the page and, when PNGs are wanted, the same plot as the
/// PNG file `png_name`: one plotting function draws both.
pub fn figure(
    page: &mut Page,
    png: &PngDir,
    png_name: &str,
    caption: &str,
    plot: impl Fn(Target) -> Result<Drawn, PlotError>,
) -> Result<(), ReportError> {
    if let Some(svg) = plot(Target::Svg)?.into_svg() {
        page.figure(&svg, caption);
    }
    if let Some(p) = png.path(png_name) {
        plot(Target::Png(&p))?;
    }
    Ok(())
}

/// A figure as [`figure`] draws it that is also an interactive chart on the
/// page ([`Page::chart_figure`]).
pub fn chart_figure(
    page: &mut Page,
    png: &PngDir,
    png_name: &str,
    caption: &str,
    plot: impl Fn(Target) -> Result<Drawn, PlotError>,
    chart: &Chart,
) -> Result<(), ReportError> {
    if let Some(svg) = plot(Target::Svg)?.into_svg() {
        page.chart_figure(&svg, caption, chart);
    }
    if let Some(p) = png.path(png_name) {
        plot(Target::Png(&p))?;
    }
    Ok(())
}

/// The factor from a term's SI value to the page's units, and that unit:
/// the page's table unit for N, B and K; Q and R are in no table, so
/// `noise --units`'s unit for them.
fn term_unit_in(t: Term, q: Quantity, data_unit: &str, units: Units) -> (f64, String) {
    match t {
        Term::Quantization | Term::RateRamp => unit_of(t, q, data_unit, units),
        t => unit_or(q, data_unit, kind_of(t), units),
    }
}

/// The selected model's noise terms of a channel as ADEV asymptotes (IEEE
/// 952 Annex C), and its ADEV minimum as a marker.
fn guides(r: &ChannelNoise, run: &str, units: Units) -> (Vec<Asymptote>, Option<(f64, f64, String)>) {
    let (q, u) = (r.channel.quantity, &r.channel.unit);
    let (level, u) = unit_or(q, u, Kind::Instability, units);
    let lines = Term::ALL
        .iter()
        .filter_map(|&t| {
            let v = r.terms.model.get(t).value()?.value;
            // σ(τ) of the term alone, as σ(1 s)·τ^slope, in the axis's unit.
            let at_1s = t.variance_basis(1.0).sqrt() * v * level;
            let (f, term_unit) = term_unit_in(t, q, &r.channel.unit, units);
            Some(Asymptote {
                label: format!(
                    "{} = {:.3e} {} ({run}, model {})",
                    t.symbol(),
                    v * f,
                    term_unit,
                    r.terms.model.label
                ),
                at_1s,
                slope: t.slope(),
            })
        })
        .collect();
    let marker = r.terms.slope.sigma_min.and_then(|m| {
        m.tau.map(|tau| {
            (
                tau,
                m.value * level,
                format!("σ_min = {:.3e} {u} at τ = {tau:.1} s", m.value * level),
            )
        })
    });
    (lines, marker)
}

/// A table's figure to four significant digits: decimals from 0.01 up (the
/// thesis's layout), an exponent below (a gyro's B in rad/s would read
/// 0.0000).
fn four(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || x.abs() >= 0.01 {
        let decimals = (3 - x.abs().log10().floor() as i32).clamp(0, 4) as usize;
        format!("{x:.decimals$}")
    } else {
        format!("{x:.3e}")
    }
}

/// The term a table shows for a run, times `factor`: the selected model's
/// value, or `≤` its upper bound where the data do not hold it.
fn held_value(terms: &NoiseTerms, term: Term, factor: f64) -> String {
    match terms.choose(term).chosen {
        Chosen::Model(v) => four(v.value * factor),
        Chosen::Bound(b) => format!("≤ {}", four(b * factor)),
        Chosen::Nothing => "—".to_string(),
    }
}

/// The thesis's tables ([`ThesisTables`]): per sensor, the selected
/// model's N, σ_min as the thesis quotes it, and the model's B, rows =
/// axes, columns = the runs' mean temperatures.
pub fn noise_tables(page: &mut Page, runs: &[RunNoise], units: Units) {
    let tables = ThesisTables::new(
        runs.iter().map(|r| r.temperature_mean_c).collect(),
        runs.iter()
            .enumerate()
            .flat_map(|(i, r)| r.channels.iter().map(move |c| (i, &c.channel, &c.terms))),
    );
    page.heading("Noise parameters (thesis layout)");
    let header: Vec<String> = std::iter::once("axis".to_string())
        .chain(
            tables
                .columns
                .iter()
                .map(|t| t.map_or("—".into(), |t| format!("{t:.0} °C"))),
        )
        .collect();
    for q in [Quantity::Acceleration, Quantity::AngularRate] {
        let Some(((nf, nunit), (bf, bunit))) =
            page_units::unit(q, Kind::WhiteNoise, units).zip(page_units::unit(q, Kind::Instability, units))
        else {
            continue;
        };
        let rows = tables.group(q).map_or(&[][..], |g| g.rows.as_slice());
        let table = |cell: &dyn Fn(&NoiseTerms) -> String| -> Vec<Vec<String>> {
            rows.iter()
                .map(|row| {
                    std::iter::once(row.name.to_string())
                        .chain(row.cells.iter().map(|c| c.map_or("—".into(), |c| cell(c.terms))))
                        .collect()
                })
                .collect()
        };
        let n_rows = table(&|terms| held_value(terms, Term::WhiteNoise, nf));
        page.table(
            &format!(
                "{} random walk N [{nunit}] (selected noise model; ≤: an upper bound)",
                if q == Quantity::AngularRate {
                    "Angle"
                } else {
                    "Velocity"
                }
            ),
            &header,
            &n_rows,
        );
        let b_rows = table(&|terms| match terms.slope.sigma_min {
            Some(m) if terms.slope.minimum == Minimum::Found => {
                format!("{} (at {:.1} s)", four(m.value * bf), m.tau.unwrap_or(f64::NAN))
            }
            Some(m) => format!(
                "no minimum within the record; σ ≤ {} at {:.1} s",
                four(m.hi * bf),
                m.tau.unwrap_or(f64::NAN)
            ),
            None => "—".into(),
        });
        page.table(
            &format!("Bias instability as the thesis quotes it: σ_min [{bunit}] (at τ); B = σ_min/0.664"),
            &header,
            &b_rows,
        );
        let fit_rows = table(&|terms| match terms.model.get(Term::BiasInstability) {
            TermEstimate::Value(v) => format!(
                "{} [{}, {}]",
                four(v.value * bf),
                four(v.lo * bf),
                four(v.hi * bf)
            ),
            TermEstimate::NotIdentifiable(_) => held_value(terms, Term::BiasInstability, bf),
        });
        page.table(
            &format!(
                "Bias instability B of the selected noise model [{bunit}], 95 % interval; ≤: an upper bound"
            ),
            &header,
            &fit_rows,
        );
    }
    // Which of the tables' differences are real: each axis's law over the
    // runs' temperatures and every pair of runs compared.
    if tables.over_temperature() {
        let laws = tables.laws(FIGURE_CONFIDENCE);
        let mut rows: Vec<Vec<String>> = laws
            .iter()
            .filter(|(_, l)| l.fit.is_some())
            .map(|(name, law)| vec![law.describe(name), law.describe_differences()])
            .collect();
        rows.extend(without_law(&laws).map(|rest| vec![rest, "—".to_string()]));
        page.table(
            &format!(
                "Over temperature: ln(term) linear in T, each run weighted by its 95 % interval; a dependence or a \
                 difference is called at p < {SIGNIFICANCE}, a bound is left out, never taken for a value"
            ),
            &["law over temperature".to_string(), "which runs differ".to_string()],
            &rows,
        );
    }
}

/// The ADEV of each channel with one curve per run.
pub fn adev_figures(
    page: &mut Page,
    runs: &[RunNoise],
    png: &PngDir,
    units: Units,
) -> Result<(), ReportError> {
    // Every channel's points in the page's units, drawn borrowed below.
    let level = |c: &ChannelNoise| unit_or(c.channel.quantity, &c.channel.unit, Kind::Instability, units);
    let points: Vec<Vec<Vec<Point>>> = runs
        .iter()
        .map(|r| r.channels.iter().map(|c| scaled(&c.points, level(c).0)).collect())
        .collect();
    // Curves coloured on a cold-to-hot scale by the runs' temperatures.
    let (t_lo, t_hi) = runs
        .iter()
        .filter_map(|r| r.temperature_mean_c)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), t| {
            (a.min(t), b.max(t))
        });
    // One plot per sensor and run: its three axes together.
    for (r, pts) in runs.iter().zip(&points) {
        let (rs, t) = (&r.channels, r.temperature_mean_c);
        let run = t.map_or("—".to_string(), |t| format!("{t:.0} °C"));
        for q in [Quantity::Acceleration, Quantity::AngularRate] {
            let curves: Vec<Curve> = rs
                .iter()
                .zip(pts)
                .filter(|(r, _)| r.channel.quantity == q)
                .map(|(r, p)| Curve::plain(r.channel.name.clone(), p))
                .collect();
            let Some(unit) = rs.iter().find(|r| r.channel.quantity == q).map(|r| level(r).1) else {
                continue;
            };
            let what = if q == Quantity::AngularRate {
                "gyroscope"
            } else {
                "accelerometer"
            };
            let title = format!("{what} at {run}");
            chart_figure(
                page,
                png,
                &format!("adev_{title}"),
                &format!("{title}: the three axes, 95 % bands"),
                |t| adev_plot(t, &title, &unit, &curves),
                &adev_chart(&title, &unit, &curves),
            )?;
        }
    }
    let first: &[ChannelNoise] = runs.first().map_or(&[], |r| r.channels.as_slice());
    page.heading("Allan deviation at each temperature");
    for name in first.iter().map(|r| r.channel.name.clone()).collect::<Vec<_>>() {
        let curves: Vec<Curve> = runs
            .iter()
            .enumerate()
            .filter_map(|(i, run)| {
                let (rs, t) = (&run.channels, run.temperature_mean_c);
                let at = rs.iter().position(|r| r.channel.name == name)?;
                Some(&rs[at]).map(|r| {
                    let label = t.map_or("—".into(), |t| format!("{t:.0} °C"));
                    // The fitted terms of the first run, drawn as dashed
                    // asymptotes; more would hide the curves.
                    let (asymptotes, marker) = if i == 0 {
                        guides(r, &label, units)
                    } else {
                        (Vec::new(), None)
                    };
                    Curve {
                        label,
                        points: &points[i][at],
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
            .map_or(String::new(), |r| level(r).1);
        chart_figure(
            page,
            png,
            &format!("adev_{name}"),
            &format!("{name}: overlapping ADEV, 95 % bands"),
            |t| adev_plot(t, &name, &unit, &curves),
            &adev_chart(&name, &unit, &curves),
        )?;
    }
    Ok(())
}

/// Each axis's selected noise model against its measured ADEV, one figure
/// per axis and run: the measured curve with its intervals, the model, each
/// kept process's own curve and each dropped term at its bound, and the
/// residuals below; with a table of each axis's model, its goodness of fit
/// and why each process was kept.
pub fn model_figures(
    page: &mut Page,
    runs: &[RunNoise],
    png: &PngDir,
    units: Units,
) -> Result<(), ReportError> {
    page.heading("Noise model of each axis");
    page.paragraph(
        "The selected model (terms chosen by the information criterion BIC) drawn on the measured \
         overlapping ADEV: each kept process dashed, each dropped term dotted at its upper bound, the \
         residual panel measured/model with the measured interval. \"criterion +x\" is how much worse the \
         best model without that process describes the curve (BIC; above 10 is very strong evidence, Kass & Raftery 1995).",
    );
    for r in runs {
        let run = r.temperature_mean_c.map(|t| format!("{t:.0} °C"));
        let at = run.as_ref().map_or(String::new(), |t| format!(" at {t}"));
        let rows: Vec<Vec<String>> = r
            .channels
            .iter()
            .map(|c| {
                let m = &c.terms.model;
                let fit = match m.quality {
                    Some(q) if m.fits => format!("{:.2} (p = {:.2})", q.chi2_reduced, q.p_value),
                    Some(q) => format!(
                        "{:.2} (p = {:.1e}): does not describe the curve",
                        q.chi2_reduced, q.p_value
                    ),
                    None => "no candidate model fits".to_string(),
                };
                let why = m
                    .evidence
                    .iter()
                    .map(|(name, d)| format!("{name}: {}", evidence(*d)))
                    .collect::<Vec<_>>()
                    .join(", ");
                let outside = if m.outside.is_empty() {
                    "—".to_string()
                } else {
                    m.outside
                        .iter()
                        .map(|t| format!("{t:.3}"))
                        .collect::<Vec<_>>()
                        .join(", ")
                };
                vec![c.channel.name.clone(), m.label.clone(), fit, why, outside]
            })
            .collect();
        page.table(
            &format!("Selected noise model per axis{at}"),
            &[
                "axis".into(),
                "model".into(),
                "χ²/dof".into(),
                "criterion without each process".into(),
                "τ [s] where the model leaves the measured interval".into(),
            ],
            &rows,
        );
        for c in &r.channels {
            let title = format!("{}{at}: noise model", c.channel.name);
            let (q, u) = (c.channel.quantity, c.channel.unit.clone());
            let term_unit = move |t: Term| term_unit_in(t, q, &u, units);
            let (level, unit) = unit_or(q, &c.channel.unit, Kind::Instability, units);
            let points = scaled(&c.points, level);
            let axis = ModelAxis {
                title: title.clone(),
                unit,
                level,
                points: &points,
                model: &c.terms.model,
                term_unit: &term_unit,
            };
            figure(
                page,
                png,
                &format!("model_{title}"),
                &format!(
                    "{}: measured ADEV ({:.0} % intervals), the selected model {} and each of its terms; residuals below",
                    title,
                    100.0 * c.terms.model.confidence,
                    c.terms.model.label
                ),
                |t| model_plot(t, &axis),
            )?;
        }
    }
    Ok(())
}

/// The raw samples of a run against time, accelerometers and gyroscopes
/// apart, each with the temperature below.
pub fn time_figures(page: &mut Page, sel: &Selection, title: &str, png: &PngDir) -> Result<(), ReportError> {
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
        let temperature = sel.temperature.as_deref();
        chart_figure(
            page,
            png,
            &format!("time_{heading}"),
            &format!("{title}: {what} samples (min/max per pixel column) and temperature"),
            |t| time_plot(t, &heading, &unit, &chans, sel.rate_hz, temperature),
            &time_chart(&heading, &unit, &chans, sel.rate_hz, temperature),
        )?;
    }
    Ok(())
}

/// The cooling run's ADEV over temperature, per channel: the dynamic ADEV
/// (sliding windows labelled by their mean temperature, the thesis's
/// method) as 3D views, raw beside compensated, and as a heat map beside
/// the heat map of the temperature bins.
pub fn surface_section(page: &mut Page, exp: &Experiment, png: &PngDir) -> Result<(), ReportError> {
    let cool = &exp.cooling;
    page.heading("Cooling run: ADEV over temperature (3D ADEV)");
    if let Some(pair) = exp.dynamic.first() {
        page.paragraph(&dynamic_note(&pair.raw));
    }
    for ((c, rows), pair) in cool.channels.iter().zip(&exp.surfaces).zip(&exp.dynamic) {
        // Raw and compensated on one σ scale: a colour is one σ in both.
        page.surface3d_pair(
            [&format!("{}: raw", c.name), &format!("{}: compensated", c.name)],
            &c.unit,
            [&dynamic_slices(&pair.raw), &dynamic_slices(&pair.compensated)],
        );
        dynamic_heatmap(
            page,
            png,
            &c.name,
            &c.unit,
            &pair.raw,
            &format!("adev_dynamic_{}", c.name),
        )?;
        figure(
            page,
            png,
            &format!("adev_over_temperature_{}", c.name),
            &format!("{}: σ(τ, T) over 5 °C bins of the cooling run", c.name),
            |t| adev_heatmap_bins(t, &c.name, &c.unit, rows),
        )?;
    }
    Ok(())
}

/// What the dynamic ADEV's windows were, and any left without a curve.
pub fn dynamic_note(d: &DynamicAdev) -> String {
    let o = &d.options;
    let mut text = format!(
        "Dynamic ADEV: OADEV over sliding windows of {} s stepped every {} s ({} windows), each \
         labelled by its mean temperature; the compensated view is the same windows after the \
         compensation fitted on this run.",
        significant(o.window_s),
        significant(o.step_s),
        d.windows.len()
    );
    let gapped = d.windows.iter().filter(|w| w.gap_samples > 0).count();
    if gapped > 0 {
        text.push_str(&format!(
            " {gapped} windows have gaps (their terms that cross a gap are skipped)."
        ));
    }
    for s in &d.skipped {
        text.push_str(&format!(
            " The window {}–{} s has no curve: {}.",
            significant(s.start_s),
            significant(s.end_s),
            s.reason
        ));
    }
    text
}

/// The dynamic ADEV as a heat map: τ across, the windows' mean temperature
/// up.
pub fn dynamic_heatmap(
    page: &mut Page,
    png: &PngDir,
    name: &str,
    unit: &str,
    d: &DynamicAdev,
    png_name: &str,
) -> Result<(), ReportError> {
    let slices: Vec<(f64, &[allan::Point])> = d
        .windows
        .iter()
        .map(|w| (w.t_mean_c, w.points.as_slice()))
        .collect();
    figure(
        page,
        png,
        png_name,
        &format!(
            "{name}: dynamic ADEV, σ(τ) of {} s windows against their mean temperature",
            significant(d.options.window_s)
        ),
        |t| adev_heatmap_slices(t, name, unit, &slices),
    )
}

/// A dynamic ADEV as the 3D view takes it: (mean temperature, [(τ, σ)]) per
/// window.
pub fn dynamic_slices(d: &DynamicAdev) -> Vec<(f64, Vec<(f64, f64)>)> {
    d.windows
        .iter()
        .map(|w| (w.t_mean_c, w.points.iter().map(|p| (p.tau, p.dev)).collect()))
        .collect()
}

/// The compensation fitted on the cooling run, on the held-out heating
/// run: bias plots, the residual bias and the ADEV minimum before and after.
pub fn compensation_section(page: &mut Page, exp: &Experiment, png: &PngDir) -> Result<(), ReportError> {
    let model = &exp.model;
    page.heading("Temperature compensation (fitted on cooling, evaluated on heating)");
    let mut comp_rows = Vec::new();
    for c in &exp.compensation {
        let (name, unit) = (&c.name, &c.unit);
        let points = |bins: &[BinMean]| -> Vec<(f64, f64)> { bins.iter().map(|b| (b.t, b.mean)).collect() };
        let (raw, compensated) = (points(&c.before), points(&c.after));
        let cm = model
            .channel(name)
            .ok_or_else(|| ReportError::Missing(format!("the model has no channel {name}")))?;
        // The same unit: its raw bias is p(T) itself.
        let curve = |t: f64| cm.bias(model, t.clamp(model.t_min_c, model.t_max_c));
        let title = format!("{name}: bias against temperature");
        figure(
            page,
            png,
            &format!("compensation_{name}"),
            &format!("{name}: 1 °C bin means of the heating run, raw and compensated, and the fitted p(T)"),
            |t| bias_plot(t, &title, unit, &raw, &compensated, &curve),
        )?;
        let (rb, ra) = (spread(&c.before).rms, spread(&c.after).rms);
        comp_rows.push(vec![
            name.clone(),
            format!("{}", cm.order),
            format!("{rb:.3e} {unit}"),
            format!("{ra:.3e} {unit}"),
            format!("{:.1} %", 100.0 * (1.0 - ra / rb)),
        ]);
    }
    page.table(
        "residual bias over temperature on the held-out heating run (RMS of 1 °C bin means)",
        &["channel", "order", "raw", "compensated", "reduction"].map(String::from),
        &comp_rows,
    );
    let mut adev_rows = Vec::new();
    for c in &exp.compensation {
        for ((t, b), (_, a)) in c.adev_before.iter().zip(&c.adev_after) {
            adev_rows.push(vec![
                c.name.clone(),
                format!("{t:.1}"),
                format!("{b:.3e} {}", c.unit),
                format!("{a:.3e} {}", c.unit),
            ]);
        }
    }
    page.table(
        "ADEV over temperature on the heating run, before and after compensation: σ_min per 10 °C bin",
        &["channel", "T [°C]", "raw", "compensated"].map(String::from),
        &adev_rows,
    );
    Ok(())
}

/// What the noise and the temperature cost in metres: the cooling run
/// navigated without aiding from many start points, raw and compensated,
/// measured beside the prediction from its noise terms; and the 60 s drift
/// for longer alignment windows.
pub fn navigation_section(page: &mut Page, exp: &Experiment, png: &PngDir) -> Result<(), ReportError> {
    let nav = &exp.navigation;
    let (raw, comp) = (&nav.raw, &nav.compensated);
    let (every, opts) = (nav.plan.every_s, &nav.plan.options);
    page.heading("Navigation without GNSS: the cooling run, raw and compensated");
    page.paragraph(&format!(
        "Strapdown navigation of the cooling run from a start point every {every} s ({} windows), each \
         levelled on its first {} s (heading 0: a MEMS gyro cannot gyrocompass; the gyro's mean over \
         the window taken as its bias) and navigated without aiding. The sensor is static, so every \
         metre is error. Predicted: the horizontal position DRMS (the 2-D rms) from the noise terms \
         identified on the compensated run (closed form per term, summed in quadrature; bias \
         instability bounded from its 1/f spectrum), for both runs: the temperature drift is in no \
         prediction, so on the raw run the measured error above the predicted is the temperature's. \
         Monte Carlo: the same terms simulated and navigated {} times (seed {}), its rms with a 95 % \
         interval.",
        raw.windows, opts.align_s, raw.monte_carlo_runs, raw.monte_carlo_seed
    ));
    let rows: Vec<Vec<String>> = raw
        .rows
        .iter()
        .zip(&comp.rows)
        .map(|(r, c)| {
            vec![
                format!("{}", r.measured.t_s),
                format!("{:.3}", r.measured.horizontal_position_m.rms),
                format!("{:.3}", r.measured.horizontal_position_m.p95),
                format!("{:.3}", c.measured.horizontal_position_m.rms),
                format!("{:.3}", c.measured.horizontal_position_m.p95),
                format!("{:.3}", c.predicted.total_m),
                monte_carlo_cell(c),
            ]
        })
        .collect();
    page.table(
        "horizontal position error against time since alignment, m (RMS and 95th percentile over the windows)",
        &[
            "t [s]",
            "raw RMS",
            "raw p95",
            "compensated RMS",
            "compensated p95",
            "predicted DRMS",
            "Monte Carlo rms (95 %)",
        ]
        .map(String::from),
        &rows,
    );
    let runs = [("raw", raw), ("compensated", comp)];
    figure(
        page,
        png,
        "navigation_cooling",
        "The cooling run's horizontal position error against time since alignment: measured (RMS over \
         the windows), predicted from the compensated run's terms, and the Monte Carlo's rms with its \
         95 % interval.",
        |t| navigation_plot(t, "Cooling run: horizontal position error", &runs),
    )?;
    let rows: Vec<Vec<String>> = nav
        .by_alignment
        .iter()
        .map(|(align_s, r, c)| {
            vec![
                format!("{align_s}"),
                format!("{r:.2}"),
                format!("{c:.2}"),
                format!("{:.2}", c / r),
            ]
        })
        .collect();
    page.table(
        "60 s without GNSS, by alignment window: horizontal position RMS, m",
        &["alignment [s]", "raw", "compensated", "compensated / raw"].map(String::from),
        &rows,
    );
    page.paragraph(&navigation_summary(raw, comp));
    Ok(())
}

/// The Monte Carlo's rms and its 95 % interval, for a table cell.
fn monte_carlo_cell(r: &Row) -> String {
    let [lo, hi] = r.monte_carlo_rms_95;
    format!("{:.3} ({lo:.3}–{hi:.3})", r.monte_carlo.rms)
}

/// One sentence on what the compensation buys at 60 s, and why not more.
fn navigation_summary(raw: &Navigated, comp: &Navigated) -> String {
    let at60 = |n: &Navigated| {
        n.rows
            .iter()
            .find(|r| r.measured.t_s == COMPARED_AT_S)
            .map(|r| (r.measured.horizontal_position_m.rms, r.predicted.total_m))
    };
    match (at60(raw), at60(comp)) {
        (Some((r, _)), Some((c, floor))) => {
            let head = format!(
                "60 s without GNSS: raw {r:.1} m, compensated {c:.1} m ({:.0} % of raw).",
                100.0 * c / r
            );
            // Within the Monte Carlo's and the windows' spread of the floor,
            // or above it: say which, from the figures.
            if c <= 1.2 * floor {
                format!(
                    "{head} The compensated run is at the floor its own noise terms predict ({floor:.1} m): \
                     what is left is white noise and bias instability, which no temperature model removes."
                )
            } else {
                format!(
                    "{head} The compensated run stays above the floor its noise terms predict ({floor:.1} m): \
                     the model leaves part of the temperature drift."
                )
            }
        }
        _ => String::new(),
    }
}

/// What each recording's noise costs in metres (`imutherm ins` with its
/// defaults), one table per recording; a recording that could not be
/// navigated says why instead.
pub fn recordings_navigation_section(
    page: &mut Page,
    plan: &Plan,
    navigated: &[(PathBuf, Result<Navigated, AnalysisError>)],
    png: &PngDir,
) -> Result<(), ReportError> {
    page.heading("Navigation without GNSS");
    page.paragraph(&format!(
        "Strapdown navigation of each static recording from a start point every {} s, each levelled on \
         its first {} s (heading 0: a MEMS gyro cannot gyrocompass) and navigated without aiding, so every \
         metre is error. Predicted: the horizontal position DRMS (2-D rms) from the recording's own noise \
         terms (closed form per term, summed in quadrature). A temperature drift is in no prediction, but \
         the terms identified on a run whose temperature changes absorb part of it: the measured error \
         above the predicted is then less than the temperature's share (`imutherm ins --model` predicts \
         from the compensated run). Monte Carlo: the same terms simulated and navigated {} times (seed \
         {}), its rms with a 95 % interval.",
        plan.every_s, plan.options.align_s, plan.monte_carlo_runs, plan.monte_carlo_seed
    ));
    for (f, navigated) in navigated {
        match navigated {
            Ok(n) => {
                let rows: Vec<Vec<String>> = n
                    .rows
                    .iter()
                    .map(|r| {
                        vec![
                            format!("{}", r.measured.t_s),
                            format!("{:.3}", r.measured.horizontal_position_m.rms),
                            format!("{:.3}", r.measured.horizontal_position_m.p50),
                            format!("{:.3}", r.measured.horizontal_position_m.p95),
                            format!("{:.3}", r.predicted.total_m),
                            monte_carlo_cell(r),
                        ]
                    })
                    .collect();
                page.table(
                    &format!(
                        "{}: horizontal position error against time since alignment, m ({} windows)",
                        f.display(),
                        n.windows
                    ),
                    &[
                        "t [s]",
                        "RMS",
                        "median",
                        "95th percentile",
                        "predicted DRMS",
                        "Monte Carlo rms (95 %)",
                    ]
                    .map(String::from),
                    &rows,
                );
                let runs = [("measured", n)];
                figure(
                    page,
                    png,
                    &format!("navigation_{}", f.display()),
                    &format!(
                        "{}: horizontal position error against time since alignment, measured, predicted \
                         and the Monte Carlo's rms with its 95 % interval",
                        f.display()
                    ),
                    |t| navigation_plot(t, "Horizontal position error", &runs),
                )?;
            }
            Err(e) => page.paragraph(&format!("{}: not navigated: {e}", f.display())),
        }
    }
    Ok(())
}
