//! What a recording's noise costs in metres: strapdown navigation of a
//! static recording from many start points, beside the closed-form
//! prediction from its own noise terms and a Monte Carlo of them.

use std::path::Path;

use crate::monte_carlo::{MonteCarlo, MonteCarloSetup, monte_carlo};
use allan::noise_terms::{Term, analyze_terms};
use ins::drift::{CurvePoint, Drift, Spread, drift_over_windows};
use ins::prediction::{AxisNoise, NoiseModel, Prediction, PredictionSetup, predict};
use ins::strapdown::{ImuData, NavOptions, align, align_samples};
use thermal::tcal::Model;

use crate::AnalysisError;
use crate::selection::Selection;

/// The six channels, in the order navigation takes them.
pub const CHANNELS: [&str; 6] = ["accel_x", "accel_y", "accel_z", "gyro_x", "gyro_y", "gyro_z"];

/// Simulated runs of the Monte Carlo by default: its rms is then known to
/// ±1.9 % (1σ; ±3.7 % at 95 %), the squared 2-D error of a run having a
/// relative standard deviation of 1, so 1/(2·√runs) on the rms. (At 100
/// runs, ±5 %: the Monte Carlo's scatter would pass for a disagreement.)
pub const MONTE_CARLO_RUNS: usize = 700;
/// The Monte Carlo's default seed (fixed: the same file gives the same
/// figures); run i uses seed + i.
pub const MONTE_CARLO_SEED: u64 = 1;

/// How far the closed form may be from the Monte Carlo's interval and still be
/// said to hold at a time, as a fraction.
pub const AGREEMENT: f64 = 0.10;

/// Where the noise terms of a prediction were identified.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoiseSource {
    /// On the navigated recording itself: on a run whose temperature
    /// drifts, its terms absorb part of the drift, and the measured error
    /// above the prediction understates the temperature's share.
    ThisRun,
    /// On the run compensated with the temperature model: the noise alone,
    /// so that on the raw run the measured error above the prediction is
    /// the temperature's.
    CompensatedRun,
}

impl NoiseSource {
    /// Its key in imutherm's JSON.
    pub fn key(self) -> &'static str {
        match self {
            NoiseSource::ThisRun => "this_run",
            NoiseSource::CompensatedRun => "compensated_run",
        }
    }

    /// In words, for a legend or a line of output.
    pub fn describe(self) -> &'static str {
        match self {
            NoiseSource::ThisRun => "this run's",
            NoiseSource::CompensatedRun => "the compensated run's",
        }
    }
}

/// One recording navigated: the measured curve, the prediction and the
/// Monte Carlo at each time.
pub struct Navigated {
    /// Windows navigated.
    pub windows: usize,
    /// Windows left out because they cross a gap.
    pub windows_with_gaps: usize,
    /// The noise terms the prediction rests on.
    pub noise: NoiseModel,
    /// Where they were identified.
    pub noise_from: NoiseSource,
    /// The Monte Carlo's runs and seed.
    pub monte_carlo_runs: usize,
    pub monte_carlo_seed: u64,
    /// One row per report time.
    pub rows: Vec<Row>,
}

impl Navigated {
    /// The first time at which the closed form is more than [`AGREEMENT`]
    /// outside the Monte Carlo's 95 % interval: where the prediction stops
    /// holding (None: it holds at every time).
    pub fn prediction_stops_at(&self) -> Option<f64> {
        self.rows
            .iter()
            .find(|r| !r.prediction_holds())
            .map(|r| r.measured.t_s)
    }

    /// The same for the height's prediction.
    pub fn vertical_prediction_stops_at(&self) -> Option<f64> {
        self.rows
            .iter()
            .find(|r| !r.vertical_prediction_holds())
            .map(|r| r.measured.t_s)
    }
}

/// One time since alignment.
pub struct Row {
    /// The error measured over the windows.
    pub measured: CurvePoint,
    /// The closed-form prediction.
    pub predicted: Prediction,
    /// The Monte Carlo's horizontal position error.
    pub monte_carlo: Spread,
    /// The 95 % confidence interval of the Monte Carlo's horizontal rms, m.
    pub monte_carlo_rms_95: [f64; 2],
    /// The Monte Carlo's height error.
    pub monte_carlo_vertical: Spread,
    /// The 95 % confidence interval of its rms, m.
    pub monte_carlo_vertical_rms_95: [f64; 2],
}

impl Row {
    /// Whether the closed form agrees with the Monte Carlo here: within
    /// [`AGREEMENT`] of its 95 % interval.
    pub fn prediction_holds(&self) -> bool {
        agrees(
            self.predicted.total_m,
            self.monte_carlo.rms,
            self.monte_carlo_rms_95,
        )
    }

