//! The navigation error against time since alignment, on log-log axes:
//! for each navigated run, the measured rms over its windows, the closed
//! form's DRMS and the Monte Carlo's rms with its 95 % interval as a band.

use plotters::coord::Shift;
use plotters::prelude::*;

use analysis::navigation::Navigated;

use crate::PlotError;
use crate::plots::{Drawn, PALETTE, Target, err, font, log_range, log_tick_label, to_png, to_svg};

/// One navigated run and its legend name ("raw", "compensated").
pub type Run<'a> = (&'a str, &'a Navigated);

/// Horizontal position error against time for `runs`. A run whose
/// prediction and Monte Carlo are those of the run before (both rest on
/// the compensated run's terms) draws its measurement only.
pub fn navigation_plot(target: Target, title: &str, runs: &[Run]) -> Result<Drawn, PlotError> {
    // Taller than the other plots by its legend, drawn below the axes.
    let size = (720, 560);
    match target {
        Target::Svg => to_svg(size, |root| draw(root, title, runs)).map(Drawn::Svg),
        Target::Png(path) => to_png(path, size, |root| draw(root, title, runs)).map(|()| Drawn::Png),
    }
}

fn same_model(a: &Navigated, b: &Navigated) -> bool {
    a.noise == b.noise
        && a.rows.len() == b.rows.len()
        && a.rows
            .iter()
            .zip(&b.rows)
            .all(|(x, y)| x.monte_carlo == y.monte_carlo)
}

/// One legend entry: its text and how its sample is drawn.
enum Sample {
    Band(RGBAColor),
    Dashed(RGBColor),
    Line(RGBColor),
}

/// The x range: the data's own span (a sixteenth of a decade either side),
/// never rounded out to whole decades beyond the last time.
fn time_range(ts: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = ts
        .filter(|t| t.is_finite() && *t > 0.0)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), t| {
            (a.min(t), b.max(t))
        });
    if !lo.is_finite() {
        return (1.0, 10.0);
    }
    let pad = 10f64.powf(1.0 / 16.0);
    let (lo, hi) = (lo / pad, hi * pad);
    if hi > lo { (lo, hi) } else { (lo, lo * 10.0) }
}

const LEGEND_ROW_PX: u32 = 20;

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    runs: &[Run],
) -> Result<(), PlotError> {
    font();
    root.fill(&WHITE).map_err(err)?;
    let rows = || runs.iter().flat_map(|(_, n)| n.rows.iter());
    let ts = time_range(rows().map(|r| r.measured.t_s));
    let ms = log_range(rows().flat_map(|r| {
        [
            r.measured.horizontal_position_m.rms,
            r.predicted.total_m,
            r.monte_carlo_rms_95[0],
            r.monte_carlo_rms_95[1],
        ]
    }));
    // The legend goes under the plot, outside it: one row per entry.
    let entries = runs
        .iter()
        .enumerate()
        .map(|(i, (_, n))| {
            if i > 0 && same_model(runs[i - 1].1, n) {
                1
            } else {
                3
            }
        })
        .sum::<u32>();
    let h = root.dim_in_pixel().1;
    let legend_px = (entries * LEGEND_ROW_PX + 16).min(h / 2);
    let (plot, legend_area) = root.split_vertically(h - legend_px);
    let mut chart = ChartBuilder::on(&plot)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d((ts.0..ts.1).log_scale(), (ms.0..ms.1).log_scale())
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("time since alignment [s]")
        .y_desc("horizontal position error [m]")
        .y_label_formatter(&|v| log_tick_label(*v, ms))
        .x_label_formatter(&|v| log_tick_label(*v, ts))
        .draw()
        .map_err(err)?;
    let mut legend: Vec<(String, Sample)> = Vec::new();
    for (i, (name, n)) in runs.iter().enumerate() {
        let colour = PALETTE[i % PALETTE.len()];
        let model_drawn = i > 0 && same_model(runs[i - 1].1, n);
        if !model_drawn {
            let band: Vec<(f64, f64)> = n
                .rows
                .iter()
                .map(|r| (r.measured.t_s, r.monte_carlo_rms_95[1]))
                .chain(
                    n.rows
                        .iter()
                        .rev()
                        .map(|r| (r.measured.t_s, r.monte_carlo_rms_95[0].max(ms.0))),
                )
                .collect();
            // The Monte Carlo is a shaded band, the closed form a black
            // dashed line: two marks that cannot be taken for each other
            // or for a measurement.
            let shade = PALETTE[(i + 2) % PALETTE.len()].mix(0.3);
            chart
                .draw_series(std::iter::once(Polygon::new(band, shade)))
                .map_err(err)?;
            legend.push((
                format!(
                    "Monte Carlo rms, 95 % band ({} runs, seed {})",
                    n.monte_carlo_runs, n.monte_carlo_seed
                ),
                Sample::Band(shade),
            ));
            chart
                .draw_series(DashedLineSeries::new(
                    n.rows.iter().map(|r| (r.measured.t_s, r.predicted.total_m)),
                    8,
                    5,
                    BLACK.stroke_width(2),
                ))
                .map_err(err)?;
            legend.push((
                format!("predicted DRMS, closed form ({} terms)", n.noise_from.describe()),
                Sample::Dashed(BLACK),
            ));
        }
        let measured = || {
            n.rows
                .iter()
                .map(|r| (r.measured.t_s, r.measured.horizontal_position_m.rms))
        };
        chart
            .draw_series(LineSeries::new(measured(), colour.stroke_width(2)))
            .map_err(err)?;
        chart
            .draw_series(measured().map(|p| Circle::new(p, 3, colour.filled())))
            .map_err(err)?;
        legend.push((
            format!("{name}: measured rms ({} windows)", n.windows),
            Sample::Line(colour),
        ));
    }
    draw_legend(&legend_area, &legend)
}

/// The legend, one entry a row, in its own area under the plot.
fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    legend: &[(String, Sample)],
) -> Result<(), PlotError> {
    let x0 = 80;
    for (k, (text, sample)) in legend.iter().enumerate() {
        let y = 8 + k as i32 * LEGEND_ROW_PX as i32 + LEGEND_ROW_PX as i32 / 2;
        match sample {
            Sample::Band(c) => area
                .draw(&Rectangle::new([(x0, y - 6), (x0 + 28, y + 6)], c.filled()))
                .map_err(err)?,
            Sample::Dashed(c) => {
                for s in [0, 12, 24] {
                    area.draw(&PathElement::new(
                        vec![(x0 + s, y), (x0 + s + 7, y)],
                        c.stroke_width(2),
                    ))
                    .map_err(err)?;
                }
            }
            Sample::Line(c) => {
                area.draw(&PathElement::new(vec![(x0, y), (x0 + 28, y)], c.stroke_width(2)))
                    .map_err(err)?;
                area.draw(&Circle::new((x0 + 14, y), 3, c.filled()))
                    .map_err(err)?;
            }
        }
        area.draw(&Text::new(
            text.clone(),
            (x0 + 38, y - 7),
            ("sans-serif", 13).into_font().color(&BLACK),
        ))
        .map_err(err)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Data from 1 s to 120 s: the axis stops just past 120 s, not at the
    /// next decade (1000 s), and starts just before 1 s.
    #[test]
    fn the_time_axis_spans_the_data_not_the_decades() {
        let (lo, hi) = time_range([1.0, 10.0, 60.0, 120.0].into_iter());
        assert!(lo < 1.0 && lo > 0.8, "{lo}");
        assert!(hi > 120.0 && hi < 150.0, "{hi}");
        assert_eq!(time_range(std::iter::empty()), (1.0, 10.0));
    }
}
