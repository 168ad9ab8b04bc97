//! What an IMU is, in the figures a reader asks for first: per axis N, B
//! (with its τ) and K with their intervals in datasheet units beside a
//! datasheet's figures; how much temperature moves it; what the
//! compensation buys on held-out data; the drift at 60 s without GNSS.
//! A value, serialisable, drawn by the report's template.

use std::f64::consts::PI;

use allan::noise_terms::{Chosen, Term};
use imu::Quantity;
use imu::units::STANDARD_GRAVITY;
use serde::Serialize;
use thermal::evaluation::spread;

use crate::datasheet::{Datasheet, Figure, summary_unit};
use crate::experiment::{COMPARED_AT_S, Experiment};
use crate::navigation::Navigated;
use crate::noise::{ChannelNoise, RunNoise};
use crate::units::{Units, density_of, unit_of};

/// The temperature datasheets quote typical figures at, °C
/// (PS-MPU-9250A-01 §3.1, §3.2: T_A = 25 °C): the run nearest it gives
/// the summary's N, B and K.
pub const DATASHEET_TEMPERATURE_C: f64 = 25.0;

/// The summary of an IMU.
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    /// The datasheet compared with, if any.
    pub datasheet: Option<DatasheetRef>,
    /// Mean temperature of the run the terms come from, °C.
    pub terms_run_c: Option<f64>,
    /// The coldest and the hottest run's mean temperatures, °C.
    pub coldest_c: Option<f64>,
    /// See `coldest_c`.
    pub hottest_c: Option<f64>,
    /// One per inertial axis, in the runs' order.
    pub axes: Vec<AxisSummary>,
    /// The compensation on held-out data, per axis; empty without one.
    pub compensation: Vec<CompensationGain>,
    /// Horizontal position error after 60 s without GNSS, if navigated.
    pub drift_60s: Option<Drift>,
    /// The gyroscope's white noise N in each constant-temperature run,
    /// coldest first: the answer's first figure.
    pub gyro_noise_by_run: Vec<RunWhiteNoise>,
    /// The gyroscope axis whose bias moves most with temperature, and its
    /// slope: the answer's second figure.
    pub steepest_gyro: Option<(String, Slope)>,
    /// The least and the most of the gyroscope's bias over temperature the
    /// compensation removes on held-out data, %.
    pub gyro_removed_pct: Option<[f64; 2]>,
}

/// The gyroscope's N in one run: the mean over its axes of the selected
/// model's N (an axis whose N is only bounded is left out).
#[derive(Debug, Clone, Serialize)]
pub struct RunWhiteNoise {
    /// The run's mean temperature, °C.
    pub temperature_c: f64,
    /// N, in `unit`.
    pub value: f64,
    /// `°/s/√Hz`, the summary's.
    pub unit: &'static str,
}

/// Each run's gyroscope N, coldest first.
fn gyro_noise_by_run(runs: &[RunNoise]) -> Vec<RunWhiteNoise> {
    let Some((scale, unit)) = density_of(Quantity::AngularRate) else {
        return Vec::new();
    };
    let mut out: Vec<RunWhiteNoise> = runs
        .iter()
        .filter_map(|r| {
            let n: Vec<f64> = r
                .channels
                .iter()
                .filter(|c| c.channel.quantity == Quantity::AngularRate)
                .filter_map(|c| match c.terms.choose(Term::WhiteNoise).chosen {
                    Chosen::Model(v) => Some(v.value),
                    _ => None,
                })
                .collect();
            if n.is_empty() {
                return None;
            }
            Some(RunWhiteNoise {
                temperature_c: r.temperature_mean_c?,
                value: scale * n.iter().sum::<f64>() / n.len() as f64,
                unit,
            })
        })
        .collect();
    out.sort_by(|a, b| a.temperature_c.total_cmp(&b.temperature_c));
    out
}

/// Which datasheet.
#[derive(Debug, Clone, Serialize)]
pub struct DatasheetRef {
    /// The part.
    pub name: String,
    /// The document.
    pub document: String,
    /// Its revision.
    pub revision: String,
}

