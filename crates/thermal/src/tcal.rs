//! Temperature compensation of the bias: fit, apply, evaluate.
//!
//! The bias of each channel is a polynomial p of temperature, fitted by
//! least squares on a scaled temperature u = (T − centre)/half-span (powers
//! of raw °C are ill-conditioned beyond a cubic) over the data's own range.
//! The samples are gathered into temperature bins, each bin weighted by the
//! samples it holds (the variance of its mean), and each sample weighs its
//! bin's weight over its count: the bins keep, besides their means, the
//! mean products u^i·u^j and x·u^j of their samples, so the normal
//! equations are those of the samples themselves, and where no floor
//! flattens the weights the fit is exactly least squares over every sample
//! (the minimum-variance fit under white noise). Bin means alone (on their
//! mean powers of u) lose the spread of the temperature inside each bin,
//! which on the benchmark of `bench/tcal_peers` cost up to a fifth more
//! error against the true bias.
//! Heating and cooling are told apart on the temperature smoothed over
//! minutes ([`crate::branch`]); where the two branches differ beyond their
//! interval, the difference is reported ([`crate::hysteresis`]). Optionally
//! a term in dT/dt absorbs thermal lag (the die is warmer than the sensor
//! of the temperature while heating, colder while cooling). The
//! compensation is the thesis's `x_comp = x − (p(T) − p(T_ref))`.
//!
//! `Order::Auto` chooses the order by cross-validation: leave one run out
//! when there are several, else leave out blocks of the run's bins dealt to
//! five folds; the smallest order within one standard error of the best
//! held-out mean square wins, so noise does not buy extra coefficients.
//! Gaps (NaN samples, bursts) only leave samples out: no score, residual or
//! model field is ever NaN.

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

use crate::ThermalError;
use crate::branch;
pub use crate::dynamics::HysteresisTerm;
use crate::dynamics::{self, Frame};
use crate::element;
use crate::hysteresis::{BranchResidual, Hysteresis, hysteresis};
use crate::weights;

/// The schema name of a saved model.
pub const SCHEMA: &str = "imutherm.tcal/1";
/// Highest order `Order::Auto` tries (unless capped by
/// [`FitOptions::max_auto_order`]).
pub const MAX_AUTO_ORDER: usize = 5;
/// Smallest temperature span a fit accepts, °C.
pub const MIN_SPAN_C: f64 = 1.0;
/// Window over which dT/dt is taken, s: long enough that the temperature
/// sensor's quantization (0.003 °C) does not dominate it.
pub const RATE_WINDOW_S: f64 = 10.0;

/// The polynomial order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Order {
    /// A given order.
    Fixed(usize),
    /// Chosen by cross-validation.
    Auto,
}

/// How to fit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitOptions {
    /// Polynomial order.
    pub order: Order,
    /// Reference temperature; `None`: the middle of the range.
    pub t_ref_c: Option<f64>,
    /// Width of the averaging bins, °C.
    pub bin_width_c: f64,
    /// Fit a term in dT/dt too.
    pub rate_term: bool,
    /// Highest order `Order::Auto` may choose: a flight stack that takes a
    /// cubic at most needs 3.
    pub max_auto_order: usize,
    /// Search the element's lag and a direction-following hysteresis on
    /// held-out cells ([`crate::dynamics`]); ignored with `rate_term`.
    pub dynamics: bool,
    /// Project the model on what a flight stack applies, a polynomial of
    /// the logged temperature: the full model's equilibrium curve, with
    /// what is lost in each channel's `projection`.
    pub firmware_projection: bool,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            order: Order::Auto,
            t_ref_c: None,
            bin_width_c: 1.0,
            rate_term: false,
            max_auto_order: MAX_AUTO_ORDER,
            dynamics: true,
            firmware_projection: false,
        }
    }
}

/// One run to fit: channels of rate samples and their temperature.
#[derive(Debug, Clone, Copy)]
pub struct Run<'a> {
    /// The channels to compensate.
    pub channels: &'a [TcalChannel<'a>],
    /// Temperature per sample, °C.
    pub temp: &'a [f64],
    /// Sample rate, Hz.
    pub rate_hz: f64,
}

/// One channel of a run to fit on: its name, unit and samples.
#[derive(Debug, Clone)]
pub struct TcalChannel<'a> {
    /// Channel name (`gyro_x`).
    pub name: String,
    /// Unit of the samples (SI).
    pub unit: String,
    /// The samples, one per temperature.
    pub data: &'a [f64],
}

impl<'a> TcalChannel<'a> {
    /// A channel called `name`, in `unit`.
    pub fn new(name: impl Into<String>, unit: impl Into<String>, data: &'a [f64]) -> Self {
        TcalChannel {
            name: name.into(),
            unit: unit.into(),
            data,
        }
    }
}

/// The model of one channel.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ChannelModel {
    /// Channel name (`gyro_x`).
    pub name: String,
    /// Unit of the channel and of the coefficients' results.
    pub unit: String,
    /// Polynomial order.
    pub order: usize,
    /// Coefficients in u = (T − centre)/scale, ascending powers.
    pub coefficients: Vec<f64>,
    /// Coefficient of dT/dt (unit per °C/s), when fitted.
    pub rate_coefficient: Option<f64>,
    /// RMS of the bin means' residuals, each bin weighted by its samples,
    /// in the channel's unit.
    pub residual_rms: f64,
    /// Largest absolute bin residual.
    pub residual_max: f64,
    /// Held-out RMS per order tried (order, RMS), when chosen automatically.
    pub cross_validation: Vec<(usize, f64)>,
    /// The heating branch minus the cooling branch, where the data show
    /// one beyond its 95 % interval.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hysteresis: Option<Hysteresis>,
    /// The element's first-order lag behind the logged temperature, s:
    /// the polynomial is of the logged temperature through it, where the
    /// held-out cells showed one ([`crate::dynamics`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lag_s: Option<f64>,
    /// The lag's 95 % interval, s, where the fit's profile bounds it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lag_interval_s: Option<[f64; 2]>,
    /// A bias following the smoothed direction of change, saturating,
    /// where the held-out cells showed one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hysteresis_term: Option<HysteresisTerm>,
    /// What a firmware that applies a polynomial of the logged temperature
    /// alone loses of the full model (`--for`): the model's polynomial is
    /// then the full model's equilibrium curve, lag and hysteresis dropped.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub projection: Option<Projection>,
}

