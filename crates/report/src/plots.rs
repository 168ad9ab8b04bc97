//! The plots, as SVG text.

use std::sync::Once;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use allan::Point;
use thermal::surface::BinCurve;

use crate::PlotError;

static FONT: Once = Once::new();

/// Registers the embedded font once: SVG text needs metrics for layout.
pub(crate) fn font() {
    FONT.call_once(|| {
        // A failure leaves plotters' built-in fallback; the plot still draws.
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            include_bytes!("../assets/DejaVuSans.ttf"),
        );
    });
}

pub(crate) fn err<E: std::fmt::Debug>(e: E) -> PlotError {
    PlotError(format!("{e:?}"))
}

/// Colours that stay apart in print and for most colour vision.
pub(crate) const PALETTE: [RGBColor; 7] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
];

/// One curve of an ADEV plot.
pub struct Curve<'a> {
    /// Legend text.
    pub label: String,
    /// The points, by increasing τ.
    pub points: &'a [Point],
    /// Noise-term asymptotes to draw dashed beside the curve.
    pub asymptotes: Vec<Asymptote>,
    /// A point to mark, with its legend text (the ADEV minimum at its τ).
    pub marker: Option<(f64, f64, String)>,
    /// The curve's colour; `None` takes the next of the palette.
    pub colour: Option<[u8; 3]>,
}

impl<'a> Curve<'a> {
    /// A curve with no asymptotes and no marker.
    pub fn plain(label: impl Into<String>, points: &'a [Point]) -> Curve<'a> {
        Curve {
            label: label.into(),
            points,
            asymptotes: Vec::new(),
            marker: None,
            colour: None,
        }
    }
}

/// A colour for a temperature on a cold-to-hot scale (blue through purple
/// to red), `fraction` 0 for the coldest recording, 1 for the hottest.
pub fn temperature_colour(fraction: f64) -> [u8; 3] {
    let f = fraction.clamp(0.0, 1.0);
    let (a, b) = ([0.0, 90.0, 200.0], [215.0, 40.0, 30.0]);
    [0, 1, 2].map(|k| (a[k] + (b[k] - a[k]) * f).round() as u8)
}

/// A straight line on log-log axes, σ(τ) = σ1·τ^slope: how a single noise
/// term reads on an ADEV plot (IEEE 952 Annex C).
#[derive(Debug, Clone)]
pub struct Asymptote {
    /// Legend text, with the term's value and unit.
    pub label: String,
    /// σ at τ = 1 s.
    pub at_1s: f64,
    /// Slope on log-log axes.
    pub slope: f64,
}

pub(crate) fn log_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if !lo.is_finite() {
        return (1e-3, 1.0);
    }
    let (a, b) = (lo.log10().floor(), hi.log10().ceil());
    (10f64.powf(a), 10f64.powf(if b > a { b } else { a + 1.0 }))
}

/// Draws with `draw` on an SVG canvas of `size` pixels and returns the text.
pub(crate) fn to_svg(
    size: (u32, u32),
    draw: impl FnOnce(&DrawingArea<SVGBackend, Shift>) -> Result<(), PlotError>,
) -> Result<String, PlotError> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        draw(&root)?;
        root.present().map_err(err)?;
    }
    Ok(svg)
}

