//! Interactive charts: the data of an ADEV or time plot as JSON, which the
//! page's script (`assets/charts.js`) draws with the vendored uPlot
//! (`vendor/uplot/`, embedded once per page) in place of the static SVG.

use serde::Serialize;

use crate::plots::{Curve, PALETTE, envelope_with_mean};

/// uPlot 1.6.32 as published on npm (`dist/uPlot.iife.min.js`).
pub const UPLOT_JS: &str = include_str!("../vendor/uplot/uPlot.iife.min.js");
/// uPlot's own style sheet (`dist/uPlot.min.css`).
pub const UPLOT_CSS: &str = include_str!("../vendor/uplot/uPlot.min.css");
/// The script that turns each figure's chart data into a uPlot chart.
pub const CHARTS_JS: &str = include_str!("../assets/charts.js");

/// Significant digits kept in the page: more than the legend shows (four),
/// and far fewer than a float's seventeen, which would double the page.
const DIGITS: usize = 6;

/// One axis of a chart.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Axis {
    /// The label, with its unit.
    pub label: String,
    /// Logarithmic.
    pub log: bool,
}

/// One trace of a chart, on the chart's x values (`null` where it has no
/// value).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Series {
    /// Legend text.
    pub label: String,
    /// `#rrggbb`.
    pub colour: String,
    /// The values.
    pub y: Vec<Option<f64>>,
    /// The lower edge of the band drawn under the trace (the ADEV's
    /// confidence interval, a time plot's minimum per column).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lo: Option<Vec<Option<f64>>>,
    /// The upper edge of the band.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hi: Option<Vec<Option<f64>>>,
    /// Drawn dashed (a noise term's asymptote).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub dash: bool,
    /// Drawn as a marker, without a line (the ADEV minimum).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub marker: bool,
    /// On the second y axis, at the right.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub right: bool,
}

impl Series {
    fn line(label: &str, colour: [u8; 3], y: Vec<Option<f64>>) -> Series {
        Series {
            label: label.to_string(),
            colour: hex(colour),
            y,
            lo: None,
            hi: None,
            dash: false,
            marker: false,
            right: false,
        }
    }
}

/// What the page's script draws: the shared x values and the traces.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Chart {
    /// The title above the plot.
    pub title: String,
    /// The x axis.
    pub x: Axis,
    /// The left y axis.
    pub y: Axis,
    /// The right y axis, for the traces marked `right`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub y2: Option<Axis>,
    /// What the band under a trace is, for the legend ("95 % interval").
    pub band: String,
    /// The x values, increasing.
    pub xs: Vec<f64>,
    /// The traces.
    pub series: Vec<Series>,
}

impl Chart {
    /// The chart as JSON to put inside a `<script type="application/json">`:
    /// every `<` written as `\u003c` (the same string to a JSON reader), so
    /// no label taken from a file name can close the element.
    pub fn to_json(&self) -> String {
        serde_json::to_string(self)
            .unwrap_or_else(|_| "null".to_string())
            .replace('<', "\\u003c")
    }
}

fn hex([r, g, b]: [u8; 3]) -> String {
    format!("#{r:02x}{g:02x}{b:02x}")
}

fn palette(i: usize) -> [u8; 3] {
    let c = PALETTE[i % PALETTE.len()];
    [c.0, c.1, c.2]
}

/// `x` to [`DIGITS`] significant digits; `None` when not finite.
fn rounded(x: f64) -> Option<f64> {
    if !x.is_finite() {
        return None;
    }
    format!("{x:.*e}", DIGITS - 1).parse().ok()
}

/// Every τ of every curve once, increasing (equal within 1e-9 relative
/// counts as one), and where each curve's points fall on it.
fn union_grid(curves: &[Curve], extra: &[f64]) -> Vec<f64> {
    let mut xs: Vec<f64> = curves
        .iter()
        .flat_map(|c| c.points.iter().map(|p| p.tau))
        .chain(extra.iter().copied())
        .filter(|t| t.is_finite() && *t > 0.0)
        .collect();
    xs.sort_by(f64::total_cmp);
    xs.dedup_by(|a, b| (*a - *b).abs() <= 1e-9 * b.abs());
    xs
}