/// What projecting the full model on a polynomial of the logged
/// temperature costs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Projection {
    /// The full model's lag, s, dropped.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lag_s: Option<f64>,
    /// The full model's heating-minus-cooling, dropped.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub heating_minus_cooling: Option<f64>,
    /// A steady climb, °C/min, the next figure is for.
    pub climb_c_per_min: f64,
    /// The bias the full model removes on that climb at the reference
    /// temperature and the projection leaves, in the channel's unit.
    pub climb_left: f64,
    /// RMS over the fitted runs' cells (level removed) left by the full
    /// model, in the channel's unit.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub full_residual_rms: Option<f64>,
    /// The same for the projection, the polynomial alone.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub projected_residual_rms: Option<f64>,
}

/// A fitted compensation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Model {
    /// `imutherm.tcal/1`.
    pub schema: String,
    /// Reference temperature, °C: the compensation is zero there.
    pub t_ref_c: f64,
    /// Range the model was fitted over, °C.
    pub t_min_c: f64,
    /// Range the model was fitted over, °C.
    pub t_max_c: f64,
    /// Centre of the scaled temperature, °C.
    pub centre_c: f64,
    /// Half-span of the scaled temperature, °C.
    pub scale_c: f64,
    /// Bin width used, °C.
    pub bin_width_c: f64,
    /// The runs the model was fitted on (file names, as the caller gave
    /// them), so that an evaluation can tell held-out runs apart.
    #[serde(default)]
    pub fitted_on: Vec<String>,
    /// A fingerprint of each fitted run's bytes, in the order of
    /// `fitted_on`, so that a run is recognised under any name.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub fitted_on_digests: Vec<String>,
    /// The dT/dt range (°C/s, lowest and highest bin mean) the rate term
    /// was fitted over; present exactly when a channel has a rate term.
    /// Applying the model clamps dT/dt to it, as T is clamped to the
    /// fitted temperature range.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dtdt_range_c_per_s: Option<[f64; 2]>,
    /// The sensor's device id, when the recordings carry one (firmware maps
    /// a calibration to a sensor by it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub device_id: Option<u32>,
    /// The accelerometer's device id, where the recording gives it apart
    /// from the gyro's (a PX4 ULog's `sensor_accel` `device_id`); absent,
    /// `device_id` stands for both.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub accel_device_id: Option<u32>,
    /// The log's IMU instance (PX4 multi-instance, ArduPilot `IMU.I`) the
    /// model was fitted on, where the log has instances.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub instance: Option<u32>,
    /// The step of a coarse temperature readout (whole °C, say) the fit
    /// found and smoothed ([`crate::element::dequantize`]); applying the
    /// model smooths a coarse readout the same way. Absent: the readings
    /// are used as logged.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub temperature_step_c: Option<f64>,
    /// Per channel.
    pub channels: Vec<ChannelModel>,
    /// Every IMU instance of a log fitted at once (`tcal fit --instance
    /// all`), each a whole model with its `instance`. The fields above are
    /// the first instance's, so a reader of one-instance models still finds
    /// a whole model; empty for a model of one sensor.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub instances: Vec<Model>,
}

impl Model {
    /// A model holding every instance in `each` (at least one, in the log's
    /// order): the first's fields at the top, all of them in `instances`.
    pub fn of_instances(each: Vec<Model>) -> Option<Model> {
        let first = each.first()?.clone();
        Some(Model {
            instances: each,
            ..first
        })
    }

    /// The model of each sensor: its instances, or the model itself.
    pub fn sensors(&self) -> Vec<&Model> {
        if self.instances.is_empty() {
            vec![self]
        } else {
            self.instances.iter().collect()
        }
    }
}

/// The samples of one bin (1 °C by default) and one direction of one run.
struct Bin {
    /// floor(T / width).
    key: i64,
    /// Heating or cooling, on the smoothed temperature.
    heating: bool,
    /// Samples averaged: the bin's weight in the fit.
    n: usize,
    /// Mean temperature, °C.
    t: f64,
    /// Mean of u^j over the samples, j = 0, 1, … up to twice the highest
    /// order: the mean of a polynomial over the bin is exactly the
    /// polynomial of these, however the temperature spreads inside the bin,
    /// and the products u^i·u^j of the normal equations are among them.
    pw: Vec<f64>,
    /// Mean of x·u^j of each channel, j up to the highest order.
    xu: Vec<Vec<f64>>,
    /// Mean dT/dt of the samples that have one; NaN when none has.
    dtdt: f64,
    /// Mean of each channel.
    x: Vec<f64>,
    /// White-noise variance of each channel's mean: the run's sample
    /// variance from first differences, over n.
    var: Vec<f64>,
    /// Index of the first sample, to order bins in time.
    first: usize,
    run: usize,
}

/// Running sums of one bin.
struct BinSum {
    t: f64,
    pw: Vec<f64>,
    xu: Vec<Vec<f64>>,
    rate: f64,
    rated: usize,
    x: Vec<f64>,
    n: usize,
    first: usize,
}

/// Whether sample `i` of `run` counts: its temperature and every channel
/// finite (a gap in any of them leaves the sample out, never a NaN in a sum).
fn usable(run: &Run, i: usize) -> bool {
    run.temp[i].is_finite() && run.channels.iter().all(|c| c.data[i].is_finite())
}

/// The lowest and highest temperature of the samples that count: the range
/// the model is fitted over, the data's own, not that of the bin means.
fn data_range(runs: &[Run]) -> Option<(f64, f64)> {
    let mut range: Option<(f64, f64)> = None;
    for r in runs {
        for (i, &t) in r.temp.iter().enumerate() {
            if usable(r, i) {
                range = Some(range.map_or((t, t), |(a, b)| (a.min(t), b.max(t))));
            }
        }
    }
    range
}

