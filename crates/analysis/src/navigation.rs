//! What a recording's noise costs in metres: strapdown navigation of a
//! static recording from many start points, beside the closed-form
//! prediction from its own noise terms and a Monte Carlo of them.

use std::path::Path;

use allan::noise_terms::{Term, analyze_terms};
use ins::drift::{CurvePoint, Spread, drift_over_windows};
use ins::monte_carlo::{MonteCarloSetup, monte_carlo};
use ins::prediction::{AxisNoise, NoiseModel, Prediction, PredictionSetup, predict};
use ins::strapdown::{ImuData, NavOptions, align, align_samples};
use thermal::tcal::Model;

use crate::AnalysisError;
use crate::selection::Selection;

/// The six channels, in the order navigation takes them.
pub const CHANNELS: [&str; 6] = ["accel_x", "accel_y", "accel_z", "gyro_x", "gyro_y", "gyro_z"];

/// Simulated runs of the Monte Carlo, and its seed (fixed: the same file
/// gives the same figures).
pub const MONTE_CARLO_RUNS: usize = 100;
const MONTE_CARLO_SEED: u64 = 1;

/// One recording navigated: the measured curve, the prediction and the
/// Monte Carlo at each time.
pub struct Navigated {
    /// Windows navigated.
    pub windows: usize,
    /// Windows left out because they cross a gap.
    pub windows_with_gaps: usize,
    /// The noise terms the prediction rests on.
    pub noise: NoiseModel,
    /// One row per report time.
    pub rows: Vec<Row>,
}

/// One time since alignment.
pub struct Row {
    /// The error measured over the windows.
    pub measured: CurvePoint,
    /// The closed-form prediction.
    pub predicted: Prediction,
    /// The Monte Carlo's horizontal position error.
    pub monte_carlo: Spread,
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

/// A recording navigated as it is and, with a model, compensated.
pub fn raw_and_compensated(
    file: &Path,
    sel: &Selection,
    model: Option<&Model>,
    plan: &Plan,
    notes: &mut Vec<String>,
) -> Result<(Navigated, Option<Navigated>), AnalysisError> {
    let six = six_channels(file, sel)?;
    let raw = navigate(file, &six, sel.rate_hz, plan)?;
    let compensated = match model {
        Some(m) => {
            let comp = compensated_channels(file, sel, m, &six, notes)?;
            Some(navigate(file, &comp, sel.rate_hz, plan)?)
        }
        None => None,
    };
    Ok((raw, compensated))
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

/// Navigates the six channels of `file` from every start point of `plan`.
pub fn navigate(file: &Path, six: &[Vec<f64>], rate: f64, plan: &Plan) -> Result<Navigated, AnalysisError> {
    let opts = &plan.options;
    let imu = ImuData {
        accel: [&six[0], &six[1], &six[2]],
        gyro: [&six[3], &six[4], &six[5]],
        rate_hz: rate,
    };
    let drift = drift_over_windows(&imu, opts, plan.every_s, &plan.times)
        .map_err(AnalysisError::ins(file.display().to_string()))?;
    // One axis at a time: each analysis turns a copy of its channel into
    // phase (and runs in parallel inside), so at most one channel's copy
    // is held beside the six, whatever the number of cores.
    let axes: Vec<AxisNoise> = CHANNELS
        .iter()
        .zip(six)
        .map(|(name, data)| axis_noise(file, name, data, rate))
        .collect::<Result<_, _>>()?;
    let noise = NoiseModel {
        accel: [axes[0], axes[1], axes[2]],
        gyro: [axes[3], axes[4], axes[5]],
    };
    // The prediction projects the noise with the attitude of the first
    // window that can be levelled (the sensor is static: one attitude).
    let na = align_samples(opts.align_s, rate);
    let first = (0..imu.len().saturating_sub(na))
        .step_by(na)
        .find(|&s| imu.finite(s..s + na))
        .unwrap_or(0);
    let alignment = align(&imu, first..first + na, opts);
    let setup =
        PredictionSetup::from_alignment(&alignment, opts.gravity(), opts.align_s, opts.remove_gyro_bias);
    let mc = monte_carlo(
        &noise,
        opts,
        &MonteCarloSetup {
            rate_hz: rate,
            runs: MONTE_CARLO_RUNS,
            seed: MONTE_CARLO_SEED,
            roll_deg: alignment.roll.to_degrees(),
            pitch_deg: alignment.pitch.to_degrees(),
        },
        &plan.times,
    )
    .map_err(AnalysisError::ins(format!(
        "{}: Monte Carlo of the identified model",
        file.display()
    )))?;
    let rows = drift
        .curve
        .iter()
        .zip(&mc)
        .map(|(m, c)| Row {
            measured: *m,
            predicted: predict(&noise, &setup, m.t_s),
            monte_carlo: c.horizontal_position_m,
        })
        .collect();
    Ok(Navigated {
        windows: drift.windows,
        windows_with_gaps: drift.windows_with_gaps,
        noise,
        rows,
    })
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