/// Draws with `draw` into a PNG file of `size` pixels.
pub(crate) fn to_png(
    path: &std::path::Path,
    size: (u32, u32),
    draw: impl FnOnce(&DrawingArea<BitMapBackend, Shift>) -> Result<(), PlotError>,
) -> Result<(), PlotError> {
    // Drawn in memory and written through imutherm's own output files
    // (`imu::output`): a scratch file of the run's own, renamed onto the
    // path once complete, so a failed or interrupted plot never leaves a
    // broken PNG under the name of the previous one, and no file or link
    // already beside it is ever opened.
    let mut pixels = vec![0u8; size.0 as usize * size.1 as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut pixels, size).into_drawing_area();
        draw(&root)?;
        root.present().map_err(err)?;
    }
    let mut png = Vec::new();
    image::ImageEncoder::write_image(
        image::codecs::png::PngEncoder::new(&mut png),
        &pixels,
        size.0,
        size.1,
        image::ColorType::Rgb8,
    )
    .map_err(|e| PlotError(format!("encoding {}: {e}", path.display())))?;
    // The figures are the report's own files: replaced on every run.
    let policy = imu::output::OutputPolicy {
        overwrite: true,
        inputs: &[],
    };
    imu::output::write_file(path, &png, &policy).map_err(|e| {
        // The error and its causes on one line: the system's reason too.
        let mut text = e.to_string();
        let mut cause = std::error::Error::source(&e);
        while let Some(c) = cause {
            text = format!("{text}: {c}");
            cause = c.source();
        }
        PlotError(text)
    })
}

/// Where a plot is drawn.
#[derive(Debug, Clone, Copy)]
pub enum Target<'a> {
    /// SVG text, returned to be put in a page.
    Svg,
    /// A PNG file, written beside and renamed onto the path once complete.
    Png(&'a std::path::Path),
}

/// A plot drawn: its SVG text, or the PNG file written.
#[derive(Debug, Clone, PartialEq)]
pub enum Drawn {
    /// The SVG text.
    Svg(String),
    /// The PNG file was written.
    Png,
}

impl Drawn {
    /// The SVG text, for a plot drawn to [`Target::Svg`].
    pub fn into_svg(self) -> Option<String> {
        match self {
            Drawn::Svg(s) => Some(s),
            Drawn::Png => None,
        }
    }
}

/// Draws one plot, by the same function for both targets, on a canvas of
/// `size` pixels.
macro_rules! draw {
    ($target:expr, $size:expr, |$root:ident| $body:expr) => {
        match $target {
            Target::Svg => to_svg($size, |$root| $body).map(Drawn::Svg),
            Target::Png(path) => to_png(path, $size, |$root| $body).map(|()| Drawn::Png),
        }
    };
}

/// Allan deviation curves on log-log axes, each with its confidence band.
pub fn adev_plot(target: Target, title: &str, unit: &str, curves: &[Curve]) -> Result<Drawn, PlotError> {
    draw!(target, (720, 480), |root| adev_plot_on(root, title, unit, curves))
}

