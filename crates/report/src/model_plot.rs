//! One axis's selected noise model drawn against its measured Allan
//! deviation: the curve with its intervals, the model's sum, each kept
//! process's own curve, each dropped term as its bound, and below it the
//! residuals (measured over model, with the same intervals), so that a
//! reader sees which process carries which stretch of τ and where the model
//! leaves the data.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use allan::Point;
use allan::noise_model::{NoiseModel, lm::power_basis, process};
use allan::noise_terms::{Term, TermEstimate};

use crate::PlotError;
use crate::html::significant;
use crate::plots::{
    Drawn, PALETTE, Target, err, font, log_range, log_tick_label, tick_label, to_png, to_svg,
};

/// What a reader needs beside the model to label it: the page's unit of
/// the deviation and of each term's value. The model stays in SI; `level`
/// carries its curves into the page's unit.
pub struct ModelAxis<'a> {
    /// Title of the figure.
    pub title: String,
    /// The unit the deviation is drawn in.
    pub unit: String,
    /// The factor from the model's SI deviation to `unit` (1 in SI).
    pub level: f64,
    /// The measured overlapping ADEV the model was fitted to, in `unit`.
    pub points: &'a [Point],
    /// The selected model, in SI.
    pub model: &'a NoiseModel,
    /// The factor from a term's SI value to the page's unit, and that unit
    /// (rad/√s for a gyro's N in SI, °/s/√Hz in the datasheets' units, …).
    pub term_unit: &'a dyn Fn(Term) -> (f64, String),
}

/// How one line of the figure is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Stroke {
    /// The model's sum.
    Model,
    /// A kept process of the model.
    Kept,
    /// A dropped term at its bound.
    Bound,
}

/// One line of the figure: its legend text and σ(τ) at the grid's τ.
#[derive(Debug, Clone)]
pub struct Line {
    /// Legend text, with the value and unit.
    pub label: String,
    /// How it is drawn.
    pub stroke: Stroke,
    /// σ at each τ of the grid.
    pub sigma: Vec<f64>,
}

/// Points of the τ grid the model's curves are drawn on.
const GRID: usize = 80;

/// The τ grid: log-spaced over the measured points' span.
pub fn grid(points: &[Point]) -> Vec<f64> {
    let (lo, hi) = points
        .iter()
        .map(|p| p.tau)
        .filter(|t| t.is_finite() && *t > 0.0)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), t| {
            (a.min(t), b.max(t))
        });
    if !lo.is_finite() {
        return Vec::new();
    }
    (0..GRID)
        .map(|j| lo * (hi / lo).powf(j as f64 / (GRID - 1) as f64))
        .collect()
}

fn interval(v: f64, lo: f64, hi: f64, unit: &str) -> String {
    format!("{v:.2e} [{lo:.2e}, {hi:.2e}] {unit}")
}