    /// The same for the height.
    pub fn vertical_prediction_holds(&self) -> bool {
        agrees(
            self.predicted.vertical_m,
            self.monte_carlo_vertical.rms,
            self.monte_carlo_vertical_rms_95,
        )
    }
}

/// Within [`AGREEMENT`] of some value in the Monte Carlo's 95 % interval
/// (or of its rms, when the runs are too few for an interval): a closed
/// form is not said to fail for the scatter of a finite Monte Carlo.
fn agrees(predicted: f64, rms: f64, [lo, hi]: [f64; 2]) -> bool {
    let (lo, hi) = (lo.min(rms), hi.max(rms));
    predicted >= lo * (1.0 - AGREEMENT) && predicted <= hi * (1.0 + AGREEMENT)
}

/// The six channels of a selection, in the order navigation takes them.
pub fn six_channels(file: &Path, sel: &Selection) -> Result<Vec<Vec<f64>>, AnalysisError> {
    CHANNELS
        .iter()
        .map(|name| {
            sel.channels
                .iter()
                .find(|c| c.name == *name)
                .map(|c| c.data.clone())
                .ok_or_else(|| AnalysisError::MissingChannel {
                    file: file.to_path_buf(),
                    what: format!(
                        "no {name} channel; ins needs the three accelerometer and three gyroscope axes"
                    ),
                })
        })
        .collect()
}

/// [`six_channels`], moving the samples out of `sel` rather than copying
/// them, for a caller that needs nothing else of the selection's channels:
/// a long recording is then held once.
pub fn take_six_channels(file: &Path, sel: &mut Selection) -> Result<Vec<Vec<f64>>, AnalysisError> {
    let at: Vec<usize> = CHANNELS
        .iter()
        .map(|name| {
            sel.channels
                .iter()
                .position(|c| c.name == *name)
                .ok_or_else(|| AnalysisError::MissingChannel {
                    file: file.to_path_buf(),
                    what: format!(
                        "no {name} channel; ins needs the three accelerometer and three gyroscope axes"
                    ),
                })
        })
        .collect::<Result<_, _>>()?;
    Ok(at
        .into_iter()
        .map(|i| std::mem::take(&mut sel.channels[i].data))
        .collect())
}

/// The six channels compensated with `model`, from the selection's
/// temperature; what the compensation could not do is added to `notes`.
pub fn compensated_channels(
    file: &Path,
    sel: &Selection,
    model: &Model,
    six: &[Vec<f64>],
    notes: &mut Vec<String>,
) -> Result<Vec<Vec<f64>>, AnalysisError> {
    let temp = sel
        .temperature
        .as_deref()
        .ok_or_else(|| AnalysisError::MissingChannel {
            file: file.to_path_buf(),
            what: "no temperature channel to compensate with".to_string(),
        })?;
    let mut out = six.to_vec();
    let mut out_of_range = 0;
    for (name, data) in CHANNELS.iter().zip(out.iter_mut()) {
        if model.channel(name).is_some() {
            let r = model
                .apply(name, data, temp, sel.rate_hz)
                .map_err(AnalysisError::thermal(format!(
                    "{}: compensating {name}",
                    file.display()
                )))?;
            out_of_range = out_of_range.max(r.out_of_range);
        } else {
            notes.push(format!(
                "note: {}: the model has no {name}: navigated raw",
                file.display()
            ));
        }
    }
    if out_of_range > 0 {
        notes.push(format!(
            "warning: {}: {out_of_range} samples outside the fitted {:.1}…{:.1} °C were compensated at the range's edge, not extrapolated",
            file.display(),
            model.t_min_c,
            model.t_max_c
        ));
    }
    Ok(out)
}

/// A recording navigated as it is and, with a model, compensated. With a
/// model both predictions rest on the compensated run's noise terms.
pub fn raw_and_compensated(
    file: &Path,
    sel: &Selection,
    model: Option<&Model>,
    plan: &Plan,
    notes: &mut Vec<String>,
) -> Result<(Navigated, Option<Navigated>), AnalysisError> {
    let six = six_channels(file, sel)?;
    match model {
        Some(m) => {
            let comp = compensated_channels(file, sel, m, &six, notes)?;
            let (raw, compensated) = navigate_pair(file, &six, &comp, sel.rate_hz, plan)?;
            Ok((raw, Some(compensated)))
        }
        None => {
            if let Some((lo, hi)) = temperature_span(sel)
                && hi - lo > TEMPERATURE_STEADY_C
            {
                notes.push(format!(
                    "note: {}: the temperature runs over {lo:.1}…{hi:.1} °C: the noise terms the prediction \
                     rests on absorb part of its drift, so the measured error above the prediction understates \
                     the temperature's share ({} predicts from the compensated run)",
                    file.display(),
                    imu::Setting::NavigationModel
                ));
            }
            Ok((navigate(file, &six, sel.rate_hz, plan)?, None))
        }
    }
}

