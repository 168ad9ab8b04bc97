//! Temperature compensation of the bias: fit, apply, evaluate.
//!
//! The bias of each channel is a polynomial p of temperature, fitted by least
//! squares on a scaled temperature u = (T − centre)/half-span (powers of raw
//! °C are ill-conditioned beyond a cubic), after averaging into temperature
//! bins so that the slow end of a cooling curve, where the run spends most
//! of its samples, does not outweigh the fast end. Optionally a term in
//! dT/dt absorbs thermal lag (the die is warmer than the sensor of the
//! temperature while heating, colder while cooling). The compensation is the
//! thesis's `x_comp = x − (p(T) − p(T_ref))`.
//!
//! `Order::Auto` chooses the order by cross-validation: leave one run out
//! when there are several, else leave out each of five contiguous blocks of
//! the run's bins; the smallest order within 5 % of the best held-out RMS
//! wins, so noise does not buy extra coefficients.

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

use crate::ThermalError;

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
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            order: Order::Auto,
            t_ref_c: None,
            bin_width_c: 1.0,
            rate_term: false,
            max_auto_order: MAX_AUTO_ORDER,
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
    /// RMS of the bin means' residuals, in the channel's unit.
    pub residual_rms: f64,
    /// Largest absolute bin residual.
    pub residual_max: f64,
    /// Held-out RMS per order tried (order, RMS), when chosen automatically.
    pub cross_validation: Vec<(usize, f64)>,
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
    /// Per channel.
    pub channels: Vec<ChannelModel>,
}

/// Temperature-bin means of one run.
struct Bin {
    t: f64,
    dtdt: f64,
    x: Vec<f64>,
    /// Index of the first sample, to order bins in time.
    first: usize,
    run: usize,
}

fn dtdt(temp: &[f64], rate_hz: f64) -> Vec<f64> {
    let h = ((RATE_WINDOW_S * rate_hz / 2.0).round() as usize).max(1);
    let n = temp.len();
    (0..n)
        .map(|i| {
            let (a, b) = (i.saturating_sub(h), (i + h).min(n - 1));
            if b > a {
                (temp[b] - temp[a]) * rate_hz / (b - a) as f64
            } else {
                0.0
            }
        })
        .collect()
}

/// Running sums of one bin.
struct BinSum {
    t: f64,
    rate: f64,
    x: Vec<f64>,
    n: usize,
    first: usize,
}

fn bins_of(run: &Run, index: usize, width: f64) -> Vec<Bin> {
    use std::collections::BTreeMap;
    let rates = dtdt(run.temp, run.rate_hz);
    // Keyed by bin and by the sign of dT/dt, so heating and cooling passes
    // through the same temperatures stay apart (that is what the rate term
    // learns from).
    let mut acc: BTreeMap<(i64, bool), BinSum> = BTreeMap::new();
    let nch = run.channels.len();
    for (i, &t) in run.temp.iter().enumerate() {
        if !t.is_finite() || run.channels.iter().any(|c| !c.data[i].is_finite()) {
            continue;
        }
        let key = ((t / width).floor() as i64, rates[i] >= 0.0);
        let e = acc.entry(key).or_insert_with(|| BinSum {
            t: 0.0,
            rate: 0.0,
            x: vec![0.0; nch],
            n: 0,
            first: i,
        });
        e.t += t;
        e.rate += rates[i];
        for (k, c) in run.channels.iter().enumerate() {
            e.x[k] += c.data[i];
        }
        e.n += 1;
    }
    acc.into_values()
        .filter(|e| e.n > 0)
        .map(|e| {
            let nf = e.n as f64;
            Bin {
                t: e.t / nf,
                dtdt: e.rate / nf,
                x: e.x.into_iter().map(|v| v / nf).collect(),
                first: e.first,
                run: index,
            }
        })
        .collect()
}

/// Least squares of `y` on the columns u^0..u^order (and dT/dt).
fn solve(
    bins: &[&Bin],
    k: usize,
    order: usize,
    rate: bool,
    centre: f64,
    scale: f64,
) -> Option<(Vec<f64>, Option<f64>)> {
    let cols = order + 1 + usize::from(rate);
    if bins.len() < cols {
        return None;
    }
    let a = DMatrix::from_fn(bins.len(), cols, |i, j| {
        let b = bins[i];
        if j <= order {
            ((b.t - centre) / scale).powi(j as i32)
        } else {
            b.dtdt
        }
    });
    let y = DVector::from_iterator(bins.len(), bins.iter().map(|b| b.x[k]));
    let sol = a.svd(true, true).solve(&y, 1e-12).ok()?;
    let coeffs: Vec<f64> = sol.iter().take(order + 1).copied().collect();
    Some((coeffs, rate.then(|| sol[order + 1])))
}

fn poly(coeffs: &[f64], u: f64) -> f64 {
    coeffs.iter().rev().fold(0.0, |acc, c| acc * u + c)
}