/// The model's lines on `taus`: its sum, each kept process (the five
/// IEEE 952 terms and each Gauss–Markov process apart), and each dropped
/// term that has a bound, at that bound.
pub fn lines(axis: &ModelAxis, taus: &[f64]) -> Vec<Line> {
    let m = axis.model;
    let mut out = Vec::new();
    if m.quality.is_some() {
        out.push(Line {
            label: format!(
                "model {} (χ²/dof {:.2}, p {:.2})",
                m.label,
                m.chi2_reduced.unwrap_or(f64::NAN),
                m.quality.map_or(f64::NAN, |q| q.p_value)
            ),
            stroke: Stroke::Model,
            sigma: taus.iter().map(|&t| axis.level * m.avar(t).sqrt()).collect(),
        });
    }
    for t in Term::ALL {
        let (f, unit) = (axis.term_unit)(t);
        match m.get(t) {
            TermEstimate::Value(v) => out.push(Line {
                label: format!(
                    "{} = {}",
                    t.symbol(),
                    interval(f * v.value, f * v.lo, f * v.hi, &unit)
                ),
                stroke: Stroke::Kept,
                sigma: taus
                    .iter()
                    .map(|&tau| axis.level * v.value * power_basis(t, tau).sqrt())
                    .collect(),
            }),
            TermEstimate::NotIdentifiable(_) => {
                if let Some(b) = m.bound(t) {
                    let why = match (m.quality.is_some(), m.fits) {
                        (_, true) => "dropped",
                        (true, false) => "the model does not fit",
                        (false, _) => "no model",
                    };
                    out.push(Line {
                        label: format!("{} ≤ {:.2e} {unit} ({why}: its bound)", t.symbol(), f * b),
                        stroke: Stroke::Bound,
                        sigma: taus
                            .iter()
                            .map(|&tau| axis.level * b * power_basis(t, tau).sqrt())
                            .collect(),
                    });
                }
            }
        }
    }
    let many = m.gauss_markov.len() > 1;
    for (k, g) in m.gauss_markov.iter().enumerate() {
        let name = if many { format!("GM{}", k + 1) } else { "GM".into() };
        let (s, tc) = (g.sigma, g.tau_c);
        let l = axis.level;
        out.push(Line {
            label: format!(
                "{name}: σ = {}\nT = {} [{}, {}] s",
                interval(l * s.value, l * s.lo, l * s.hi, &axis.unit),
                significant(tc.value),
                significant(tc.lo),
                significant(tc.hi)
            ),
            stroke: Stroke::Kept,
            sigma: taus
                .iter()
                .map(|&tau| l * s.value * process::gauss_markov(tau, tc.value).sqrt())
                .collect(),
        });
    }
    out
}

/// Measured over model at each point, with the point's interval likewise
/// divided: (τ, ratio, lo, hi); `level` carries the SI model into the
/// points' unit. Empty without a model.
pub fn residuals(points: &[Point], model: &NoiseModel, level: f64) -> Vec<(f64, f64, f64, f64)> {
    if model.quality.is_none() {
        return Vec::new();
    }
    points
        .iter()
        .filter_map(|p| {
            let s = level * model.avar(p.tau).sqrt();
            (s > 0.0 && s.is_finite() && p.dev > 0.0).then(|| (p.tau, p.dev / s, p.dev_lo / s, p.dev_hi / s))
        })
        .collect()
}

/// Canvas: the ADEV panel over the residual panel, the legend at the right.
const SIZE: (u32, u32) = (1000, 620);
const PLOT_WIDTH: u32 = 620;
const TOP_HEIGHT: u32 = 440;

/// The figure of one axis's noise model.
pub fn model_plot(target: Target, axis: &ModelAxis) -> Result<Drawn, PlotError> {
    match target {
        Target::Svg => to_svg(SIZE, |root| model_plot_on(root, axis)).map(Drawn::Svg),
        Target::Png(path) => to_png(path, SIZE, |root| model_plot_on(root, axis)).map(|()| Drawn::Png),
    }
}

/// The colour of the k-th kept process.
fn kept_colour(k: usize) -> RGBColor {
    // PALETTE[0] is the measured curve's, PALETTE[6] black the model's.
    PALETTE[1 + k % 5]
}

const BOUND_GREY: RGBColor = RGBColor(140, 140, 140);
const OUTSIDE_RED: RGBColor = RGBColor(200, 30, 30);