/// The bins of one run, with the powers of u up to `powers`.
fn bins_of(run: &Run, index: usize, width: f64, centre: f64, scale: f64, powers: usize) -> Vec<Bin> {
    use std::collections::BTreeMap;
    let white: Vec<f64> = run.channels.iter().map(|c| white_variance(run, c.data)).collect();
    let rates = branch::dtdt(run.temp, run.rate_hz, RATE_WINDOW_S);
    let heating = branch::heating(run.temp, run.rate_hz);
    // Keyed by bin and direction, so heating and cooling passes through the
    // same temperatures stay apart (that is what the rate term and the
    // hysteresis learn from).
    let mut acc: BTreeMap<(i64, bool), BinSum> = BTreeMap::new();
    let nch = run.channels.len();
    for (i, &t) in run.temp.iter().enumerate() {
        if !usable(run, i) {
            continue;
        }
        let key = ((t / width).floor() as i64, heating[i]);
        let e = acc.entry(key).or_insert_with(|| BinSum {
            t: 0.0,
            pw: vec![0.0; 2 * powers + 1],
            xu: vec![vec![0.0; powers + 1]; nch],
            rate: 0.0,
            rated: 0,
            x: vec![0.0; nch],
            n: 0,
            first: i,
        });
        e.t += t;
        let u = (t - centre) / scale;
        let mut p = 1.0;
        for s in e.pw.iter_mut() {
            *s += p;
            p *= u;
        }
        if rates[i].is_finite() {
            e.rate += rates[i];
            e.rated += 1;
        }
        for (k, c) in run.channels.iter().enumerate() {
            e.x[k] += c.data[i];
            let mut p = c.data[i];
            for s in e.xu[k].iter_mut() {
                *s += p;
                p *= u;
            }
        }
        e.n += 1;
    }
    acc.into_iter()
        .filter(|(_, e)| e.n > 0)
        .map(|((key, heating), e)| {
            let nf = e.n as f64;
            Bin {
                key,
                heating,
                n: e.n,
                t: e.t / nf,
                pw: e.pw.into_iter().map(|v| v / nf).collect(),
                xu: e
                    .xu
                    .into_iter()
                    .map(|c| c.into_iter().map(|v| v / nf).collect())
                    .collect(),
                dtdt: if e.rated > 0 {
                    e.rate / e.rated as f64
                } else {
                    f64::NAN
                },
                x: e.x.into_iter().map(|v| v / nf).collect(),
                var: white.iter().map(|w| w / nf).collect(),
                first: e.first,
                run: index,
            }
        })
        .collect()
}

/// A channel's white-noise variance per sample: half the mean square of
/// the differences of consecutive usable samples, which slow drift and the
/// temperature trend barely touch.
fn white_variance(run: &Run, data: &[f64]) -> f64 {
    let (mut sum, mut count) = (0.0, 0usize);
    for i in 1..data.len() {
        if usable(run, i) && usable(run, i - 1) {
            sum += (data[i] - data[i - 1]).powi(2);
            count += 1;
        }
    }
    if count > 0 { 0.5 * sum / count as f64 } else { 0.0 }
}

/// The fitted mean of `b`.
fn predict(b: &Bin, coeffs: &[f64], rate: Option<f64>) -> f64 {
    let p: f64 = coeffs.iter().zip(&b.pw).map(|(c, u)| c * u).sum();
    p + rate.map_or(0.0, |k| k * b.dtdt)
}

/// Weighted least squares over the samples on u^0..u^order (and the
/// bin's dT/dt), each sample of `bins[i]` weighing `w[i]` over its count
/// ([`bin_weights`]): the normal equations from the bins' mean products.
fn solve(bins: &[&Bin], w: &[f64], k: usize, order: usize, rate: bool) -> Option<(Vec<f64>, Option<f64>)> {
    let cols = order + 1 + usize::from(rate);
    if bins.len() < cols {
        return None;
    }
    let mut a = DMatrix::<f64>::zeros(cols, cols);
    let mut y = DVector::<f64>::zeros(cols);
    for (b, &w) in bins.iter().zip(w) {
        for i in 0..cols {
            for j in 0..cols {
                a[(i, j)] += w * match (i <= order, j <= order) {
                    (true, true) => b.pw[i + j],
                    (true, false) => b.pw[i] * b.dtdt,
                    (false, true) => b.pw[j] * b.dtdt,
                    (false, false) => b.dtdt * b.dtdt,
                };
            }
            y[i] += w * if i <= order { b.xu[k][i] } else { b.x[k] * b.dtdt };
        }
    }
    // Each column scaled to a unit diagonal (dT/dt is a hundredth of u).
    let (sol, _) = dynamics::normal_solve(&a, &y, false)?;
    let coeffs: Vec<f64> = sol.iter().take(order + 1).copied().collect();
    Some((coeffs, rate.then(|| sol[order + 1])))
}

/// Each bin's weight for channel `k`: 1/(σ²/n + τ²), the inverse of its
/// mean's variance with the floor τ² of [`weights::floor_variance`] fitted
/// at `order`, scaled so that the largest is 1. A bin of a few samples
/// never pulls the curve against bins of thousands; where the bias wanders
/// more than white noise explains, long dwells stop outweighing the rest.
/// Data without white noise (a noiseless simulation) weigh by their counts.
fn bin_weights(bins: &[&Bin], k: usize, order: usize, rate: bool) -> Vec<f64> {
    let v: Vec<f64> = bins.iter().map(|b| b.var[k]).collect();
    if v.iter().any(|v| !(v.is_finite() && *v > 0.0)) {
        return bins.iter().map(|b| b.n as f64).collect();
    }
    let params = order + 1 + usize::from(rate);
    let tau2 = weights::floor_variance(&v, params, |w| {
        let (c, r) = solve(bins, w, k, order, rate)?;
        Some(bins.iter().map(|b| b.x[k] - predict(b, &c, r)).collect())
    });
    let w: Vec<f64> = v.iter().map(|v| 1.0 / (v + tau2)).collect();
    let max = w.iter().copied().fold(0.0, f64::max);
    w.iter().map(|w| w / max).collect()
}

fn poly(coeffs: &[f64], u: f64) -> f64 {
    coeffs.iter().rev().fold(0.0, |acc, c| acc * u + c)
}

/// Fits a compensation to one or more runs (the same channels in each):
/// the polynomial of the logged temperature, then (with
/// [`FitOptions::dynamics`]) the element's lag and a hysteresis where the
/// held-out cells show them; a coarse temperature readout is smoothed
/// first.
pub fn fit(runs: &[Run], opts: &FitOptions) -> Result<Model, ThermalError> {
    use std::borrow::Cow;
    let steps: Vec<Option<f64>> = runs.iter().map(|r| element::coarse_step(r.temp)).collect();
    let smoothed: Vec<Cow<[f64]>> = runs
        .iter()
        .zip(&steps)
        .map(|(r, s)| match s {
            Some(_) => Cow::Owned(element::dequantize(r.temp)),
            None => Cow::Borrowed(r.temp),
        })
        .collect();
    let runs: Vec<Run> = runs
        .iter()
        .zip(&smoothed)
        .map(|(r, t)| Run {
            channels: r.channels,
            temp: t,
            rate_hz: r.rate_hz,
        })
        .collect();
    gravity_holds(&runs)?;
    let mut model = fit_polynomial(&runs, opts)?;
    model.temperature_step_c = steps.iter().flatten().copied().reduce(f64::max);
    if opts.dynamics && !opts.rate_term {
        let frame = Frame {
            centre: model.centre_c,
            scale: model.scale_c,
            width: opts.bin_width_c,
            t_min: model.t_min_c,
            t_max: model.t_max_c,
            orders: match opts.order {
                Order::Fixed(o) => (o, o),
                Order::Auto => (0, opts.max_auto_order),
            },
        };
        for (ch, found) in model.channels.iter_mut().zip(dynamics::search(&runs, &frame)) {
            let Some(f) = found else { continue };
            ch.order = f.order;
            ch.coefficients = f.coefficients;
            ch.lag_s = f.lag_s;
            ch.lag_interval_s = f.lag_interval_s;
            ch.hysteresis_term = f.hysteresis;
            ch.residual_rms = f.residual_rms;
            ch.residual_max = f.residual_max;
            ch.cross_validation = f.cross_validation;
            // The branches' difference: what the fitted term gives, where
            // there is one, else what its residuals still show.
            ch.hysteresis = match &ch.hysteresis_term {
                Some(h) => Some(Hysteresis {
                    heating_minus_cooling: h.heating_minus_cooling,
                    interval_95: h.interval_95,
                    bins: f.branches.len(),
                    t_range_c: [model.t_min_c, model.t_max_c],
                }),
                None => hysteresis(&f.branches),
            };
        }
        if opts.firmware_projection {
            let projected = dynamics::project(&runs, &model);
            model = projected;
        }
    }
    model.validate()?;
    Ok(model)
}