/// Fits a compensation to one or more runs (the same channels in each).
pub fn fit(runs: &[Run], opts: &FitOptions) -> Result<Model, ThermalError> {
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
    }
    let bins: Vec<Bin> = runs
        .iter()
        .enumerate()
        .flat_map(|(i, r)| bins_of(r, i, opts.bin_width_c))
        .collect();
    let (t_min_c, t_max_c) = bins
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), bin| {
            (a.min(bin.t), b.max(bin.t))
        });
    if bins.is_empty() {
        return Err(ThermalError::NoTemperature);
    }
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
    let all: Vec<&Bin> = bins.iter().collect();
    let needed = |order: usize| order + 1 + usize::from(opts.rate_term);

    let mut channels = Vec::with_capacity(names.len());
    for (k, c) in first.channels.iter().enumerate() {
        let (order, cross_validation) = match opts.order {
            Order::Fixed(o) => {
                if all.len() < needed(o) {
                    return Err(ThermalError::TooFewBins {
                        bins: all.len(),
                        width_c: opts.bin_width_c,
                        order: o,
                        needed: needed(o),
                    });
                }
                (o, Vec::new())
            }
            Order::Auto => choose_order(
                &bins,
                k,
                runs.len(),
                opts.rate_term,
                opts.max_auto_order,
                centre,
                scale,
            )?,
        };
        let Some((coefficients, rate_coefficient)) = solve(&all, k, order, opts.rate_term, centre, scale)
        else {
            return Err(ThermalError::TooFewBins {
                bins: all.len(),
                width_c: opts.bin_width_c,
                order,
                needed: needed(order),
            });
        };
        let resid: Vec<f64> = all
            .iter()
            .map(|b| {
                b.x[k]
                    - poly(&coefficients, (b.t - centre) / scale)
                    - rate_coefficient.unwrap_or(0.0) * b.dtdt
            })
            .collect();
        let residual_rms = (resid.iter().map(|r| r * r).sum::<f64>() / resid.len() as f64).sqrt();
        let residual_max = resid.iter().fold(0.0f64, |m, r| m.max(r.abs()));
        channels.push(ChannelModel {
            name: c.name.clone(),
            unit: c.unit.clone(),
            order,
            coefficients,
            rate_coefficient,
            residual_rms,
            residual_max,
            cross_validation,
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
        channels,
    };
    // A fit never hands out a model its own loader would refuse (a channel
    // that is not an inertial axis, a coefficient that overflowed).
    model.validate()?;
    Ok(model)
}

/// Cross-validated order: held-out RMS per order, the smallest order within
/// 5 % of the best.
fn choose_order(
    bins: &[Bin],
    k: usize,
    runs: usize,
    rate: bool,
    max_order: usize,
    centre: f64,
    scale: f64,
) -> Result<(usize, Vec<(usize, f64)>), ThermalError> {
    // Folds: one per run, else five contiguous blocks in time of one run.
    let mut order_in_time: Vec<&Bin> = bins.iter().collect();
    order_in_time.sort_by_key(|b| (b.run, b.first));
    let folds: Vec<Vec<usize>> = if runs > 1 {
        (0..runs)
            .map(|r| {
                (0..order_in_time.len())
                    .filter(|&i| order_in_time[i].run == r)
                    .collect()
            })
            .collect()
    } else {
        let n = order_in_time.len();
        (0..5).map(|f| (f * n / 5..(f + 1) * n / 5).collect()).collect()
    };
    let mut scores = Vec::new();
    for order in 0..=max_order {
        let mut sq = 0.0;
        let mut count = 0usize;
        let mut ok = true;
        for fold in &folds {
            let train: Vec<&Bin> = (0..order_in_time.len())
                .filter(|i| !fold.contains(i))
                .map(|i| order_in_time[i])
                .collect();
            match solve(&train, k, order, rate, centre, scale) {
                Some((c, r)) => {
                    for &i in fold {
                        let b = order_in_time[i];
                        let e = b.x[k] - poly(&c, (b.t - centre) / scale) - r.unwrap_or(0.0) * b.dtdt;
                        sq += e * e;
                        count += 1;
                    }
                }
                None => ok = false,
            }
        }
        if ok && count > 0 {
            scores.push((order, (sq / count as f64).sqrt()));
        }
    }
    let best = scores.iter().map(|s| s.1).fold(f64::INFINITY, f64::min);
    let chosen = scores
        .iter()
        .find(|s| s.1 <= 1.05 * best)
        .map(|s| s.0)
        .ok_or(ThermalError::TooFewBins {
            bins: bins.len(),
            width_c: 0.0,
            order: 0,
            needed: 2,
        })?;
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
    /// x − (p(T) − p(T_ref)) − k·dT/dt, with T clamped to the fitted range.
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
        let rates = ch.rate_coefficient.map(|_| dtdt(temp, rate_hz));
        let mut report = ApplyReport::default();
        for (i, (x, &t)) in data.iter_mut().zip(temp).enumerate() {
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
            // k times a rate no fit ever saw.
            let lag = match (&rates, ch.rate_coefficient, self.dtdt_range_c_per_s) {
                (Some(r), Some(k), Some([lo, hi])) => k * r[i].clamp(lo, hi),
                _ => 0.0,
            };
            *x -= ch.bias(self, tc) - at_ref + lag;
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
        let rates = dtdt(&temp, 1.0);
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