fn adev_plot_on<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    unit: &str,
    curves: &[Curve],
) -> Result<(), PlotError> {
    font();
    root.fill(&WHITE).map_err(err)?;
    let taus = log_range(curves.iter().flat_map(|c| c.points.iter().map(|p| p.tau)));
    let devs = log_range(curves.iter().flat_map(|c| {
        c.points
            .iter()
            .flat_map(|p| [p.dev_lo.max(p.dev * 1e-3), p.dev_hi])
    }));
    let mut chart = ChartBuilder::on(root)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d((taus.0..taus.1).log_scale(), (devs.0..devs.1).log_scale())
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("τ [s]")
        .y_desc(format!("Allan deviation [{unit}]"))
        .y_label_formatter(&|v| log_tick_label(*v, devs))
        .x_label_formatter(&|v| log_tick_label(*v, taus))
        .draw()
        .map_err(err)?;
    for (i, c) in curves.iter().enumerate() {
        let colour = c
            .colour
            .map_or(PALETTE[i % PALETTE.len()], |[r, g, b]| RGBColor(r, g, b));
        let band: Vec<(f64, f64)> = c
            .points
            .iter()
            .map(|p| (p.tau, p.dev_hi))
            .chain(c.points.iter().rev().map(|p| (p.tau, p.dev_lo.max(devs.0))))
            .collect();
        chart
            .draw_series(std::iter::once(Polygon::new(band, colour.mix(0.18))))
            .map_err(err)?;
        chart
            .draw_series(LineSeries::new(
                c.points.iter().map(|p| (p.tau, p.dev)),
                colour.stroke_width(2),
            ))
            .map_err(err)?
            .label(c.label.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2)));
        chart
            .draw_series(
                c.points
                    .iter()
                    .map(|p| Circle::new((p.tau, p.dev), 3, colour.filled())),
            )
            .map_err(err)?;
        for (k, a) in c.asymptotes.iter().enumerate() {
            let shade = PALETTE[(4 + k) % PALETTE.len()];
            let line = |tau: f64| a.at_1s * tau.powf(a.slope);
            let pts: Vec<(f64, f64)> = (0..=40)
                .map(|j| {
                    let tau = taus.0 * (taus.1 / taus.0).powf(j as f64 / 40.0);
                    (tau, line(tau))
                })
                .filter(|&(_, v)| v >= devs.0 && v <= devs.1)
                .collect();
            chart
                .draw_series(DashedLineSeries::new(pts, 6, 4, shade.stroke_width(1)))
                .map_err(err)?
                .label(a.label.clone())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], shade.stroke_width(1)));
        }
        if let Some((tau, dev, label)) = &c.marker {
            chart
                .draw_series(std::iter::once(TriangleMarker::new(
                    (*tau, *dev),
                    7,
                    BLACK.filled(),
                )))
                .map_err(err)?
                .label(label.clone())
                .legend(|(x, y)| TriangleMarker::new((x + 9, y), 5, BLACK.filled()));
        }
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        // σ is largest at short τ (white noise falls as τ^-1/2), so the lower
        // left of a log-log ADEV plot holds no data.
        .position(SeriesLabelPosition::LowerLeft)
        .draw()
        .map_err(err)?;
    Ok(())
}

/// A tick label on a log axis over `range`: one format for the whole axis,
/// exponents on every tick where any tick needs one (`1e-4`, `1e-3`, not
/// `1e-4`, `0.001`), plain numbers otherwise.
pub fn log_tick_label(v: f64, (lo, hi): (f64, f64)) -> String {
    if !v.is_finite() || v <= 0.0 {
        return String::new();
    }
    if lo >= 1e-3 && hi < 1e5 {
        return tick_label(v, v);
    }
    let s = format!("{v:.6e}");
    match s.split_once('e') {
        Some((m, e)) => format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.')),
        None => s,
    }
}