fn index_of(xs: &[f64], x: f64) -> Option<usize> {
    let i = xs.partition_point(|v| *v < x * (1.0 - 1e-9));
    (i < xs.len() && (xs[i] - x).abs() <= 1e-9 * x.abs().max(1e-300)).then_some(i)
}

/// The interactive twin of [`crate::plots::adev_plot`]: the same curves
/// with their 95 % bands, asymptotes and minimum marker, on log axes.
pub fn adev_chart(title: &str, unit: &str, curves: &[Curve]) -> Chart {
    let markers: Vec<f64> = curves
        .iter()
        .filter_map(|c| c.marker.as_ref().map(|m| m.0))
        .collect();
    let xs = union_grid(curves, &markers);
    let on_grid = |pairs: &mut dyn Iterator<Item = (f64, f64)>| {
        let mut y = vec![None; xs.len()];
        for (tau, v) in pairs {
            if let Some(i) = index_of(&xs, tau) {
                y[i] = rounded(v).filter(|v| *v > 0.0);
            }
        }
        y
    };
    // The asymptotes are drawn only where the curves are, as on the SVG.
    let (lo, hi) = curves
        .iter()
        .flat_map(|c| c.points.iter())
        .flat_map(|p| [p.dev_lo.max(p.dev * 1e-3), p.dev_hi])
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    let mut series = Vec::new();
    for (i, c) in curves.iter().enumerate() {
        let colour = c.colour.unwrap_or_else(|| palette(i));
        let mut s = Series::line(
            &c.label,
            colour,
            on_grid(&mut c.points.iter().map(|p| (p.tau, p.dev))),
        );
        s.lo = Some(on_grid(&mut c.points.iter().map(|p| (p.tau, p.dev_lo))));
        s.hi = Some(on_grid(&mut c.points.iter().map(|p| (p.tau, p.dev_hi))));
        series.push(s);
        for (k, a) in c.asymptotes.iter().enumerate() {
            let y = xs
                .iter()
                .map(|&tau| {
                    let v = a.at_1s * tau.powf(a.slope);
                    (v >= lo && v <= hi).then(|| rounded(v)).flatten()
                })
                .collect();
            let mut s = Series::line(&a.label, palette(4 + k), y);
            s.dash = true;
            series.push(s);
        }
        if let Some((tau, dev, label)) = &c.marker {
            let mut s = Series::line(label, [0, 0, 0], on_grid(&mut std::iter::once((*tau, *dev))));
            s.marker = true;
            series.push(s);
        }
    }
    Chart {
        title: title.to_string(),
        x: Axis {
            label: "τ [s]".into(),
            log: true,
        },
        y: Axis {
            label: format!("Allan deviation [{unit}]"),
            log: true,
        },
        y2: None,
        band: "95 % interval".into(),
        xs: xs.iter().filter_map(|&x| rounded(x)).collect(),
        series,
    }
}