/// Largest angle between runs' mean accelerometer vectors a fit accepts,
/// degrees: a few mg/°C over 100 °C turn gravity by a few degrees at most.
pub const MAX_GRAVITY_TURN_DEG: f64 = 10.0;

/// Refuses runs whose mean accelerometer vectors (where the runs carry all
/// three axes) point more than [`MAX_GRAVITY_TURN_DEG`] apart.
fn gravity_holds(runs: &[Run]) -> Result<(), ThermalError> {
    let means: Vec<Option<[f64; 3]>> = runs
        .iter()
        .map(|r| {
            let mut m = [0.0; 3];
            for (axis, slot) in ["accel_x", "accel_y", "accel_z"].iter().zip(m.iter_mut()) {
                let c = r.channels.iter().find(|c| c.name == *axis)?;
                let (s, n) = c
                    .data
                    .iter()
                    .filter(|v| v.is_finite())
                    .fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
                if n == 0 {
                    return None;
                }
                *slot = s / n as f64;
            }
            Some(m)
        })
        .collect();
    let norm = |v: &[f64; 3]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    for i in 0..means.len() {
        for j in i + 1..means.len() {
            let (Some(a), Some(b)) = (means[i], means[j]) else {
                continue;
            };
            let (na, nb) = (norm(&a), norm(&b));
            if !(na > 0.0 && nb > 0.0) {
                continue;
            }
            let cos = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / (na * nb);
            let angle_deg = cos.clamp(-1.0, 1.0).acos().to_degrees();
            if angle_deg > MAX_GRAVITY_TURN_DEG {
                return Err(ThermalError::GravityTurned {
                    first: i + 1,
                    second: j + 1,
                    angle_deg,
                    first_mean: a,
                    second_mean: b,
                });
            }
        }
    }
    Ok(())
}

/// The polynomial of the logged temperature alone.
fn fit_polynomial(runs: &[Run], opts: &FitOptions) -> Result<Model, ThermalError> {
    let Some(first) = runs.first() else {
        return Err(ThermalError::Invalid("no run to fit".into()));
    };
    if !(opts.bin_width_c.is_finite() && opts.bin_width_c > 0.0) {
        return Err(ThermalError::Invalid(format!(
            "bin width {} °C must be positive",
            opts.bin_width_c
        )));
    }
    let names: Vec<&str> = first.channels.iter().map(|c| c.name.as_str()).collect();
    for r in runs {
        let these: Vec<&str> = r.channels.iter().map(|c| c.name.as_str()).collect();
        if these != names {
            return Err(ThermalError::Invalid(format!(
                "runs have different channels: {names:?} and {these:?}"
            )));
        }
        if let Some(c) = r.channels.iter().find(|c| c.data.len() != r.temp.len()) {
            return Err(ThermalError::Invalid(format!(
                "{} has {} samples but the temperature {}",
                c.name,
                c.data.len(),
                r.temp.len()
            )));
        }
    }
    let Some((t_min_c, t_max_c)) = data_range(runs) else {
        return Err(ThermalError::NoTemperature);
    };
    if t_max_c - t_min_c < MIN_SPAN_C {
        return Err(ThermalError::NoSpread {
            span_c: t_max_c - t_min_c,
            min_c: t_min_c,
            max_c: t_max_c,
        });
    }
    let centre = 0.5 * (t_min_c + t_max_c);
    let scale = 0.5 * (t_max_c - t_min_c);
    let t_ref_c = opts.t_ref_c.unwrap_or(centre);
    // Outside the data the polynomial is an extrapolation: every sample
    // would be shifted by p(T_ref) − p(T) with p(T_ref) a guess.
    if !(t_ref_c >= t_min_c && t_ref_c <= t_max_c) {
        return Err(ThermalError::TrefOutsideRange {
            t_ref_c,
            t_min_c,
            t_max_c,
        });
    }
    let powers = match opts.order {
        Order::Fixed(o) => o,
        Order::Auto => opts.max_auto_order,
    };
    let mut bins: Vec<Bin> = runs
        .iter()
        .enumerate()
        .flat_map(|(i, r)| bins_of(r, i, opts.bin_width_c, centre, scale, powers))
        .collect();
    // A rate term needs each bin's dT/dt: a bin of samples isolated by gaps
    // has none, and is left to fits without the term.
    if opts.rate_term {
        bins.retain(|b| b.dtdt.is_finite());
    }
    let all: Vec<&Bin> = bins.iter().collect();
    let needed = |order: usize| order + 1 + usize::from(opts.rate_term);

    let mut channels = Vec::with_capacity(names.len());
    for (k, c) in first.channels.iter().enumerate() {
        // The floor is judged at the highest order tried, whose residuals
        // hold the least misfit.
        let w = bin_weights(&all, k, powers, opts.rate_term);
        let (order, cross_validation) = match opts.order {
            Order::Fixed(o) => (o, Vec::new()),
            Order::Auto => choose_order(&all, &w, k, runs.len(), opts, t_min_c, t_max_c)?,
        };
        let Some((coefficients, rate_coefficient)) = solve(&all, &w, k, order, opts.rate_term) else {
            return Err(ThermalError::TooFewBins {
                bins: all.len(),
                width_c: opts.bin_width_c,
                order,
                needed: needed(order),
            });
        };
        let resid: Vec<f64> = all
            .iter()
            .map(|b| b.x[k] - predict(b, &coefficients, rate_coefficient))
            .collect();
        let total: f64 = all.iter().map(|b| b.n as f64).sum();
        let residual_rms = (all
            .iter()
            .zip(&resid)
            .map(|(b, r)| b.n as f64 * r * r)
            .sum::<f64>()
            / total)
            .sqrt();
        let residual_max = resid.iter().fold(0.0f64, |m, r| m.max(r.abs()));
        let branches: Vec<BranchResidual> = all
            .iter()
            .zip(&resid)
            .map(|(b, &residual)| BranchResidual {
                bin: b.key,
                heating: b.heating,
                n: b.n,
                t: b.t,
                residual,
            })
            .collect();
        channels.push(ChannelModel {
            name: c.name.clone(),
            unit: c.unit.clone(),
            order,
            coefficients,
            rate_coefficient,
            residual_rms,
            residual_max,
            cross_validation,
            hysteresis: hysteresis(&branches),
            lag_s: None,
            lag_interval_s: None,
            hysteresis_term: None,
            projection: None,
        });
    }
    let dtdt_range_c_per_s = opts.rate_term.then(|| {
        bins.iter()
            .fold([f64::INFINITY, f64::NEG_INFINITY], |[lo, hi], b| {
                [lo.min(b.dtdt), hi.max(b.dtdt)]
            })
    });
    let model = Model {
        schema: SCHEMA.to_string(),
        t_ref_c,
        t_min_c,
        t_max_c,
        centre_c: centre,
        scale_c: scale,
        bin_width_c: opts.bin_width_c,
        fitted_on: Vec::new(),
        fitted_on_digests: Vec::new(),
        dtdt_range_c_per_s,
        device_id: None,
        accel_device_id: None,
        instance: None,
        temperature_step_c: None,
        channels,
        instances: Vec::new(),
    };
    // A fit never hands out a model its own loader would refuse (a channel
    // that is not an inertial axis, a coefficient that overflowed, a
    // residual that is not a number).
    model.validate()?;
    Ok(model)
}

