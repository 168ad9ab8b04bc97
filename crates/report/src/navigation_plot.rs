//! The navigation error against time since alignment, on log-log axes:
//! for each navigated run, the measured rms over its windows, the closed
//! form's DRMS and the Monte Carlo's rms with its 95 % interval as a band.

use plotters::coord::Shift;
use plotters::prelude::*;

use analysis::navigation::Navigated;

use crate::PlotError;
use crate::plots::{Drawn, PALETTE, Target, err, font, log_range, tick_label, to_png, to_svg};

/// One navigated run and its legend name ("raw", "compensated").
pub type Run<'a> = (&'a str, &'a Navigated);

/// Horizontal position error against time for `runs`. A run whose
/// prediction and Monte Carlo are those of the run before (both rest on
/// the compensated run's terms) draws its measurement only.
pub fn navigation_plot(target: Target, title: &str, runs: &[Run]) -> Result<Drawn, PlotError> {
    let size = (720, 480);
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

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    runs: &[Run],
) -> Result<(), PlotError> {
    font();
    root.fill(&WHITE).map_err(err)?;
    let rows = || runs.iter().flat_map(|(_, n)| n.rows.iter());
    let ts = log_range(rows().map(|r| r.measured.t_s));
    let ms = log_range(rows().flat_map(|r| {
        [
            r.measured.horizontal_position_m.rms,
            r.predicted.total_m,
            r.monte_carlo_rms_95[0],
            r.monte_carlo_rms_95[1],
        ]
    }));
    let mut chart = ChartBuilder::on(root)
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
        .y_label_formatter(&|v| tick_label(*v, *v))
        .x_label_formatter(&|v| tick_label(*v, *v))
        .draw()
        .map_err(err)?;
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
            let shade = PALETTE[(i + 2) % PALETTE.len()];
            chart
                .draw_series(std::iter::once(Polygon::new(band, shade.mix(0.25))))
                .map_err(err)?
                .label(format!(
                    "Monte Carlo rms, 95 % ({} runs, seed {})",
                    n.monte_carlo_runs, n.monte_carlo_seed
                ))
                .legend(move |(x, y)| {
                    Rectangle::new([(x, y - 5), (x + 18, y + 5)], shade.mix(0.25).filled())
                });
            chart
                .draw_series(DashedLineSeries::new(
                    n.rows.iter().map(|r| (r.measured.t_s, r.predicted.total_m)),
                    6,
                    4,
                    shade.stroke_width(2),
                ))
                .map_err(err)?
                .label(format!("predicted DRMS ({} terms)", n.noise_from.describe()))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], shade.stroke_width(2)));
        }
        let measured = || {
            n.rows
                .iter()
                .map(|r| (r.measured.t_s, r.measured.horizontal_position_m.rms))
        };
        chart
            .draw_series(LineSeries::new(measured(), colour.stroke_width(2)))
            .map_err(err)?
            .label(format!("{name}: measured rms ({} windows)", n.windows))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2)));
        chart
            .draw_series(measured().map(|p| Circle::new(p, 3, colour.filled())))
            .map_err(err)?;
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 13))
        // The error grows with time: the upper left holds no data.
        .position(SeriesLabelPosition::UpperLeft)
        .draw()
        .map_err(err)?;
    Ok(())
}