/// A tick label on an axis spanning `span` (on a log axis, the tick itself):
/// as many decimals as ten ticks over the span need and no more, so no
/// float noise (`6.939e-18` where 0 is meant, `1000.0`); exponents below
/// 0.001 and from 100 000 on.
pub fn tick_label(v: f64, span: f64) -> String {
    if !v.is_finite() {
        return String::new();
    }
    let span = if span.is_finite() && span != 0.0 {
        span.abs()
    } else {
        v.abs()
    };
    if v == 0.0 || v.abs() < span * 1e-9 {
        return "0".to_string();
    }
    let (a, step) = (v.abs(), span / 10.0);
    if !(1e-3..1e5).contains(&a) {
        let digits = ((a / step).log10().ceil().max(0.0) as usize)
            .saturating_sub(1)
            .min(6);
        let s = format!("{v:.digits$e}");
        return match s.split_once('e') {
            Some((m, e)) if m.contains('.') => {
                format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.'))
            }
            _ => s,
        };
    }
    let decimals = (-step.log10().floor()).clamp(0.0, 9.0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// Blue (low) to yellow (high), through green: readable in grey too.
fn heat(v: f64) -> RGBColor {
    let stops = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (253.0, 231.0, 37.0),
    ];
    let x = v.clamp(0.0, 1.0) * (stops.len() - 1) as f64;
    let i = (x.floor() as usize).min(stops.len() - 2);
    let f = x - i as f64;
    let (a, b) = (stops[i], stops[i + 1]);
    let mix = |p: f64, q: f64| (p + (q - p) * f).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// The ADEV over temperature as a heat map: τ (log) across, the
/// temperature bins' mean temperature up, σ as a log colour scale; from
/// the bins' curves alone, without the noise models of a surface's rows.
pub fn adev_heatmap_bins(
    target: Target,
    title: &str,
    unit: &str,
    rows: &[BinCurve],
) -> Result<Drawn, PlotError> {
    let slices: Vec<(f64, &[Point])> = rows.iter().map(|r| (r.t_mean_c, r.points.as_slice())).collect();
    adev_heatmap_slices(target, title, unit, &slices)
}

/// [`adev_heatmap_bins`] of any slices, (mean temperature °C, OADEV points)
/// each: the dynamic ADEV's windows as well as temperature bins. Each
/// slice fills the band halfway to its neighbours in temperature.
pub fn adev_heatmap_slices(
    target: Target,
    title: &str,
    unit: &str,
    slices: &[(f64, &[Point])],
) -> Result<Drawn, PlotError> {
    let mut rows: Vec<(f64, &[Point])> = slices.iter().copied().filter(|s| s.0.is_finite()).collect();
    rows.sort_by(|a, b| a.0.total_cmp(&b.0));
    draw!(target, (720, 480), |root| adev_heatmap_on(
        root, title, unit, &rows
    ))
}

/// Colour levels of a heat map and of its colour bar.
const LEVELS: usize = 64;

fn adev_heatmap_on<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    unit: &str,
    rows: &[(f64, &[Point])],
) -> Result<(), PlotError> {
    font();
    root.fill(&WHITE).map_err(err)?;
    let (main, bar) = root.split_horizontally(640);
    let taus = log_range(rows.iter().flat_map(|r| r.1.iter().map(|p| p.tau)));
    let (tmin, tmax) = match (rows.first(), rows.last()) {
        (Some(a), Some(b)) if b.0 > a.0 => (a.0, b.0),
        (Some(a), _) => (a.0 - 1.0, a.0 + 1.0),
        _ => (0.0, 1.0),
    };
    // The band of slice k: halfway to each neighbour; the outer halves as
    // wide as the inner ones.
    let edge = |k: usize| -> (f64, f64) {
        let t = rows[k].0;
        let below = if k > 0 {
            (t - rows[k - 1].0) / 2.0
        } else {
            f64::NAN
        };
        let above = rows.get(k + 1).map_or(f64::NAN, |r| (r.0 - t) / 2.0);
        let (below, above) = match (below.is_finite(), above.is_finite()) {
            (true, true) => (below, above),
            (true, false) => (below, below),
            (false, true) => (above, above),
            (false, false) => (1.0, 1.0),
        };
        (t - below, t + above)
    };
    let (lo_t, hi_t) = if rows.is_empty() {
        (tmin, tmax)
    } else {
        (edge(0).0, edge(rows.len() - 1).1)
    };
    let step = (hi_t - lo_t).max(f64::MIN_POSITIVE);
    let devs: Vec<f64> = rows
        .iter()
        .flat_map(|r| r.1.iter().map(|p| p.dev.log10()))
        .collect();
    let (dlo, dhi) = devs
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let span = if dhi > dlo { dhi - dlo } else { 1.0 };
    let mut chart = ChartBuilder::on(&main)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d((taus.0..taus.1).log_scale(), lo_t..hi_t)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("τ [s]")
        .y_desc("temperature [°C]")
        .x_label_formatter(&|v| log_tick_label(*v, taus))
        .y_label_formatter(&|v| tick_label(*v, step))
        .draw()
        .map_err(err)?;
    // One cell per slice and τ, in the colour bar's 64 levels; a column of
    // cells of one level in adjacent slices is drawn as one rectangle, which
    // keeps the SVG of a dense dynamic ADEV (a hundred windows) small.
    let level =
        |dev: f64| (((dev.log10() - dlo) / span * LEVELS as f64).floor() as i64).clamp(0, LEVELS as i64 - 1);
    let mut open: std::collections::BTreeMap<u64, (i64, f64, f64, f64, f64)> = Default::default();
    let mut cells: Vec<(i64, f64, f64, f64, f64)> = Vec::new();
    for (i, &(_, points)) in rows.iter().enumerate() {
        let (below, above) = edge(i);
        let mut seen = std::collections::BTreeSet::new();
        for (k, p) in points.iter().enumerate() {
            let left = if k == 0 {
                p.tau / 2f64.sqrt()
            } else {
                (p.tau * points[k - 1].tau).sqrt()
            };
            let right = match points.get(k + 1) {
                Some(q) => (p.tau * q.tau).sqrt(),
                None => p.tau * 2f64.sqrt(),
            };
            let key = p.tau.to_bits();
            seen.insert(key);
            let l = level(p.dev);
            match open.get_mut(&key) {
                Some(c) if c.0 == l && c.1 == left && c.2 == right && c.4 == below => c.4 = above,
                _ => {
                    if let Some(c) = open.insert(key, (l, left, right, below, above)) {
                        cells.push(c);
                    }
                }
            }
        }
        // A τ this slice lacks ends the column's run.
        let ended: Vec<u64> = open.keys().filter(|k| !seen.contains(k)).copied().collect();
        for k in ended {
            cells.extend(open.remove(&k));
        }
    }
    cells.extend(open.into_values());
    chart
        .draw_series(cells.iter().map(|&(l, left, right, below, above)| {
            Rectangle::new(
                [(left, below), (right, above)],
                heat((l as f64 + 0.5) / LEVELS as f64).filled(),
            )
        }))
        .map_err(err)?;
    // The colour bar, with its scale in the plotted unit.
    let mut cb = ChartBuilder::on(&bar)
        .margin_top(44)
        .margin_bottom(52)
        .y_label_area_size(0)
        .right_y_label_area_size(70)
        .build_cartesian_2d(0.0..1.0, (10f64.powf(dlo)..10f64.powf(dlo + span)).log_scale())
        .map_err(err)?;
    cb.configure_mesh()
        .disable_x_mesh()
        .disable_x_axis()
        .y_desc(format!("σ [{unit}]"))
        // The bar's area is narrow: left to themselves, its texts would
        // be sized to it, under a pixel.
        .y_label_style(("sans-serif", 12))
        .axis_desc_style(("sans-serif", 13))
        .y_label_formatter(&|v| log_tick_label(*v, (10f64.powf(dlo), 10f64.powf(dlo + span))))
        .draw()
        .map_err(err)?;
    let n = LEVELS;
    cb.draw_series((0..n).map(|i| {
        let (a, b) = (i as f64 / n as f64, (i + 1) as f64 / n as f64);
        Rectangle::new(
            [
                (0.0, 10f64.powf(dlo + a * span)),
                (1.0, 10f64.powf(dlo + b * span)),
            ],
            heat((a + b) / 2.0).filled(),
        )
    }))
    .map_err(err)?;
    Ok(())
}

/// Bias against temperature (bin means, before and after compensation) and
/// the fitted curve.
pub fn bias_plot(
    target: Target,
    title: &str,
    unit: &str,
    before: &[(f64, f64)],
    after: &[(f64, f64)],
    model: &dyn Fn(f64) -> f64,
) -> Result<Drawn, PlotError> {
    draw!(target, (720, 420 + LEGEND_STRIP), |root| bias_plot_on(
        root, title, unit, before, after, model
    ))
}

fn bias_plot_on<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    unit: &str,
    before: &[(f64, f64)],
    after: &[(f64, f64)],
    model: &dyn Fn(f64) -> f64,
) -> Result<(), PlotError> {
    font();
    root.fill(&WHITE).map_err(err)?;
    let (root, strip) = root.split_vertically(420);
    let root = &root;
    let all = before.iter().chain(after);
    let (tlo, thi, ylo, yhi) = all.fold(
        (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY),
        |(a, b, c, d), &(t, y)| (a.min(t), b.max(t), c.min(y), d.max(y)),
    );
    if !tlo.is_finite() {
        return Err(PlotError("no bins to plot".into()));
    }
    let pad = 0.05 * (yhi - ylo).max(1e-12);
    let y_span = yhi - ylo + 2.0 * pad;
    let mut chart = ChartBuilder::on(root)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(80)
        .build_cartesian_2d(tlo..thi.max(tlo + 1.0), (ylo - pad)..(yhi + pad))
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("temperature [°C]")
        .y_desc(format!("bias [{unit}]"))
        .x_label_formatter(&|v| tick_label(*v, thi - tlo))
        .y_label_formatter(&|v| tick_label(*v, y_span))
        .draw()
        .map_err(err)?;
    let (c0, c1, c2) = (PALETTE[0], PALETTE[1], PALETTE[2]);
    chart
        .draw_series(before.iter().map(|&(t, y)| Circle::new((t, y), 3, c0.filled())))
        .map_err(err)?;
    let steps = 200;
    chart
        .draw_series(LineSeries::new(
            (0..=steps).map(|i| {
                let t = tlo + (thi - tlo) * i as f64 / steps as f64;
                (t, model(t))
            }),
            c1.stroke_width(2),
        ))
        .map_err(err)?;
    chart
        .draw_series(after.iter().map(|&(t, y)| Circle::new((t, y), 3, c2.filled())))
        .map_err(err)?;
    legend_strip(
        &strip,
        &[
            ("bin means, raw".into(), Mark::Dot(c0)),
            ("fitted bias p(T)".into(), Mark::Line(c1)),
            ("bin means, compensated".into(), Mark::Dot(c2)),
        ],
    )
}