/// One axis.
#[derive(Debug, Clone, Serialize)]
pub struct AxisSummary {
    /// Channel name.
    pub name: String,
    /// "gyroscope" or "accelerometer".
    pub sensor: &'static str,
    /// N, B, K.
    pub terms: Vec<TermSummary>,
    /// Bias against temperature: the slope of a straight line through the
    /// held-out run's 1 °C bin means.
    pub bias_slope: Option<Slope>,
    /// What the datasheet says of the bias over temperature.
    pub bias_datasheet: DatasheetCell,
    /// N of the hottest run over N of the coldest.
    pub noise_growth: Option<f64>,
}

/// One noise term of an axis.
#[derive(Debug, Clone, Serialize)]
pub struct TermSummary {
    /// N, B or K.
    pub symbol: &'static str,
    /// The unit of the values.
    pub unit: &'static str,
    /// The estimate (or the upper bound, when `how` says so).
    pub value: Option<f64>,
    /// Its interval.
    pub lo: Option<f64>,
    /// See `lo`.
    pub hi: Option<f64>,
    /// The τ it was read at, s (for B: the ADEV minimum's).
    pub tau_s: Option<f64>,
    /// "fit", "slope", "upper bound" or "not identified".
    pub how: &'static str,
    /// The selected noise model the value or bound was read from ("N + B +
    /// K"; "none" when no candidate model fits).
    pub model: String,
    /// The datasheet's figure.
    pub datasheet: DatasheetCell,
}

/// A datasheet's figure beside a measured one.
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "state", rename_all = "snake_case")]
pub enum DatasheetCell {
    /// No datasheet was given.
    NoDatasheet,
    /// The datasheet does not give this figure.
    NotGiven,
    /// The document gives it, the file does not carry it.
    NotCarried,
    /// The figure.
    Given {
        /// As the datasheet has it.
        figure: Figure,
        /// "above" or "below" when the measured interval excludes the
        /// figure, "within" when it holds it.
        verdict: Option<&'static str>,
    },
}

/// A slope with its 95 % interval.
#[derive(Debug, Clone, Serialize)]
pub struct Slope {
    /// Per °C.
    pub value: f64,
    /// Half-width of its 95 % interval (least squares, white residuals).
    pub half_width: f64,
    /// "°/s/°C" or "mg/°C".
    pub unit: &'static str,
    /// What it is fitted on: "held-out run" (its 1 °C bin means) or "run
    /// means" (each constant-temperature run's mean against its mean
    /// temperature).
    pub from: &'static str,
}

/// The compensation on one axis of the held-out run.
#[derive(Debug, Clone, Serialize)]
pub struct CompensationGain {
    /// Channel name.
    pub name: String,
    /// RMS of the raw 1 °C bin means about their mean.
    pub raw: f64,
    /// The same, compensated.
    pub compensated: f64,
    /// "°/s" or "mg".
    pub unit: &'static str,
    /// 1 − compensated/raw, %.
    pub reduction_pct: f64,
}

/// Horizontal position RMS at 60 s, m.
#[derive(Debug, Clone, Serialize)]
pub struct Drift {
    /// Raw.
    pub raw_m: f64,
    /// Compensated.
    pub compensated_m: Option<f64>,
}

/// °/s per rad/s, mg per m/s²: the units bias slopes and residuals are
/// quoted in (PS-MPU-9250A-01 §3.2 gives the accelerometer's in mg/°C).
fn bias_scale(q: Quantity) -> Option<(f64, &'static str)> {
    match q {
        Quantity::AngularRate => Some((180.0 / PI, "°/s")),
        Quantity::Acceleration => Some((1.0 / (STANDARD_GRAVITY * 1e-3), "mg")),
        _ => None,
    }
}