/// The interactive twin of [`crate::plots::time_plot`]: per channel the
/// mean of each of at most [`crate::plots::TIME_COLUMNS`] columns, with
/// its minimum and maximum as a band, and the temperature on a second axis.
/// The page holds at most that many columns however long the recording.
pub fn time_chart(
    title: &str,
    unit: &str,
    channels: &[(String, &[f64])],
    rate_hz: f64,
    temperature: Option<&[f64]>,
) -> Chart {
    let envs: Vec<_> = channels
        .iter()
        .map(|(_, x)| envelope_with_mean(x, rate_hz))
        .collect();
    let temp = temperature.map(|t| envelope_with_mean(t, rate_hz));
    // Columns start at the same times for channels of the same length; a
    // shorter one has no value past its end.
    let mut xs: Vec<f64> = envs.iter().chain(&temp).flatten().map(|c| c.0).collect();
    xs.sort_by(f64::total_cmp);
    xs.dedup();
    let place = |env: &[(f64, f64, f64, f64)], pick: fn(&(f64, f64, f64, f64)) -> f64| {
        let mut y = vec![None; xs.len()];
        for c in env {
            if let Ok(i) = xs.binary_search_by(|v| v.total_cmp(&c.0)) {
                y[i] = rounded(pick(c));
            }
        }
        y
    };
    let mut series: Vec<Series> = channels
        .iter()
        .zip(&envs)
        .enumerate()
        .map(|(i, ((name, _), env))| {
            let mut s = Series::line(name, palette(i), place(env, |c| c.2));
            s.lo = Some(place(env, |c| c.1));
            s.hi = Some(place(env, |c| c.3));
            s
        })
        .collect();
    if let Some(env) = &temp {
        let mut s = Series::line("temperature", [213, 0, 0], place(env, |c| c.2));
        s.right = true;
        series.push(s);
    }
    Chart {
        title: title.to_string(),
        x: Axis {
            label: "time [s]".into(),
            log: false,
        },
        y: Axis {
            label: format!("[{unit}]"),
            log: false,
        },
        y2: temp.as_ref().map(|_| Axis {
            label: "temperature [°C]".into(),
            log: false,
        }),
        band: "min, max of the column".into(),
        xs: xs.iter().filter_map(|&x| rounded(x)).collect(),
        series,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use allan::Point;

    fn point(tau: f64, dev: f64) -> Point {
        Point {
            tau,
            dev,
            dev_lo: dev * 0.8,
            dev_hi: dev * 1.25,
            m: 1,
            n: 10,
            edf: 10.0,
            alpha: 0,
            noise_id: allan::NoiseIdMethod::B1Ratio,
        }
    }

    #[test]
    fn curves_on_different_taus_share_one_grid_with_gaps() {
        let a = [point(1.0, 0.1), point(2.0, 0.07)];
        let b = [point(1.0, 0.2), point(4.0, 0.1)];
        let chart = adev_chart("t", "rad/s", &[Curve::plain("a", &a), Curve::plain("b", &b)]);
        assert_eq!(chart.xs, vec![1.0, 2.0, 4.0]);
        assert_eq!(chart.series[0].y, vec![Some(0.1), Some(0.07), None]);
        assert_eq!(chart.series[1].y, vec![Some(0.2), None, Some(0.1)]);
        assert_eq!(chart.series[1].lo.as_ref().unwrap()[2], Some(0.08));
        assert_eq!(chart.series[1].hi.as_ref().unwrap()[2], Some(0.125));
        assert!(chart.x.log && chart.y.log);
        assert_eq!(chart.y.label, "Allan deviation [rad/s]");
    }

    #[test]
    fn a_label_cannot_close_the_script_element() {
        let a = [point(1.0, 0.1)];
        let chart = adev_chart("</script><b>", "g", &[Curve::plain("</script>x", &a)]);
        let json = chart.to_json();
        assert!(!json.contains('<'), "{json}");
        let back: serde_json::Value = serde_json::from_str(&json).unwrap();
        assert_eq!(back["title"], "</script><b>");
        assert_eq!(back["series"][0]["label"], "</script>x");
    }

    #[test]
    fn a_long_recording_is_held_in_a_bounded_number_of_columns() {
        // An hour at 1 kHz: 3.6 M samples.
        let x: Vec<f64> = (0..3_600_000).map(|i| (i % 6) as f64).collect();
        let chart = time_chart("t", "g", &[("ax".into(), &x)], 1000.0, Some(&x));
        assert!(chart.xs.len() <= crate::plots::TIME_COLUMNS);
        let s = &chart.series[0];
        assert_eq!(s.lo.as_ref().unwrap()[0], Some(0.0));
        assert_eq!(s.hi.as_ref().unwrap()[0], Some(5.0));
        // A column holds 3600 samples, whole periods of the 0..5 pattern.
        assert_eq!(s.y[0], Some(2.5));
        assert!(chart.series[1].right);
        assert_eq!(chart.xs[1], 3.6, "column start, s");
    }

    #[test]
    fn values_keep_six_significant_digits() {
        assert_eq!(rounded(0.123456789), Some(0.123457));
        assert_eq!(rounded(1.0e-7 / 3.0), Some(3.33333e-8));
        assert_eq!(rounded(f64::NAN), None);
    }
}