/// Pixels below a plot for its legend.
const LEGEND_STRIP: u32 = 30;

/// How a legend entry shows its trace.
enum Mark {
    /// A line.
    Line(RGBColor),
    /// A point.
    Dot(RGBColor),
    /// A filled band.
    Band(RGBColor),
}

/// The legend in a strip of its own below the plot, one row left to right,
/// so that it never hides data (a legend inside the axes sits on the
/// curves wherever they run).
fn legend_strip<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    items: &[(String, Mark)],
) -> Result<(), PlotError> {
    let style = ("sans-serif", 14)
        .into_font()
        .color(&BLACK)
        .pos(Pos::new(HPos::Left, VPos::Center));
    let y = (area.dim_in_pixel().1 / 2) as i32;
    // Lined up with the plot's left edge (its y label area).
    let mut x = 92;
    for (label, mark) in items {
        match mark {
            Mark::Line(c) => area.draw(&PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(2))),
            Mark::Dot(c) => area.draw(&Circle::new((x + 9, y), 3, c.filled())),
            Mark::Band(c) => area.draw(&Rectangle::new(
                [(x, y - 4), (x + 18, y + 4)],
                c.mix(0.5).filled(),
            )),
        }
        .map_err(err)?;
        area.draw(&Text::new(label.clone(), (x + 24, y), style.clone()))
            .map_err(err)?;
        let (w, _) = area.estimate_text_size(label, &style).map_err(err)?;
        x += 24 + w as i32 + 20;
    }
    Ok(())
}