/// Cross-validated order: the held-out mean square per order, weighted by
/// the bins' samples, and the smallest order whose excess over the best is
/// within one standard error of that excess (the "one-standard-error rule"
/// of Hastie, Tibshirani & Friedman, *The Elements of Statistical
/// Learning*, 2nd ed., §7.10), so noise does not buy extra coefficients.
fn choose_order(
    bins: &[&Bin],
    w: &[f64],
    k: usize,
    runs: usize,
    opts: &FitOptions,
    t_min_c: f64,
    t_max_c: f64,
) -> Result<(usize, Vec<(usize, f64)>), ThermalError> {
    let mut by_time: Vec<usize> = (0..bins.len()).collect();
    by_time.sort_by_key(|&i| (bins[i].run, bins[i].first));
    let in_time: Vec<&Bin> = by_time.iter().map(|&i| bins[i]).collect();
    let w: Vec<f64> = by_time.iter().map(|&i| w[i]).collect();
    // The bins holding the range's ends always train: held out they would
    // be extrapolated, and the model is never applied beyond its range.
    let edge = |b: &Bin| {
        let key = |t: f64| (t / opts.bin_width_c).floor() as i64;
        b.key == key(t_min_c) || b.key == key(t_max_c)
    };
    // Folds: one per run; in one run, blocks of about a tenth of the bins,
    // dealt round-robin to five folds, so that most held-out bins lie
    // between trained ones.
    let (folds, fold_of): (usize, Vec<Option<usize>>) = if runs > 1 {
        (
            runs,
            in_time.iter().map(|b| (!edge(b)).then_some(b.run)).collect(),
        )
    } else {
        let block = in_time.len().div_ceil(10).max(1);
        (
            5,
            in_time
                .iter()
                .enumerate()
                .map(|(i, b)| (!edge(b)).then_some((i / block) % 5))
                .collect(),
        )
    };
    let too_few = || ThermalError::TooFewBinsToChoose {
        bins: bins.len(),
        width_c: opts.bin_width_c,
    };
    // Per order: each held-out bin's w·e².
    let mut per_order: Vec<(usize, Vec<f64>)> = Vec::new();
    for order in 0..=opts.max_auto_order {
        let mut sq = vec![f64::NAN; in_time.len()];
        let mut ok = true;
        for f in 0..folds {
            let test: Vec<usize> = (0..in_time.len()).filter(|&i| fold_of[i] == Some(f)).collect();
            if test.is_empty() {
                continue;
            }
            let kept: Vec<usize> = (0..in_time.len()).filter(|&i| fold_of[i] != Some(f)).collect();
            let train: Vec<&Bin> = kept.iter().map(|&i| in_time[i]).collect();
            let tw: Vec<f64> = kept.iter().map(|&i| w[i]).collect();
            let Some((c, r)) = solve(&train, &tw, k, order, opts.rate_term) else {
                ok = false;
                break;
            };
            for i in test {
                let b = in_time[i];
                let e = b.x[k] - predict(b, &c, r);
                sq[i] = w[i] * e * e;
            }
        }
        if ok && sq.iter().any(|v| v.is_finite()) && sq.iter().all(|v| v.is_finite() || v.is_nan()) {
            per_order.push((order, sq));
        }
    }
    let held: Vec<usize> = (0..in_time.len()).filter(|&i| fold_of[i].is_some()).collect();
    let total: f64 = held.iter().map(|&i| w[i]).sum();
    let ms = |sq: &[f64]| held.iter().map(|&i| sq[i]).sum::<f64>() / total;
    let Some((_, best)) = per_order
        .iter()
        .filter(|(_, sq)| ms(sq).is_finite())
        .min_by(|a, b| ms(&a.1).total_cmp(&ms(&b.1)))
    else {
        return Err(too_few());
    };
    let chosen = per_order
        .iter()
        .find(|(_, sq)| {
            let d: Vec<f64> = held.iter().map(|&i| sq[i] - best[i]).collect();
            let m = d.len() as f64;
            let mean = d.iter().sum::<f64>() / m;
            let var = d.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (m - 1.0).max(1.0);
            mean * m / total <= (m * var).sqrt() / total
        })
        .map(|(o, _)| *o)
        .ok_or_else(too_few)?;
    let scores = per_order.iter().map(|(o, sq)| (*o, ms(sq).sqrt())).collect();
    Ok((chosen, scores))
}
impl ChannelModel {
    /// The modelled bias at temperature `t` (°C).
    pub fn bias(&self, model: &Model, t: f64) -> f64 {
        poly(&self.coefficients, (t - model.centre_c) / model.scale_c)
    }