fn model_plot_on<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    axis: &ModelAxis,
) -> Result<(), PlotError> {
    font();
    root.fill(&WHITE).map_err(err)?;
    let (plots, legend) = root.split_horizontally(PLOT_WIDTH);
    let (top, bottom) = plots.split_vertically(TOP_HEIGHT);
    let pts = axis.points;
    if pts.is_empty() {
        return Err(PlotError(format!("{}: no ADEV points to plot", axis.title)));
    }
    let taus = grid(pts);
    let lines = lines(axis, &taus);
    let tau_range = log_range(pts.iter().map(|p| p.tau));
    // The axis spans the measurement and the model; the bounds' lines are
    // cut where they leave it rather than widening it by decades.
    let dev_range = log_range(
        pts.iter()
            .flat_map(|p| [p.dev_lo.max(p.dev * 1e-3), p.dev_hi])
            .chain(
                lines
                    .iter()
                    .filter(|l| l.stroke == Stroke::Model)
                    .flat_map(|l| l.sigma.clone()),
            ),
    );
    let mut chart = ChartBuilder::on(&top)
        .caption(&axis.title, ("sans-serif", 20))
        .margin(10)
        .x_label_area_size(30)
        .y_label_area_size(72)
        .build_cartesian_2d(
            (tau_range.0..tau_range.1).log_scale(),
            (dev_range.0..dev_range.1).log_scale(),
        )
        .map_err(err)?;
    chart
        .configure_mesh()
        .y_desc(format!("Allan deviation [{}]", axis.unit))
        .x_label_formatter(&|v| log_tick_label(*v, tau_range))
        .y_label_formatter(&|v| log_tick_label(*v, dev_range))
        .draw()
        .map_err(err)?;
    let blue = PALETTE[0];
    let band: Vec<(f64, f64)> = pts
        .iter()
        .map(|p| (p.tau, p.dev_hi.min(dev_range.1)))
        .chain(pts.iter().rev().map(|p| (p.tau, p.dev_lo.max(dev_range.0))))
        .collect();
    chart
        .draw_series(std::iter::once(Polygon::new(band, blue.mix(0.18))))
        .map_err(err)?;
    chart
        .draw_series(LineSeries::new(
            pts.iter().map(|p| (p.tau, p.dev)),
            blue.stroke_width(2),
        ))
        .map_err(err)?;
    chart
        .draw_series(pts.iter().map(|p| Circle::new((p.tau, p.dev), 3, blue.filled())))
        .map_err(err)?;
    let in_range = |v: f64| v >= dev_range.0 && v <= dev_range.1;
    let mut kept = 0;
    let mut legend_items = vec![(
        format!("measured, {:.0} % interval", 100.0 * axis.model.confidence),
        Mark::Band(blue),
    )];
    for l in &lines {
        let xy = || {
            taus.iter()
                .copied()
                .zip(l.sigma.iter().copied())
                .filter(|&(_, v)| in_range(v))
        };
        let mark = match l.stroke {
            Stroke::Model => {
                chart
                    .draw_series(LineSeries::new(xy(), BLACK.stroke_width(2)))
                    .map_err(err)?;
                Mark::Line(BLACK)
            }
            Stroke::Kept => {
                let c = kept_colour(kept);
                kept += 1;
                chart
                    .draw_series(DashedLineSeries::new(xy(), 8, 4, c.stroke_width(2)))
                    .map_err(err)?;
                Mark::Dashed(c)
            }
            Stroke::Bound => {
                chart
                    .draw_series(DashedLineSeries::new(xy(), 2, 4, BOUND_GREY.stroke_width(1)))
                    .map_err(err)?;
                Mark::Dotted(BOUND_GREY)
            }
        };
        legend_items.push((l.label.clone(), mark));
    }
    let res = residuals(pts, axis.model, axis.level);
    residual_panel(&bottom, &res, axis.model, tau_range)?;
    if !axis.model.outside.is_empty() {
        legend_items.push(("outside the measured interval".into(), Mark::Dot(OUTSIDE_RED)));
    }
    let mut notes = Vec::new();
    if axis.model.quality.is_none() {
        notes.push("no candidate model fits: no terms".to_string());
    } else if !axis.model.fits {
        notes.push("the model does not describe the curve (p < 0.01)".to_string());
    }
    for (name, d) in &axis.model.evidence {
        notes.push(format!("without {name}: {}", evidence(*d)));
    }
    legend_column(&legend, &legend_items, &notes)
}