/// Columns a time plot is decimated to: one min/max pair per pixel column
/// keeps every excursion visible and draws 10^7 samples as fast as 10^3.
pub const TIME_COLUMNS: usize = 1000;

/// (time, min, max) of each of at most [`TIME_COLUMNS`] equal slices of `x`.
pub fn envelope(x: &[f64], rate_hz: f64) -> Vec<(f64, f64, f64)> {
    envelope_with_mean(x, rate_hz)
        .into_iter()
        .map(|(t, lo, _, hi)| (t, lo, hi))
        .collect()
}

/// (time, min, mean, max) of each of at most [`TIME_COLUMNS`] equal slices
/// of `x`, over its finite samples; a slice with none is left out.
pub fn envelope_with_mean(x: &[f64], rate_hz: f64) -> Vec<(f64, f64, f64, f64)> {
    if x.is_empty() {
        return Vec::new();
    }
    let per = x.len().div_ceil(TIME_COLUMNS).max(1);
    x.chunks(per)
        .enumerate()
        .filter_map(|(i, c)| {
            let (lo, hi, sum, n) = c.iter().filter(|v| v.is_finite()).fold(
                (f64::INFINITY, f64::NEG_INFINITY, 0.0, 0usize),
                |(a, b, s, n), &v| (a.min(v), b.max(v), s + v, n + 1),
            );
            (n > 0).then(|| ((i * per) as f64 / rate_hz, lo, sum / n as f64, hi))
        })
        .collect()
}