    /// The coefficients in powers of (T − t_ref), ascending: what flight
    /// stacks load (PX4's `TC_*_X0..3` around `TC_*_TREF`, ArduPilot's
    /// `INS_TCALn_*_ECOEF` around 35 °C when t_ref is 35).
    pub fn power_coefficients(&self, model: &Model) -> Vec<f64> {
        self.power_coefficients_about(model, model.t_ref_c)
    }

    /// The coefficients in powers of (T − t0), ascending, for any t0: the
    /// same polynomial re-expanded exactly (ArduPilot evaluates about a
    /// fixed 35 °C, whatever the model's reference).
    pub fn power_coefficients_about(&self, model: &Model, t0: f64) -> Vec<f64> {
        // Expand p((T − t0 + t0 − centre)/scale) in (T − t0).
        let n = self.coefficients.len();
        let d = (t0 - model.centre_c) / model.scale_c;
        let mut out = vec![0.0; n];
        for (j, &c) in self.coefficients.iter().enumerate() {
            // c·(v/scale + d)^j with v = T − t_ref.
            let mut binom = 1.0;
            for (i, slot) in out.iter_mut().enumerate().take(j + 1) {
                *slot += c * binom * d.powi((j - i) as i32) / model.scale_c.powi(i as i32);
                binom = binom * (j - i) as f64 / (i + 1) as f64;
            }
        }
        out
    }
}

/// What applying a model did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ApplyReport {
    /// Samples whose temperature was outside the fitted range (their
    /// temperature was clamped to the range's edge, never extrapolated).
    pub out_of_range: usize,
}

impl Model {
    /// The model of `name`.
    pub fn channel(&self, name: &str) -> Option<&ChannelModel> {
        self.channels.iter().find(|c| c.name == name)
    }

    /// Compensates `data` of channel `name` in place:
    /// x − (p(T_e) − p(T_ref)) − k·dT/dt − h, T_e the logged temperature (a
    /// coarse readout smoothed) through the channel's lag, clamped to the
    /// fitted range, h its hysteresis term.
    pub fn apply(
        &self,
        name: &str,
        data: &mut [f64],
        temp: &[f64],
        rate_hz: f64,
    ) -> Result<ApplyReport, ThermalError> {
        // A model built in code has not been through the loader; a reversed
        // range or a zero scale must be an error here, not a panic.
        self.validate()?;
        let ch = self
            .channel(name)
            .ok_or_else(|| ThermalError::MissingChannel(name.to_string()))?;
        if data.len() != temp.len() {
            return Err(ThermalError::Invalid(format!(
                "{} samples but {} temperatures",
                data.len(),
                temp.len()
            )));
        }
        let at_ref = ch.bias(self, self.t_ref_c);
        let rates = ch
            .rate_coefficient
            .map(|_| branch::dtdt(temp, rate_hz, RATE_WINDOW_S));
        // A model without lag, hysteresis or a smoothed readout (every model
        // before them) applies exactly as before: the logged temperature.
        let used: std::borrow::Cow<[f64]> = match self.temperature_step_c {
            Some(_) if element::coarse_step(temp).is_some() => element::dequantize(temp).into(),
            _ => temp.into(),
        };
        let element_t = ch.lag_s.map(|tau| element::lag(&used, rate_hz, tau));
        // The hysteresis follows the element's own rate of change.
        let direction = ch
            .hysteresis_term
            .as_ref()
            .map(|h| h.direction(element_t.as_deref().unwrap_or(&used), rate_hz));
        let mut report = ApplyReport::default();
        for (i, x) in data.iter_mut().enumerate() {
            let t = element_t.as_ref().map_or(used[i], |e| e[i]);
            if !t.is_finite() {
                *x = f64::NAN;
                continue;
            }
            if t < self.t_min_c || t > self.t_max_c {
                report.out_of_range += 1;
            }
            let tc = t.clamp(self.t_min_c, self.t_max_c);
            // dT/dt is clamped to the range the rate term was fitted on: one
            // spike in the temperature would otherwise throw the channel by
            // k times a rate no fit ever saw. A sample isolated by gaps has
            // no dT/dt, and gets the temperature term alone.
            let lag = match (&rates, ch.rate_coefficient, self.dtdt_range_c_per_s) {
                (Some(r), Some(k), Some([lo, hi])) if r[i].is_finite() => k * r[i].clamp(lo, hi),
                _ => 0.0,
            };
            let hyst = match (&ch.hysteresis_term, &direction) {
                (Some(h), Some(d)) if d[i].is_finite() => {
                    h.amplitude((tc - self.centre_c) / self.scale_c) * d[i]
                }
                _ => 0.0,
            };
            *x -= ch.bias(self, tc) - at_ref + lag + hyst;
        }
        Ok(report)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ModelError;

    /// A 20 → 60 °C ramp at 1 Hz whose gyro_x bias is a cubic in T.
    fn ramp() -> (Vec<f64>, Vec<f64>) {
        let temp: Vec<f64> = (0..4000).map(|i| 20.0 + i as f64 * 0.01).collect();
        let x = temp
            .iter()
            .map(|t| 1e-3 + 2e-5 * (t - 40.0) - 3e-7 * (t - 40.0).powi(3))
            .collect();
        (temp, x)
    }

    fn fit_ramp(opts: &FitOptions) -> Result<Model, ThermalError> {
        let (temp, x) = ramp();
        let channels = vec![TcalChannel::new("gyro_x", "rad/s", x.as_slice())];
        fit(
            &[Run {
                channels: &channels,
                temp: &temp,
                rate_hz: 1.0,
            }],
            opts,
        )
    }

    /// Gaussian noise from a fixed seed (Box–Muller on an LCG): the tests
    /// stay deterministic without a generator crate.
    fn noise(n: usize, sigma: f64, seed: u64) -> Vec<f64> {
        let mut state = seed.wrapping_mul(2862933555777941757).wrapping_add(3037000493);
        let mut uniform = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        };
        (0..n)
            .map(|_| {
                let (a, b) = (uniform(), uniform());
                sigma * (-2.0 * a.ln()).sqrt() * (2.0 * std::f64::consts::PI * b).cos()
            })
            .collect()
    }

    fn cubic(t: f64) -> f64 {
        1e-3 + 2e-5 * (t - 40.0) - 3e-7 * (t - 40.0).powi(3)
    }

    fn fit_one(temp: &[f64], x: &[f64], rate_hz: f64, opts: &FitOptions) -> Result<Model, ThermalError> {
        let channels = vec![TcalChannel::new("gyro_x", "rad/s", x)];
        fit(
            &[Run {
                channels: &channels,
                temp,
                rate_hz,
            }],
            opts,
        )
    }