impl Summary {
    /// The summary of constant-temperature runs, compared with `sheet`.
    pub fn of_runs(runs: &[RunNoise], sheet: Option<&Datasheet>) -> Summary {
        let temps: Vec<f64> = runs.iter().filter_map(|r| r.temperature_mean_c).collect();
        let coldest = temps.iter().copied().reduce(f64::min);
        let hottest = temps.iter().copied().reduce(f64::max);
        let terms_run = runs.iter().min_by(|a, b| {
            let d = |r: &RunNoise| {
                r.temperature_mean_c
                    .map_or(f64::INFINITY, |t| (t - DATASHEET_TEMPERATURE_C).abs())
            };
            d(a).total_cmp(&d(b))
        });
        let at = |t: Option<f64>| {
            runs.iter()
                .find(|r| r.temperature_mean_c.is_some() && r.temperature_mean_c == t)
        };
        let (cold_run, hot_run) = (at(coldest), at(hottest));
        let axes = terms_run
            .map(|run| {
                run.channels
                    .iter()
                    .filter(|c| bias_scale(c.channel.quantity).is_some())
                    .map(|c| {
                        let q = c.channel.quantity;
                        let n_of = |r: Option<&RunNoise>| {
                            r?.channels
                                .iter()
                                .find(|x| x.channel.name == c.channel.name)?
                                .terms
                                .choose(Term::WhiteNoise)
                                .value()
                        };
                        let noise_growth = match (n_of(cold_run), n_of(hot_run)) {
                            (Some(a), Some(b)) if a > 0.0 && coldest != hottest => Some(b / a),
                            _ => None,
                        };
                        let bias_slope = across_runs(runs, &c.channel.name, q);
                        AxisSummary {
                            name: c.channel.name.clone(),
                            sensor: if q == Quantity::AngularRate {
                                "gyroscope"
                            } else {
                                "accelerometer"
                            },
                            terms: [Term::WhiteNoise, Term::BiasInstability, Term::RateRandomWalk]
                                .into_iter()
                                .map(|t| term_summary(c, t, sheet))
                                .collect(),
                            bias_datasheet: {
                                let mut d = cell(sheet, q, |s| {
                                    s.sensor(q).and_then(|f| f.bias_over_temperature.clone())
                                });
                                set_verdict(&mut d, bias_slope.as_ref());
                                d
                            },
                            bias_slope,
                            noise_growth,
                        }
                    })
                    .collect()
            })
            .unwrap_or_default();
        Summary {
            datasheet: sheet.map(|s| DatasheetRef {
                name: s.name.clone(),
                document: s.document.clone(),
                revision: s.revision.clone(),
            }),
            terms_run_c: terms_run.and_then(|r| r.temperature_mean_c),
            coldest_c: coldest,
            hottest_c: hottest,
            axes,
            compensation: Vec::new(),
            drift_60s: None,
            gyro_noise_by_run: gyro_noise_by_run(runs),
            steepest_gyro: None,
            gyro_removed_pct: None,
        }
        .with_answer()
    }

    /// The summary of the whole experiment: the runs', with the bias slope
    /// and the compensation's gain on the held-out heating run, and the
    /// cooling run's drift at 60 s.
    pub fn of_experiment(exp: &Experiment, sheet: Option<&Datasheet>) -> Summary {
        let mut s = Summary::of_runs(&exp.runs, sheet);
        for axis in &mut s.axes {
            let Some(c) = exp.compensation.iter().find(|c| c.name == axis.name) else {
                continue;
            };
            let Some((scale, unit)) = bias_scale(c.quantity) else {
                continue;
            };
            // The held-out run's bins sample every temperature between the
            // runs', so its slope replaces the one across run means.
            if let Some(slope) = line_slope(&c.before.iter().map(|b| (b.t, b.mean)).collect::<Vec<_>>())
                .map(|fit| slope_in(fit, scale, c.quantity, "held-out run"))
            {
                set_verdict(&mut axis.bias_datasheet, Some(&slope));
                axis.bias_slope = Some(slope);
            }
            let (raw, comp) = (spread(&c.before).rms, spread(&c.after).rms);
            s.compensation.push(CompensationGain {
                name: c.name.clone(),
                raw: raw * scale,
                compensated: comp * scale,
                unit,
                reduction_pct: 100.0 * (1.0 - comp / raw),
            });
        }
        let at60 = |n: &Navigated| {
            n.rows
                .iter()
                .find(|r| r.measured.t_s == COMPARED_AT_S)
                .map(|r| r.measured.horizontal_position_m.rms)
        };
        s.drift_60s = at60(&exp.navigation.raw).map(|raw_m| Drift {
            raw_m,
            compensated_m: at60(&exp.navigation.compensated),
        });
        s.with_answer()
    }