/// A temperature span within which a run counts as at one temperature, °C:
/// what a run at room temperature or in a chamber holds. Beyond it the
/// run's bias follows its temperature, and its noise fit takes part of
/// that for a random walk or a bias instability.
const TEMPERATURE_STEADY_C: f64 = 1.0;

/// The finite temperatures' least and greatest, if any.
fn temperature_span(sel: &Selection) -> Option<(f64, f64)> {
    let t = sel.temperature.as_deref()?;
    t.iter()
        .filter(|v| v.is_finite())
        .fold(None, |acc, &v| match acc {
            None => Some((v, v)),
            Some((lo, hi)) => Some((f64::min(lo, v), f64::max(hi, v))),
        })
}

/// The raw and the compensated channels of one run navigated, both
/// predicted (and simulated) from the compensated run's noise terms: the
/// temperature drift is then in neither prediction, and the raw run's
/// measured error above it is the temperature's share, not the part of it
/// that the raw run's own terms would have absorbed.
pub fn navigate_pair(
    file: &Path,
    raw: &[Vec<f64>],
    compensated: &[Vec<f64>],
    rate: f64,
    plan: &Plan,
) -> Result<(Navigated, Navigated), AnalysisError> {
    let noise = identify_noise(file, compensated, rate)?;
    let comp_drift = drift(file, compensated, rate, plan)?;
    let raw_drift = drift(file, raw, rate, plan)?;
    let (setup, mc) = simulate(file, compensated, rate, plan, &noise)?;
    let source = NoiseSource::CompensatedRun;
    Ok((
        assemble(raw_drift, noise, source, &setup, &mc, plan),
        assemble(comp_drift, noise, source, &setup, &mc, plan),
    ))
}

/// How a recording is navigated: the options, a start point every
/// `every_s` seconds, the errors read at `times` after alignment.
#[derive(Debug, Clone)]
pub struct Plan {
    /// Alignment, latitude, gyro bias.
    pub options: NavOptions,
    /// Seconds between start points.
    pub every_s: f64,
    /// Times since alignment, s.
    pub times: Vec<f64>,
    /// Runs of the Monte Carlo, and the seed of its first.
    pub monte_carlo_runs: usize,
    pub monte_carlo_seed: u64,
}

impl Plan {
    /// The navigation imutherm runs by default on `times`: 10 s alignment,
    /// no latitude, a window every 10 s, [`MONTE_CARLO_RUNS`] runs.
    pub fn standard(times: Vec<f64>) -> Plan {
        Plan {
            options: NavOptions::default(),
            every_s: 10.0,
            times,
            monte_carlo_runs: MONTE_CARLO_RUNS,
            monte_carlo_seed: MONTE_CARLO_SEED,
        }
    }
}

/// N, B and K of one channel from the selected noise model; a term the
/// model does not hold is 0 (its upper bound would enter the prediction as
/// a term the data does not show).
fn axis_noise(file: &Path, name: &str, data: &[f64], rate: f64) -> Result<AxisNoise, AnalysisError> {
    let (_, terms) = analyze_terms(data, rate, allan::DEFAULT_CONFIDENCE).map_err(AnalysisError::allan(
        format!("{}: noise terms of {name}", file.display()),
    ))?;
    let get = |t: Term| terms.model.get(t).value().map_or(0.0, |v| v.value);
    Ok(AxisNoise {
        n: get(Term::WhiteNoise),
        b: get(Term::BiasInstability),
        k: get(Term::RateRandomWalk),
    })
}

/// The noise terms of the six channels.
pub fn identify_noise(file: &Path, six: &[Vec<f64>], rate: f64) -> Result<NoiseModel, AnalysisError> {
    // One axis at a time: each analysis turns a copy of its channel into
    // phase (and runs in parallel inside), so at most one channel's copy
    // is held beside the six, whatever the number of cores.
    let axes: Vec<AxisNoise> = CHANNELS
        .iter()
        .zip(six)
        .map(|(name, data)| axis_noise(file, name, data, rate))
        .collect::<Result<_, _>>()?;
    Ok(NoiseModel {
        accel: [axes[0], axes[1], axes[2]],
        gyro: [axes[3], axes[4], axes[5]],
    })
}