    #[test]
    fn without_a_floor_the_fit_is_least_squares_over_every_sample() {
        // A heating run whose rate falls tenfold, so bins hold from a few
        // dozen to hundreds of samples, the temperature noisy and spread
        // inside each bin: the binned normal equations must give the
        // coefficients of an ordinary least-squares cubic on the samples.
        let n = 20_000;
        let tn = noise(n, 0.05, 7);
        let temp: Vec<f64> = (0..n)
            .map(|i| {
                let f = i as f64 / n as f64;
                20.0 + 30.0 * (1.0 - (-2.3 * f).exp()) / (1.0 - (-2.3f64).exp()) + tn[i]
            })
            .collect();
        let xn = noise(n, 2e-3, 8);
        let x: Vec<f64> = temp.iter().zip(&xn).map(|(t, e)| cubic(*t) + e).collect();
        let opts = FitOptions {
            order: Order::Fixed(3),
            ..FitOptions::default()
        };
        let m = fit_one(&temp, &x, 10.0, &opts).unwrap();
        let (c, s) = (m.centre_c, m.scale_c);
        let a = DMatrix::from_fn(n, 4, |i, j| ((temp[i] - c) / s).powi(j as i32));
        let ols = a
            .svd(true, true)
            .solve(&DVector::from_column_slice(&x), 1e-14)
            .unwrap();
        for (j, (got, want)) in m.channels[0].coefficients.iter().zip(ols.iter()).enumerate() {
            assert!(
                (got - want).abs() <= 1e-9 * want.abs().max(1e-3),
                "u^{j}: {got} vs {want}"
            );
        }
    }

    /// A cooling run, 24 → 16 °C over 2 h at 2 Hz, logged in bursts of 5 s
    /// every 305 s with the gaps written out as NaN rows.
    fn bursty_cooling() -> (Vec<f64>, Vec<f64>) {
        let n = 2 * 7200;
        let e = noise(n, 1e-4, 7);
        (0..n)
            .map(|i| {
                let s = i as f64 / 2.0;
                if s % 305.0 < 5.0 {
                    let t = 16.0 + 8.0 * (-s / 3000.0).exp();
                    (t, 1e-3 + 4e-5 * (t - 20.0) + 3e-6 * (t - 20.0).powi(2) + e[i])
                } else {
                    (f64::NAN, f64::NAN)
                }
            })
            .unzip()
    }

    #[test]
    fn a_bursty_run_with_nan_rows_fits_a_model_its_loader_takes() {
        let (temp, x) = bursty_cooling();
        for order in [Order::Auto, Order::Fixed(2)] {
            let m = fit_one(
                &temp,
                &x,
                2.0,
                &FitOptions {
                    order,
                    ..FitOptions::default()
                },
            )
            .unwrap();
            let c = &m.channels[0];
            assert!(c.residual_rms.is_finite() && c.residual_max.is_finite());
            assert!(c.cross_validation.iter().all(|(_, s)| s.is_finite()));
            let text = serde_json::to_string(&m).unwrap();
            for field in [
                "residual_rms",
                "residual_max",
                "cross_validation",
                "t_min_c",
                "t_max_c",
            ] {
                assert!(!text.contains(&format!("\"{field}\":null")), "{text}");
            }
            let loaded = Model::from_json(&text).unwrap();
            assert_eq!(loaded.channels[0].order, c.order);
        }
        // One NaN row in an otherwise whole run.
        let (mut temp, x) = ramp();
        let mut x: Vec<f64> = x
            .iter()
            .zip(noise(x.len(), 1e-5, 5))
            .map(|(x, e)| x + e)
            .collect();
        temp[1234] = f64::NAN;
        x[2345] = f64::NAN;
        let m = fit_one(&temp, &x, 1.0, &FitOptions::default()).unwrap();
        // The data are a cubic: no lower order follows them.
        assert!(m.channels[0].order >= 3, "{:?}", m.channels[0]);
    }

    #[test]
    fn the_fitted_range_is_the_datas() {
        let (temp, x) = bursty_cooling();
        let m = fit_one(&temp, &x, 2.0, &FitOptions::default()).unwrap();
        let finite = || temp.iter().copied().filter(|t| t.is_finite());
        assert_eq!(m.t_min_c, finite().fold(f64::INFINITY, f64::min));
        assert_eq!(m.t_max_c, finite().fold(f64::NEG_INFINITY, f64::max));
        let mut y = x.clone();
        let report = m.apply("gyro_x", &mut y, &temp, 2.0).unwrap();
        assert_eq!(report.out_of_range, 0, "the fitted run lies inside its own range");
    }

    #[test]
    fn a_few_samples_never_pull_the_curve() {
        // A 20 → 70 °C heating at 4 Hz with white noise, then one lone sample
        // 5 σ off at the far end of a short dip: the old equal-weight bins
        // gave it the weight of a bin of thousands.
        let n = 4 * 2700;
        let sigma = 1e-2;
        let e = noise(n, sigma, 3);
        let temp: Vec<f64> = (0..n).map(|i| 20.0 + 50.0 * i as f64 / n as f64).collect();
        let x: Vec<f64> = temp.iter().zip(&e).map(|(t, e)| cubic(*t) + e).collect();
        let opts = FitOptions {
            order: Order::Fixed(3),
            ..FitOptions::default()
        };
        let m = fit_one(&temp, &x, 4.0, &opts).unwrap();
        let (mut temp2, mut x2) = (temp.clone(), x.clone());
        temp2.push(69.0);
        x2.push(cubic(69.0) + 5.0 * sigma);
        let m2 = fit_one(&temp2, &x2, 4.0, &opts).unwrap();
        let c = m.channel("gyro_x").unwrap();
        let c2 = m2.channel("gyro_x").unwrap();
        for t in [20.0, 35.0, 50.0, 69.0] {
            let moved = (c2.bias(&m2, t) - c.bias(&m, t)).abs();
            assert!(moved < 0.01 * sigma, "{t} °C: {moved}");
            // And the fit is the truth within a few σ/√n.
            let err = (c.bias(&m, t) - cubic(t)).abs();
            assert!(err < 6.0 * sigma / (n as f64).sqrt() * 4.0, "{t} °C: {err}");
        }
        assert!(c.hysteresis.is_none(), "a run that only heats has one branch");
    }