/// Why a process was kept: how much worse the criterion is without it, or
/// that no admissible model goes without it.
pub fn evidence(d: f64) -> String {
    if d.is_finite() {
        format!("criterion +{d:.1}")
    } else {
        "no admissible model".to_string()
    }
}

/// The residual panel: measured over model with its interval, 1 marked,
/// points outside the interval in red.
fn residual_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    res: &[(f64, f64, f64, f64)],
    model: &NoiseModel,
    tau_range: (f64, f64),
) -> Result<(), PlotError> {
    // At least 0.5–1.5 so that a fitting model does not fill the panel with
    // its noise; wider where the intervals reach further, up to 0–10 (an
    // interval beyond is cut at the edge).
    let (lo, hi) = res
        .iter()
        .flat_map(|&(_, _, l, h)| [l, h])
        .filter(|v| v.is_finite())
        .fold((0.5f64, 1.5f64), |(a, b), v| (a.min(v), b.max(v)));
    let (lo, hi) = (lo.max(0.0), hi.min(10.0));
    let mut chart = ChartBuilder::on(area)
        .margin_left(10)
        .margin_right(10)
        .margin_bottom(6)
        .x_label_area_size(36)
        .y_label_area_size(72)
        .build_cartesian_2d((tau_range.0..tau_range.1).log_scale(), lo..hi)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("τ [s]")
        .y_desc("measured / model")
        .y_labels(6)
        .x_label_formatter(&|v| log_tick_label(*v, tau_range))
        .y_label_formatter(&|v| tick_label(*v, hi - lo))
        .draw()
        .map_err(err)?;
    chart
        .draw_series(LineSeries::new(
            [(tau_range.0, 1.0), (tau_range.1, 1.0)],
            BLACK.stroke_width(1),
        ))
        .map_err(err)?;
    if res.is_empty() {
        return Ok(());
    }
    let outside = |tau: f64| model.outside.iter().any(|&o| (o - tau).abs() <= 1e-9 * tau);
    let clamp = |v: f64| v.clamp(lo, hi);
    chart
        .draw_series(res.iter().map(|&(t, _, l, h)| {
            let c = if outside(t) { OUTSIDE_RED } else { PALETTE[0] };
            PathElement::new(vec![(t, clamp(l)), (t, clamp(h))], c.stroke_width(1))
        }))
        .map_err(err)?;
    chart
        .draw_series(res.iter().map(|&(t, r, _, _)| {
            let c = if outside(t) { OUTSIDE_RED } else { PALETTE[0] };
            Circle::new((t, clamp(r)), 3, c.filled())
        }))
        .map_err(err)?;
    Ok(())
}

/// How a legend entry shows its line.
enum Mark {
    Line(RGBColor),
    Dashed(RGBColor),
    Dotted(RGBColor),
    Dot(RGBColor),
    Band(RGBColor),
}