/// Samples against time (min/max envelope per pixel column), with the
/// temperature below when given.
pub fn time_plot(
    target: Target,
    title: &str,
    unit: &str,
    channels: &[(String, &[f64])],
    rate_hz: f64,
    temperature: Option<&[f64]>,
) -> Result<Drawn, PlotError> {
    draw!(target, (720, 520 + LEGEND_STRIP), |root| time_plot_on(
        root,
        title,
        unit,
        channels,
        rate_hz,
        temperature
    ))
}

fn time_plot_on<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    unit: &str,
    channels: &[(String, &[f64])],
    rate_hz: f64,
    temperature: Option<&[f64]>,
) -> Result<(), PlotError> {
    font();
    root.fill(&WHITE).map_err(err)?;
    let (root, strip) = root.split_vertically(520);
    let root = &root;
    let (top, bottom) = if temperature.is_some() {
        root.split_vertically(340)
    } else {
        root.split_vertically(520)
    };
    let envs: Vec<Vec<(f64, f64, f64)>> = channels.iter().map(|(_, x)| envelope(x, rate_hz)).collect();
    let t_end = channels.iter().map(|(_, x)| x.len()).max().unwrap_or(1) as f64 / rate_hz;
    let (lo, hi) = envs
        .iter()
        .flatten()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), e| {
            (a.min(e.1), b.max(e.2))
        });
    if !lo.is_finite() {
        return Err(PlotError("nothing to plot".into()));
    }
    let pad = 0.05 * (hi - lo).max(1e-12);
    let y_span = hi - lo + 2.0 * pad;
    let mut chart = ChartBuilder::on(&top)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(30)
        .y_label_area_size(80)
        .build_cartesian_2d(0.0..t_end.max(1e-9), (lo - pad)..(hi + pad))
        .map_err(err)?;
    chart
        .configure_mesh()
        .y_desc(format!("[{unit}]"))
        .x_label_formatter(&|v| tick_label(*v, t_end))
        .y_label_formatter(&|v| tick_label(*v, y_span))
        .draw()
        .map_err(err)?;
    for (i, env) in envs.iter().enumerate() {
        let colour = PALETTE[i % PALETTE.len()];
        let band: Vec<(f64, f64)> = env
            .iter()
            .map(|e| (e.0, e.2))
            .chain(env.iter().rev().map(|e| (e.0, e.1)))
            .collect();
        chart
            .draw_series(std::iter::once(Polygon::new(band, colour.mix(0.5))))
            .map_err(err)?;
    }
    let mut items: Vec<(String, Mark)> = channels
        .iter()
        .enumerate()
        .map(|(i, (name, _))| (name.clone(), Mark::Band(PALETTE[i % PALETTE.len()])))
        .collect();
    if temperature.is_some() {
        items.push(("temperature".into(), Mark::Line(RED)));
    }
    legend_strip(&strip, &items)?;
    if let Some(temp) = temperature {
        let env = envelope(temp, rate_hz);
        let (tlo, thi) = env.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), e| {
            (a.min(e.1), b.max(e.2))
        });
        let tpad = 0.05 * (thi - tlo).max(0.1);
        let mut tc = ChartBuilder::on(&bottom)
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(80)
            .build_cartesian_2d(0.0..t_end.max(1e-9), (tlo - tpad)..(thi + tpad))
            .map_err(err)?;
        let t_span = thi - tlo + 2.0 * tpad;
        tc.configure_mesh()
            .x_desc("time [s]")
            .y_desc("temperature [°C]")
            .x_label_formatter(&|v| tick_label(*v, t_end))
            .y_label_formatter(&|v| tick_label(*v, t_span))
            .draw()
            .map_err(err)?;
        tc.draw_series(LineSeries::new(
            env.iter().map(|e| (e.0, 0.5 * (e.1 + e.2))),
            RED.stroke_width(2),
        ))
        .map_err(err)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The y of the text element holding `label` in `svg`.
    fn text_y(svg: &str, label: &str) -> f64 {
        let end = svg
            .find(&format!(">{label}</text>"))
            .or_else(|| svg.find(&format!(">\n{label}\n</text>")))
            .unwrap_or_else(|| panic!("no {label} in {}", &svg[svg.len().saturating_sub(1500)..]));
        let tag = &svg[svg[..end].rfind("<text").expect("text element")..end];
        let y = tag.split(" y=\"").nth(1).and_then(|v| v.split('"').next());
        y.and_then(|v| v.parse().ok()).expect("y attribute")
    }

    #[test]
    fn legends_sit_below_the_axes_not_on_the_data() {
        let pts = [(20.0, 1.0), (40.0, 2.0), (60.0, 3.0)];
        let svg = bias_plot(Target::Svg, "b", "g", &pts, &pts, &|t| t / 20.0)
            .unwrap()
            .into_svg()
            .unwrap();
        // The plot takes the top 420 px; the legend the strip below.
        for label in ["bin means, raw", "fitted bias p(T)", "bin means, compensated"] {
            assert!(text_y(&svg, label) > 420.0, "{label} is inside the plot");
        }
        let x: Vec<f64> = (0..500).map(|i| (i % 5) as f64).collect();
        let svg = time_plot(Target::Svg, "t", "g", &[("ax".into(), &x)], 10.0, Some(&x))
            .unwrap()
            .into_svg()
            .unwrap();
        for label in ["ax", "temperature"] {
            assert!(text_y(&svg, label) > 520.0, "{label} is inside the plot");
        }
    }

    #[test]
    fn ticks_carry_no_float_noise() {
        // Linear axes: the span decides the decimals.
        assert_eq!(tick_label(6.938893903907228e-18, 0.02), "0");
        assert_eq!(tick_label(0.1 + 0.2, 1.0), "0.3");
        assert_eq!(tick_label(0.004, 0.02), "0.004");
        assert_eq!(tick_label(-0.15, 0.5), "-0.15");
        assert_eq!(tick_label(1200.0, 3600.0), "1200");
        assert_eq!(tick_label(120_000.0, 100_000.0), "1.2e5");
        // Log axes: the tick is its own span.
        assert_eq!(tick_label(1000.0, 1000.0), "1000");
        assert_eq!(tick_label(0.1, 0.1), "0.1");
        assert_eq!(tick_label(1e-5, 1e-5), "1e-5");
        assert_eq!(tick_label(f64::NAN, 1.0), "");
        // A log axis from 1e-4 to 1: one format on every tick.
        let axis = (1e-4, 1.0);
        let labels: Vec<String> = [1e-4, 1e-3, 1e-2, 0.1, 1.0, 2e-3]
            .map(|v| log_tick_label(v, axis))
            .to_vec();
        assert_eq!(labels, ["1e-4", "1e-3", "1e-2", "1e-1", "1e0", "2e-3"]);
        // Within 0.001 … 100 000, plain numbers.
        assert_eq!(log_tick_label(0.001, (1e-3, 1e3)), "0.001");
        assert_eq!(log_tick_label(1000.0, (1e-3, 1e3)), "1000");
        assert_eq!(log_tick_label(0.0, axis), "");
    }
}