    #[test]
    fn hysteresis_is_reported_only_where_the_branches_differ() {
        // 20 → 60 → 20 °C at 2 Hz; the cooling branch reads `offset` lower.
        let half = 2 * 3600;
        let e = noise(2 * half, 1e-3, 11);
        let temp: Vec<f64> = (0..2 * half)
            .map(|i| {
                let s = i.min(2 * half - i) as f64;
                20.0 + 40.0 * s / half as f64
            })
            .collect();
        for offset in [0.0, 5e-4] {
            let x: Vec<f64> = temp
                .iter()
                .enumerate()
                .map(|(i, t)| cubic(*t) + e[i] - if i > half { offset } else { 0.0 })
                .collect();
            let m = fit_one(&temp, &x, 2.0, &FitOptions::default()).unwrap();
            let h = &m.channels[0].hysteresis;
            if offset == 0.0 {
                assert!(h.is_none(), "{h:?}");
            } else {
                let h = h.as_ref().expect("a 5e-4 offset over 40 bins is seen");
                assert!(h.interval_95[0] < offset && offset < h.interval_95[1], "{h:?}");
                assert!(h.bins > 30);
            }
        }
    }

    #[test]
    fn runs_whose_gravity_turns_are_refused() {
        // A cold run lying on z and a hot one on x, as the BMI270 logs of
        // issue 49 were recorded: 90° apart.
        let temp_a: Vec<f64> = (0..600).map(|i| 10.0 + i as f64 * 0.01).collect();
        let temp_b: Vec<f64> = (0..600).map(|i| 40.0 + i as f64 * 0.01).collect();
        let (z, g, zero) = (vec![9.8; 600], vec![9.8; 600], vec![0.0; 600]);
        let a = vec![
            TcalChannel::new("accel_x", "m/s^2", zero.as_slice()),
            TcalChannel::new("accel_y", "m/s^2", zero.as_slice()),
            TcalChannel::new("accel_z", "m/s^2", z.as_slice()),
        ];
        let b = vec![
            TcalChannel::new("accel_x", "m/s^2", g.as_slice()),
            TcalChannel::new("accel_y", "m/s^2", zero.as_slice()),
            TcalChannel::new("accel_z", "m/s^2", zero.as_slice()),
        ];
        let runs = [
            Run {
                channels: &a,
                temp: &temp_a,
                rate_hz: 1.0,
            },
            Run {
                channels: &b,
                temp: &temp_b,
                rate_hz: 1.0,
            },
        ];
        let e = fit(&runs, &FitOptions::default()).unwrap_err();
        match e {
            ThermalError::GravityTurned { angle_deg, .. } => assert!((angle_deg - 90.0).abs() < 1e-6),
            other => panic!("{other}"),
        }
    }

    #[test]
    fn a_reference_outside_the_fitted_range_is_refused() {
        for t_ref in [500.0, 19.0, f64::NAN, f64::INFINITY] {
            let e = fit_ramp(&FitOptions {
                t_ref_c: Some(t_ref),
                ..FitOptions::default()
            })
            .unwrap_err();
            assert!(matches!(e, ThermalError::TrefOutsideRange { .. }), "{t_ref}: {e}");
        }
        let m = fit_ramp(&FitOptions {
            t_ref_c: Some(25.0),
            ..FitOptions::default()
        })
        .unwrap();
        assert_eq!(m.t_ref_c, 25.0);
    }

    #[test]
    fn auto_order_respects_its_cap() {
        let m = fit_ramp(&FitOptions {
            max_auto_order: 1,
            ..FitOptions::default()
        })
        .unwrap();
        assert_eq!(m.channels[0].order, 1);
        assert!(m.channels[0].cross_validation.iter().all(|(o, _)| *o <= 1));
        let m = fit_ramp(&FitOptions::default()).unwrap();
        assert_eq!(m.channels[0].order, 3, "the data are a cubic");
    }

    #[test]
    fn re_expansion_about_any_point_is_the_same_polynomial() {
        let m = fit_ramp(&FitOptions {
            order: Order::Fixed(3),
            ..FitOptions::default()
        })
        .unwrap();
        let c = &m.channels[0];
        for t0 in [35.0, 20.0, 61.0] {
            let p = c.power_coefficients_about(&m, t0);
            for t in [20.0, 33.3, 47.0, 60.0] {
                let d: f64 = t - t0;
                let v: f64 = p.iter().enumerate().map(|(k, pk)| pk * d.powi(k as i32)).sum();
                assert!(
                    (v - c.bias(&m, t)).abs() < 1e-12,
                    "t0 {t0}, T {t}: {v} vs {}",
                    c.bias(&m, t)
                );
            }
        }
    }

    #[test]
    fn a_reversed_range_is_an_error_not_a_panic() {
        let mut m = fit_ramp(&FitOptions::default()).unwrap();
        std::mem::swap(&mut m.t_min_c, &mut m.t_max_c);
        let mut x = vec![0.0; 3];
        let e = m.apply("gyro_x", &mut x, &[30.0, 40.0, 50.0], 1.0).unwrap_err();
        assert!(
            matches!(e, ThermalError::Model(ModelError::EmptyRange { .. })),
            "{e}"
        );
    }

    #[test]
    fn the_rate_term_is_clamped_to_the_fitted_dtdt_range() {
        // Heating and cooling passes with a lag term: x = k·dT/dt.
        let n = 8000;
        let temp: Vec<f64> = (0..n)
            .map(|i| {
                let ph = i as f64 / n as f64 * 2.0 * std::f64::consts::PI;
                40.0 - 20.0 * ph.cos()
            })
            .collect();
        let rates = branch::dtdt(&temp, 1.0, RATE_WINDOW_S);
        let x: Vec<f64> = temp.iter().zip(&rates).map(|(t, r)| 1e-4 * t + 0.5 * r).collect();
        let channels = vec![TcalChannel::new("accel_x", "m/s^2", x.as_slice())];
        let m = fit(
            &[Run {
                channels: &channels,
                temp: &temp,
                rate_hz: 1.0,
            }],
            &FitOptions {
                order: Order::Fixed(1),
                rate_term: true,
                ..FitOptions::default()
            },
        )
        .unwrap();
        let [lo, hi] = m.dtdt_range_c_per_s.unwrap();
        assert!(lo < 0.0 && hi > 0.0, "{lo} {hi}");
        let k = m.channels[0].rate_coefficient.unwrap();
        assert!((k - 0.5).abs() < 0.05, "{k}");
        // One sample of a steady 40 °C run reads 500 °C.
        let mut t = vec![40.0; 200];
        t[100] = 500.0;
        let mut data = vec![9.8; 200];
        m.apply("accel_x", &mut data, &t, 1.0).unwrap();
        let worst = data.iter().map(|v| (v - 9.8).abs()).fold(0.0, f64::max);
        let bound = k.abs() * lo.abs().max(hi) + 1e-4 * 40.0;
        assert!(worst <= bound, "{worst} > {bound}");
        assert!(worst < 0.1, "{worst} m/s²");
    }
}