    /// The answer's figures drawn from the axes and the compensation.
    fn with_answer(mut self) -> Summary {
        self.steepest_gyro = self
            .axes
            .iter()
            .filter(|a| a.sensor == "gyroscope")
            .filter_map(|a| Some((a.name.clone(), a.bias_slope.clone()?)))
            .max_by(|a, b| a.1.value.abs().total_cmp(&b.1.value.abs()));
        let removed: Vec<f64> = self
            .compensation
            .iter()
            .filter(|c| c.unit == "°/s" && c.reduction_pct.is_finite())
            .map(|c| c.reduction_pct)
            .collect();
        self.gyro_removed_pct = (!removed.is_empty()).then(|| {
            [
                removed.iter().copied().fold(f64::INFINITY, f64::min),
                removed.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            ]
        });
        self
    }
}

fn cell(
    sheet: Option<&Datasheet>,
    q: Quantity,
    figure: impl Fn(&Datasheet) -> Option<Figure>,
) -> DatasheetCell {
    match sheet {
        None => DatasheetCell::NoDatasheet,
        Some(s) if s.omits(q) => DatasheetCell::NotCarried,
        Some(s) => figure(s).map_or(DatasheetCell::NotGiven, |figure| DatasheetCell::Given {
            figure,
            verdict: None,
        }),
    }
}

fn term_summary(c: &ChannelNoise, term: Term, sheet: Option<&Datasheet>) -> TermSummary {
    let q = c.channel.quantity;
    let unit = summary_unit(q, term).unwrap_or("");
    // N is quoted as a density (the same number per √Hz as per √s); B and
    // K in the datasheet units (IEEE 952 Annex C conversions).
    let factor = match term {
        Term::WhiteNoise => density_of(q).map_or(1.0, |d| d.0),
        t => unit_of(t, q, &c.channel.unit, Units::Datasheet).0,
    };
    let choice = c.terms.choose(term);
    let (value, lo, hi, tau, how) = match choice.chosen {
        Chosen::Model(v) => (Some(v.value), Some(v.lo), Some(v.hi), v.tau, "fit"),
        Chosen::Bound(b) => (Some(b), None, Some(b), None, "upper bound"),
        Chosen::Nothing => (None, None, None, None, "not identified"),
    };
    // B is read where the ADEV flattens: its minimum's τ.
    let tau_s = if term == Term::BiasInstability {
        tau.or(c.terms.slope.sigma_min.and_then(|m| m.tau))
    } else {
        tau
    };
    let scaled = |x: Option<f64>| x.map(|x| x * factor);
    let (value, lo, hi) = (scaled(value), scaled(lo), scaled(hi));
    let mut datasheet = cell(sheet, q, |s| s.figure(q, term).cloned());
    if let DatasheetCell::Given { figure, verdict } = &mut datasheet
        && let Some(v) = figure.value
        && let Some(h) = hi
    {
        // A bound above the figure alone says nothing either way.
        *verdict = match lo {
            _ if h < v => Some("below"),
            Some(l) if l > v => Some("above"),
            Some(_) => Some("within"),
            None => None,
        };
    }
    TermSummary {
        symbol: term.symbol(),
        unit,
        value,
        lo,
        hi,
        tau_s,
        how,
        model: c.terms.model.label.clone(),
        datasheet,
    }
}

/// The slope of a channel's mean across constant-temperature runs, in
/// the summary's unit; none with fewer than three runs at distinct
/// temperatures.
fn across_runs(runs: &[RunNoise], name: &str, q: Quantity) -> Option<Slope> {
    let (scale, _) = bias_scale(q)?;
    let pts: Vec<(f64, f64)> = runs
        .iter()
        .filter_map(|r| {
            let t = r.temperature_mean_c?;
            let c = r.channels.iter().find(|c| c.channel.name == name)?;
            Some((t, c.mean?))
        })
        .collect();
    line_slope(&pts).map(|fit| slope_in(fit, scale, q, "run means"))
}

fn slope_in((value, half_width): (f64, f64), scale: f64, q: Quantity, from: &'static str) -> Slope {
    Slope {
        value: value * scale,
        half_width: half_width * scale,
        unit: if q == Quantity::AngularRate {
            "°/s/°C"
        } else {
            "mg/°C"
        },
        from,
    }
}