fn imu_of(six: &[Vec<f64>], rate: f64) -> ImuData<'_> {
    ImuData {
        accel: [&six[0], &six[1], &six[2]],
        gyro: [&six[3], &six[4], &six[5]],
        rate_hz: rate,
    }
}

fn drift(file: &Path, six: &[Vec<f64>], rate: f64, plan: &Plan) -> Result<Drift, AnalysisError> {
    drift_over_windows(&imu_of(six, rate), &plan.options, plan.every_s, &plan.times)
        .map_err(AnalysisError::ins(file.display().to_string()))
}

/// The prediction's setup and the Monte Carlo of `noise`, both in the
/// attitude of the first window of `six` that can be levelled (the sensor
/// is static: one attitude).
fn simulate(
    file: &Path,
    six: &[Vec<f64>],
    rate: f64,
    plan: &Plan,
    noise: &NoiseModel,
) -> Result<(PredictionSetup, MonteCarlo), AnalysisError> {
    let opts = &plan.options;
    let imu = imu_of(six, rate);
    let na = align_samples(opts.align_s, rate);
    let first = (0..imu.len().saturating_sub(na))
        .step_by(na)
        .find(|&s| imu.finite(s..s + na))
        .unwrap_or(0);
    let alignment = align(&imu, first..first + na, opts);
    let setup =
        PredictionSetup::from_alignment(&alignment, opts.gravity(), opts.align_s, opts.remove_gyro_bias)
            .with_latitude(opts.latitude_deg);
    let mc = monte_carlo(
        noise,
        opts,
        &MonteCarloSetup {
            rate_hz: rate,
            runs: plan.monte_carlo_runs,
            seed: plan.monte_carlo_seed,
            roll_deg: alignment.roll.to_degrees(),
            pitch_deg: alignment.pitch.to_degrees(),
        },
        &plan.times,
    )
    .map_err(AnalysisError::monte_carlo(format!(
        "{}: Monte Carlo of the identified model",
        file.display()
    )))?;
    Ok((setup, mc))
}

fn assemble(
    drift: Drift,
    noise: NoiseModel,
    noise_from: NoiseSource,
    setup: &PredictionSetup,
    mc: &MonteCarlo,
    plan: &Plan,
) -> Navigated {
    let rows = drift
        .curve
        .iter()
        .zip(&mc.curve)
        .zip(mc.horizontal_rms_95.iter().zip(&mc.vertical_rms_95))
        .map(|((m, c), (ci, vci))| Row {
            measured: *m,
            predicted: predict(&noise, setup, m.t_s),
            monte_carlo: c.horizontal_position_m,
            monte_carlo_rms_95: *ci,
            monte_carlo_vertical: c.vertical_position_m,
            monte_carlo_vertical_rms_95: *vci,
        })
        .collect();
    Navigated {
        windows: drift.windows,
        windows_with_gaps: drift.windows_with_gaps,
        noise,
        noise_from,
        monte_carlo_runs: plan.monte_carlo_runs,
        monte_carlo_seed: plan.monte_carlo_seed,
        rows,
    }
}

/// Navigates the six channels of `file` from every start point of `plan`,
/// predicted from their own noise terms.
pub fn navigate(file: &Path, six: &[Vec<f64>], rate: f64, plan: &Plan) -> Result<Navigated, AnalysisError> {
    let d = drift(file, six, rate, plan)?;
    let noise = identify_noise(file, six, rate)?;
    let (setup, mc) = simulate(file, six, rate, plan, &noise)?;
    Ok(assemble(d, noise, NoiseSource::ThisRun, &setup, &mc, plan))
}

/// The horizontal position RMS at `t_s` after alignment, from a start
/// point every `every_s` seconds, with `options`: one figure of a
/// navigation for comparing alignment windows.
pub fn horizontal_rms_at(
    six: &[Vec<f64>],
    rate_hz: f64,
    options: &NavOptions,
    every_s: f64,
    times: &[f64],
    t_s: f64,
) -> Result<Option<f64>, ins::InsError> {
    let data = ImuData {
        accel: [&six[0], &six[1], &six[2]],
        gyro: [&six[3], &six[4], &six[5]],
        rate_hz,
    };
    let d = drift_over_windows(&data, options, every_s, times)?;
    Ok(d.curve
        .iter()
        .find(|p| p.t_s == t_s)
        .map(|p| p.horizontal_position_m.rms))
}