/// The legend as a column of its own at the right of the panels (a legend
/// inside log-log axes sits on a curve wherever it is put), then the notes
/// on why each process was kept.
fn legend_column<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    items: &[(String, Mark)],
    notes: &[String],
) -> Result<(), PlotError> {
    let style = ("sans-serif", 13)
        .into_font()
        .color(&BLACK)
        .pos(Pos::new(HPos::Left, VPos::Center));
    let (x, mut y) = (8, 46);
    let dash = |c: RGBColor, x: i32, y: i32, on: i32, off: i32| -> Vec<PathElement<(i32, i32)>> {
        let mut out = Vec::new();
        let mut a = x;
        while a < x + 22 {
            let b = (a + on).min(x + 22);
            out.push(PathElement::new(vec![(a, y), (b, y)], c.stroke_width(2)));
            a = b + off;
        }
        out
    };
    for (label, mark) in items {
        match mark {
            Mark::Line(c) => area
                .draw(&PathElement::new(vec![(x, y), (x + 22, y)], c.stroke_width(2)))
                .map_err(err)?,
            Mark::Dashed(c) => {
                for s in dash(*c, x, y, 8, 4) {
                    area.draw(&s).map_err(err)?;
                }
            }
            Mark::Dotted(c) => {
                for s in dash(*c, x, y, 2, 4) {
                    area.draw(&s).map_err(err)?;
                }
            }
            Mark::Dot(c) => area.draw(&Circle::new((x + 11, y), 3, c.filled())).map_err(err)?,
            Mark::Band(c) => area
                .draw(&Rectangle::new(
                    [(x, y - 5), (x + 22, y + 5)],
                    c.mix(0.4).filled(),
                ))
                .map_err(err)?,
        }
        // A long label goes on as indented lines under its first.
        for (k, text) in label.split('\n').enumerate() {
            if k > 0 {
                y += 18;
            }
            let indent = if k > 0 { 16 } else { 0 };
            area.draw(&Text::new(text.to_string(), (x + 30 + indent, y), style.clone()))
                .map_err(err)?;
        }
        y += 22;
    }
    y += 12;
    for n in notes {
        area.draw(&Text::new(n.clone(), (x, y), style.clone()))
            .map_err(err)?;
        y += 20;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use allan::noise_model::estimate;

    /// White noise N plus random walk K (σ² = N²/τ + K²τ/3, IEEE 952
    /// Annex C), at octave τ with the degrees of freedom of a long record:
    /// the model keeps N and K, and each kept line lies under the measured
    /// curve while their sum follows it.
    fn white_and_walk() -> Vec<Point> {
        let (n, k) = (1.5e-4f64, 2e-6f64);
        octave_points(16, 1_440_000, 1.4e6, |tau| {
            (n * n / tau + k * k * tau / 3.0).sqrt()
        })
    }

    /// The figure of `model` fitted to `pts`, in rad/s.
    fn rad_axis<'a>(
        title: &str,
        pts: &'a [Point],
        model: &'a NoiseModel,
        term_unit: &'a dyn Fn(Term) -> (f64, String),
    ) -> ModelAxis<'a> {
        ModelAxis {
            title: title.into(),
            unit: "rad/s".into(),
            level: 1.0,
            points: pts,
            model,
            term_unit,
        }
    }

    /// The lines of the figure of `model` at the τ of `pts`.
    fn lines_at_points(title: &str, pts: &[Point], model: &NoiseModel) -> Vec<Line> {
        let unit = |_: Term| (1.0, "u".to_string());
        let taus: Vec<f64> = pts.iter().map(|p| p.tau).collect();
        lines(&rad_axis(title, pts, model, &unit), &taus)
    }

    /// `count` octave τ from 10 ms with the deviation `dev(τ)`, `terms`
    /// terms each and `edf_tau / τ` degrees of freedom (at least 4), their
    /// interval ±2/√edf.
    fn octave_points(count: i32, terms: usize, edf_tau: f64, dev: impl Fn(f64) -> f64) -> Vec<Point> {
        (0..count)
            .map(|j| {
                let tau = 0.01 * 2f64.powi(j);
                let dev = dev(tau);
                let edf = (edf_tau / tau).max(4.0);
                let half = 2.0 / edf.sqrt();
                Point {
                    tau,
                    m: 1 << j,
                    dev,
                    n: terms,
                    edf,
                    dev_lo: dev * (1.0 - half),
                    dev_hi: dev * (1.0 + half),
                    alpha: 0,
                    noise_id: allan::NoiseIdMethod::Assumed,
                }
            })
            .collect()
    }

    #[test]
    fn each_kept_line_lies_under_the_curve_and_their_sum_follows_it() {
        let pts = white_and_walk();
        let model = estimate(&pts, 0.95);
        let ls = lines_at_points("gyro_x", &pts, &model);
        let sum = ls
            .iter()
            .find(|l| l.stroke == Stroke::Model)
            .expect("a model line");
        let kept: Vec<&Line> = ls.iter().filter(|l| l.stroke == Stroke::Kept).collect();
        assert!(kept.iter().any(|l| l.label.starts_with("N = ")), "{ls:?}");
        assert!(kept.iter().any(|l| l.label.starts_with("K = ")), "{ls:?}");
        for (i, p) in pts.iter().enumerate() {
            let total: f64 = kept.iter().map(|l| l.sigma[i].powi(2)).sum();
            assert!(
                (total.sqrt() / sum.sigma[i] - 1.0).abs() < 1e-9,
                "sum of the kept lines"
            );
            for l in &kept {
                assert!(
                    l.sigma[i] <= p.dev_hi,
                    "{} above the curve at τ = {}",
                    l.label,
                    p.tau
                );
            }
        }
        // B is not in these data: it can only be a bound, drawn as one.
        assert!(
            ls.iter()
                .any(|l| l.stroke == Stroke::Bound && l.label.starts_with("B ≤")),
            "{ls:?}"
        );
        for (_, r, lo, hi) in residuals(&pts, &model, 1.0) {
            assert!(
                lo <= 1.0 && 1.0 <= hi,
                "the exact curve's residual interval holds 1: {r}"
            );
        }
    }

    #[test]
    fn a_gauss_markov_term_is_drawn_apart_with_its_correlation_time() {
        // White noise N plus one Gauss–Markov process (σ, T = 100 s), its
        // exact Allan variance (process::gauss_markov), at octave τ.
        let (n, s, tc) = (1e-4f64, 3e-5f64, 100.0);
        let pts = octave_points(18, 2_000_000, 2e6, |tau| {
            (n * n / tau + s * s * process::gauss_markov(tau, tc)).sqrt()
        });
        let model = estimate(&pts, 0.95);
        assert_eq!(model.gauss_markov.len(), 1, "model {}", model.label);
        let ls = lines_at_points("gm", &pts, &model);
        let gm = ls
            .iter()
            .find(|l| l.label.starts_with("GM: σ = "))
            .expect("a GM line");
        assert_eq!(gm.stroke, Stroke::Kept);
        assert!(gm.label.contains("\nT = "), "{}", gm.label);
        let sum = ls.iter().find(|l| l.stroke == Stroke::Model).unwrap();
        for (i, p) in pts.iter().enumerate() {
            assert!(gm.sigma[i] <= p.dev_hi, "GM above the curve at τ = {}", p.tau);
            let kept: f64 = ls
                .iter()
                .filter(|l| l.stroke == Stroke::Kept)
                .map(|l| l.sigma[i].powi(2))
                .sum();
            assert!((kept.sqrt() / sum.sigma[i] - 1.0).abs() < 1e-9);
        }
        let unit = |_: Term| (1.0, "u".to_string());
        let svg = model_plot(Target::Svg, &rad_axis("gm", &pts, &model, &unit))
            .unwrap()
            .into_svg()
            .unwrap();
        assert!(svg.contains("T = "), "the correlation time is in the legend");
    }

    #[test]
    fn the_figure_names_every_line_and_the_residual_axis() {
        let pts = white_and_walk();
        let model = estimate(&pts, 0.95);
        let unit = |t: Term| (1.0, format!("unit-of-{}", t.symbol()));
        let axis = rad_axis("gyro_x at 34 °C", &pts, &model, &unit);
        let svg = model_plot(Target::Svg, &axis).unwrap().into_svg().unwrap();
        for text in [
            "gyro_x at 34 °C",
            "Allan deviation [rad/s]",
            "measured / model",
            "τ [s]",
            "unit-of-N",
            "unit-of-K",
            "(dropped: its bound)",
            "model N + K",
        ] {
            assert!(svg.contains(text), "the figure lacks {text:?}");
        }
    }

    #[test]
    fn a_model_that_does_not_fit_labels_its_bounds_so() {
        // Every other point 15 % high, each with 400 degrees of freedom
        // (σ known to 3.5 %): a zigzag no sum of the candidates follows,
        // under which the candidates' lines still fit.
        let pts: Vec<Point> = white_and_walk()
            .into_iter()
            .enumerate()
            .map(|(j, p)| {
                let dev = p.dev * if j % 2 == 1 { 1.15 } else { 1.0 };
                let half = 2.0 / 400f64.sqrt();
                Point {
                    dev,
                    edf: 400.0,
                    dev_lo: dev * (1.0 - half),
                    dev_hi: dev * (1.0 + half),
                    ..p
                }
            })
            .collect();
        let model = estimate(&pts, 0.95);
        let unit = |_: Term| (1.0, String::new());
        let axis = rad_axis("bump", &pts, &model, &unit);
        let ls = lines(&axis, &[1.0]);
        if model.quality.is_some() && !model.fits {
            assert!(ls.iter().all(|l| l.stroke != Stroke::Kept), "{ls:?}");
            assert!(
                ls.iter()
                    .filter(|l| l.stroke == Stroke::Bound)
                    .all(|l| l.label.ends_with("(the model does not fit: its bound)")),
                "{ls:?}"
            );
        } else {
            panic!(
                "expected a model that does not fit: {} (fits: {})",
                model.label, model.fits
            );
        }
    }

    #[test]
    fn a_curve_no_model_fits_is_said_and_drawn_without_lines() {
        let mut pts = white_and_walk();
        pts.truncate(1);
        let model = estimate(&pts, 0.95);
        let unit = |_: Term| (1.0, String::new());
        let axis = rad_axis("short", &pts, &model, &unit);
        assert!(residuals(&pts, &model, 1.0).is_empty());
        let svg = model_plot(Target::Svg, &axis).unwrap().into_svg().unwrap();
        assert!(svg.contains("no candidate model fits"), "{svg}");
    }

    /// On a page in other units the points come scaled and the axis says
    /// by how much: the model's lines follow the points by the same factor,
    /// the residuals stay ratios, and a term's label is in its own unit.
    #[test]
    fn a_page_unit_scales_the_lines_the_labels_and_not_the_residuals() {
        let pts = white_and_walk();
        let model = estimate(&pts, 0.95);
        let si_unit = |_: Term| (1.0, "rad/√s".to_string());
        let si = rad_axis("si", &pts, &model, &si_unit);
        let deg = 180.0 / std::f64::consts::PI;
        let scaled_pts = crate::page_units::scaled(&pts, deg);
        let deg_unit = |_: Term| (deg, "°/√s".to_string());
        let page = ModelAxis {
            unit: "°/s".into(),
            level: deg,
            ..rad_axis("deg", &scaled_pts, &model, &deg_unit)
        };
        let taus: Vec<f64> = pts.iter().map(|p| p.tau).collect();
        let (a, b) = (lines(&si, &taus), lines(&page, &taus));
        assert_eq!(a.len(), b.len());
        for (a, b) in a.iter().zip(&b) {
            for (x, y) in a.sigma.iter().zip(&b.sigma) {
                assert!((y / x - deg).abs() < 1e-9 * deg, "{} vs {}", a.label, b.label);
            }
        }
        let n = b.iter().find(|l| l.label.starts_with("N = ")).expect("N is kept");
        let value: f64 = n.label["N = ".len()..]
            .split(' ')
            .next()
            .unwrap()
            .parse()
            .unwrap();
        let si_value: f64 = a.iter().find(|l| l.label.starts_with("N = ")).unwrap().label["N = ".len()..]
            .split(' ')
            .next()
            .unwrap()
            .parse()
            .unwrap();
        assert!(
            (value / si_value / deg - 1.0).abs() < 0.01,
            "{} vs {}",
            n.label,
            si_value
        );
        assert!(n.label.ends_with("°/√s"), "{}", n.label);
        let (ra, rb) = (residuals(&pts, &model, 1.0), residuals(&scaled_pts, &model, deg));
        for (x, y) in ra.iter().zip(&rb) {
            assert!((x.1 - y.1).abs() < 1e-12 && (x.2 - y.2).abs() < 1e-12);
        }
    }
}