/// The datasheet's ± figure bounds |slope|: "above" when the whole
/// interval lies beyond it, "within" otherwise; no verdict without a slope
/// in the figure's unit (a verdict from an earlier slope is dropped).
fn set_verdict(cell: &mut DatasheetCell, slope: Option<&Slope>) {
    let DatasheetCell::Given { figure, verdict } = cell else {
        return;
    };
    *verdict = match (slope, figure.value) {
        (Some(slope), Some(v)) if figure.unit.as_deref() == Some(slope.unit) => {
            Some(if slope.value.abs() - slope.half_width > v {
                "above"
            } else {
                "within"
            })
        }
        _ => None,
    };
}

/// Least-squares slope of (temperature, mean) points and the half-width
/// of its 95 % interval (normal quantile 1.96).
fn line_slope(points: &[(f64, f64)]) -> Option<(f64, f64)> {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .copied()
        .filter(|(t, m)| t.is_finite() && m.is_finite())
        .collect();
    let n = pts.len() as f64;
    if pts.len() < 3 {
        return None;
    }
    let (mt, my) = (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxx: f64 = pts.iter().map(|p| (p.0 - mt).powi(2)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let slope = pts.iter().map(|p| (p.0 - mt) * (p.1 - my)).sum::<f64>() / sxx;
    let rss: f64 = pts.iter().map(|p| (p.1 - my - slope * (p.0 - mt)).powi(2)).sum();
    let se = (rss / (n - 2.0) / sxx).sqrt();
    Some((slope, 1.96 * se))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_summary_units_are_those_of_the_datasheet_unit_system() {
        for q in [Quantity::AngularRate, Quantity::Acceleration] {
            for t in [Term::BiasInstability, Term::RateRandomWalk] {
                assert_eq!(
                    Some(unit_of(t, q, "", Units::Datasheet).1.as_str()),
                    summary_unit(q, t)
                );
            }
            assert_eq!(density_of(q).map(|d| d.1), summary_unit(q, Term::WhiteNoise));
        }
    }

    /// The answer's second figure: the gyro axis whose bias moves most (by
    /// magnitude), and the least and most of the gyro's bias compensation
    /// removes; accelerometer axes take no part.
    #[test]
    fn the_answer_takes_the_steepest_gyro_and_the_gyros_range_removed() {
        let axis = |name: &str, sensor: &'static str, slope: f64| AxisSummary {
            name: name.to_string(),
            sensor,
            terms: Vec::new(),
            bias_slope: Some(Slope {
                value: slope,
                half_width: 0.001,
                unit: if sensor == "gyroscope" {
                    "°/s/°C"
                } else {
                    "mg/°C"
                },
                from: "held-out run",
            }),
            bias_datasheet: DatasheetCell::NoDatasheet,
            noise_growth: None,
        };
        let gain = |name: &str, unit: &'static str, pct: f64| CompensationGain {
            name: name.to_string(),
            raw: 1.0,
            compensated: 1.0 - pct / 100.0,
            unit,
            reduction_pct: pct,
        };
        let s = Summary {
            datasheet: None,
            terms_run_c: None,
            coldest_c: None,
            hottest_c: None,
            axes: vec![
                axis("accel_x", "accelerometer", 9.0),
                axis("gyro_x", "gyroscope", 0.02),
                axis("gyro_y", "gyroscope", -0.03),
            ],
            compensation: vec![
                gain("accel_x", "mg", 50.0),
                gain("gyro_x", "°/s", 97.0),
                gain("gyro_y", "°/s", 94.5),
            ],
            drift_60s: None,
            gyro_noise_by_run: Vec::new(),
            steepest_gyro: None,
            gyro_removed_pct: None,
        }
        .with_answer();
        let (name, slope) = s.steepest_gyro.unwrap();
        assert_eq!((name.as_str(), slope.value), ("gyro_y", -0.03));
        assert_eq!(s.gyro_removed_pct, Some([94.5, 97.0]));
    }

    #[test]
    fn a_straight_line_gives_its_slope_with_a_null_interval() {
        let pts: Vec<(f64, f64)> = (0..10)
            .map(|i| (20.0 + i as f64, 0.5 - 0.01 * (20.0 + i as f64)))
            .collect();
        let (s, h) = line_slope(&pts).unwrap();
        assert!((s + 0.01).abs() < 1e-12 && h < 1e-9, "{s} {h}");
        assert!(line_slope(&pts[..2]).is_none());
    }
}
