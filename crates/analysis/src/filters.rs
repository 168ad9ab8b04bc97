//! The selected noise model written as the parameters of the filters people
//! paste them into, each with its unit and the formula that gives it, and
//! what each filter's model leaves out.
//!
//! Every filter below takes white rate noise as a standard deviation per
//! prediction step of length Δt and the bias random walk as a rate of
//! change, both multiplied by Δt in its covariance prediction; the
//! continuous terms of IEEE 952 (N in unit/√Hz = unit·√s, K in unit/s/√s)
//! become, for the same growth of variance per step (N²Δt of angle or
//! velocity, K²Δt of bias):
//!
//! - parameter for N = N/√Δt, and parameter for K = K/√Δt.
//!
//! Sources, read in each project's own code:
//! - PX4-Autopilot `src/modules/ekf2/EKF/covariance.cpp`,
//!   `Ekf::predictCovariance`: the delta-angle variance is
//!   `sq(delta_ang_dt * gyro_noise)` (EKF2_GYR_NOISE, rad/s), and the gyro
//!   bias gains `sq(dt * gyro_bias_p_noise)` per step (EKF2_GYR_B_NOISE,
//!   rad/s²); the same for the accelerometer (EKF2_ACC_NOISE, m/s²;
//!   EKF2_ACC_B_NOISE, m/s³). Δt is the filter's averaged update period,
//!   10 ms by default (`FILTER_UPDATE_PERIOD_S` / EKF2_PREDICT_US).
//! - ArduPilot `libraries/AP_NavEKF3/AP_NavEKF3_core.cpp`,
//!   `NavEKF3_core::CovariancePrediction`: `dAngVar = sq(dt * _gyrNoise)`
//!   (EK3_GYRO_P_NSE, rad/s) and
//!   `dAngBiasVar = sq(sq(dt) * _gyroBiasProcessNoise)` on a bias held in
//!   delta-angle units (EK3_GBIAS_P_NSE, rad/s/s), likewise for the
//!   accelerometer (EK3_ACC_P_NSE, m/s/s; EK3_ABIAS_P_NSE, m/s/s/s); Δt is
//!   at least `EKF_TARGET_DT` = 12 ms (`AP_NavEKF3_core.h`). With the bias
//!   in delta-angle units the variance added is dt⁴·p² = dt²·(K²·dt), so
//!   p = K/√Δt as for PX4.
//! - Kalibr (ethz-asl/kalibr wiki, "IMU Noise Model"): continuous-time
//!   `*_noise_density` = N and `*_random_walk` = K, unchanged; written by
//!   [`crate::kalibr`].
//!
//! Neither EKF models quantization, flicker (bias instability) or a
//! Gauss–Markov bias; where the model holds one, [`FilterParams::left_out`]
//! says so. The generic state-space form ([`gauss_markov_state_space`])
//! keeps every term the model holds.

use allan::noise_model::NoiseModel;
use allan::noise_terms::{Chosen, NoiseTerms, Term};
use imu::Quantity;
use serde::Serialize;

/// EKF2's prediction period, s (PX4 `FILTER_UPDATE_PERIOD_S`, the default
/// EKF2_PREDICT_US of 10 000 µs).
pub const PX4_DT_S: f64 = 0.010;

/// EKF3's prediction period, s (ArduPilot `EKF_TARGET_DT`).
pub const ARDUPILOT_DT_S: f64 = 0.012;

/// One filter parameter.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FilterParam {
    /// The parameter's name in the filter.
    pub name: &'static str,
    /// Its value, in `unit`.
    pub value: f64,
    /// Its unit.
    pub unit: &'static str,
    /// How it is had from the noise model.
    pub formula: String,
    /// Where its input came from: the model's value, its interval's upper
    /// end, or an upper bound of a term the model does not hold.
    pub source: String,
}

/// One filter's parameters for one sensor.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FilterParams {
    /// "px4_ekf2" or "ardupilot_ekf3".
    pub filter: &'static str,
    /// The prediction period assumed, s.
    pub dt_s: f64,
    /// The parameters.
    pub params: Vec<FilterParam>,
    /// Terms of the model the filter has no state for.
    pub left_out: Vec<String>,
}

/// A filter's input: a continuous term's value, and where it came from.
type Input = (f64, String);

/// N (the model's value, else its bound) and K (the upper end of the
/// model's interval, else its bound; a filter copes with a random walk
/// overstated, not one understated), with where each came from. A
/// Gauss–Markov term stands in for K where K is not in the model: below
/// its correlation time it is a random walk of K² = 2σ²/T.
fn inputs(terms: &NoiseTerms) -> (Option<Input>, Option<Input>) {
    let n = match terms.choose(Term::WhiteNoise).chosen {
        Chosen::Model(v) => Some((v.value, "N of the model".to_string())),
        Chosen::Bound(b) => Some((b, "upper bound of N (not in the model)".to_string())),
        Chosen::Nothing => None,
    };
    let gm = terms
        .model
        .gauss_markov
        .iter()
        .map(|g| (2.0 * g.sigma.hi.powi(2) / g.tau_c.lo).sqrt())
        .fold(None, |a: Option<f64>, v| Some(a.map_or(v, |a| a.max(v))));
    let k = match (terms.choose(Term::RateRandomWalk).chosen, gm) {
        (Chosen::Model(v), _) => Some((v.hi, "upper end of the model's K interval".to_string())),
        (_, Some(g)) => Some((
            g,
            "the Gauss–Markov term as a random walk, K = σ·√(2/T) (σ at its interval's upper end, T at its lower)"
                .to_string(),
        )),
        (Chosen::Bound(b), None) => Some((b, "upper bound of K (not in the model)".to_string())),
        (Chosen::Nothing, None) => None,
    };
    (n, k)
}

fn left_out(model: &NoiseModel) -> Vec<String> {
    let mut out: Vec<String> = [Term::Quantization, Term::BiasInstability, Term::RateRamp]
        .into_iter()
        .filter(|t| model.get(*t).value().is_some())
        .map(|t| format!("{} ({})", t.symbol(), t.name()))
        .collect();
    out.extend(model.gauss_markov.iter().map(|g| {
        format!(
            "Gauss–Markov σ = {:.3e}, T = {:.1} s (as a random walk in the bias noise)",
            g.sigma.value, g.tau_c.value
        )
    }));
    out
}

/// PX4 EKF2 and ArduPilot EKF3 parameters of one sensor's channel (SI data:
/// rad/s or m/s²); `None` for a channel that is neither gyro nor
/// accelerometer.
pub fn filter_params(quantity: Quantity, terms: &NoiseTerms) -> Option<Vec<FilterParams>> {
    let gyro = match quantity {
        Quantity::AngularRate => true,
        Quantity::Acceleration => false,
        _ => return None,
    };
    let (n, k) = inputs(terms);
    let make = |filter, dt: f64, names: [(&'static str, &'static str); 2]| {
        let mut params = Vec::new();
        for ((name, unit), input, sym) in [(names[0], &n, "N"), (names[1], &k, "K")] {
            if let Some((v, how)) = input {
                params.push(FilterParam {
                    name,
                    value: v / dt.sqrt(),
                    unit,
                    formula: format!("{sym}/√Δt, Δt = {dt} s"),
                    source: how.clone(),
                });
            }
        }
        FilterParams {
            filter,
            dt_s: dt,
            params,
            left_out: left_out(&terms.model),
        }
    };
    let (px4, ardupilot) = if gyro {
        (
            [("EKF2_GYR_NOISE", "rad/s"), ("EKF2_GYR_B_NOISE", "rad/s^2")],
            [("EK3_GYRO_P_NSE", "rad/s"), ("EK3_GBIAS_P_NSE", "rad/s/s")],
        )
    } else {
        (
            [("EKF2_ACC_NOISE", "m/s^2"), ("EKF2_ACC_B_NOISE", "m/s^3")],
            [("EK3_ACC_P_NSE", "m/s/s"), ("EK3_ABIAS_P_NSE", "m/s/s/s")],
        )
    };
    Some(vec![
        make("px4_ekf2", PX4_DT_S, px4),
        make("ardupilot_ekf3", ARDUPILOT_DT_S, ardupilot),
    ])
}

/// One state or white input of the generic model.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StateSpaceTerm {
    /// "white_noise", "random_walk", "gauss_markov", "quantization",
    /// "bias_instability" or "rate_ramp".
    pub kind: &'static str,
    /// Continuous form: ẋ = −x/T + w (T infinite for a random walk), w of
    /// power spectral density `q_c`; for white noise, the measurement
    /// noise density itself.
    pub tau_c_s: Option<f64>,
    /// Spectral density of the driving (or measured) white noise, unit²·s
    /// for white noise, unit²/s for a random walk and a Gauss–Markov
    /// process (2σ²/T).
    pub q_c: Option<f64>,
    /// Stationary standard deviation of a Gauss–Markov state, unit.
    pub sigma: Option<f64>,
    /// What the term is in a filter, or why it has no state.
    pub note: String,
}

/// The model as a linear state-space form: white measurement noise of
/// density N², a random-walk bias state of q_c = K², and one first-order
/// Gauss–Markov state per GM term (φ = e^{−Δt/T}, discrete variance
/// σ²(1 − φ²) per step of Δt; Maybeck, *Stochastic Models* vol. 1, §4.9).
/// Terms with no finite state (flicker, quantization, a ramp) are listed
/// with what a filter can do instead.
pub fn gauss_markov_state_space(model: &NoiseModel) -> Vec<StateSpaceTerm> {
    let mut out = Vec::new();
    let value = |t: Term| model.get(t).value().copied();
    // White noise and the rate random walk: a density, squared.
    for (t, kind, note) in [
        (
            Term::WhiteNoise,
            "white_noise",
            "measurement noise: variance N²/Δt per sample of Δt",
        ),
        (
            Term::RateRandomWalk,
            "random_walk",
            "bias state ẋ = w: variance K²·Δt added per step",
        ),
    ] {
        if let Some(v) = value(t) {
            out.push(StateSpaceTerm {
                kind,
                tau_c_s: None,
                q_c: Some(v.value * v.value),
                sigma: None,
                note: note.to_string(),
            });
        }
    }
    for g in &model.gauss_markov {
        let (s, t) = (g.sigma.value, g.tau_c.value);
        out.push(StateSpaceTerm {
            kind: "gauss_markov",
            tau_c_s: Some(t),
            q_c: Some(2.0 * s * s / t),
            sigma: Some(s),
            note: "bias state ẋ = −x/T + w: x ← e^{−Δt/T}x, variance σ²(1 − e^{−2Δt/T}) added per step"
                .to_string(),
        });
    }
    for (t, kind, note) in [
        (
            Term::BiasInstability,
            "bias_instability",
            "flicker has no finite state; approximate it by one or more Gauss–Markov states \
             with T around the τ of the Allan minimum",
        ),
        (
            Term::Quantization,
            "quantization",
            "white phase noise: add 3Q²/Δt² (Q in unit·s) to the measurement variance at Δt",
        ),
        (
            Term::RateRamp,
            "rate_ramp",
            "a deterministic drift: estimate it, or model the bias as integrated random walk",
        ),
    ] {
        if value(t).is_some() {
            out.push(StateSpaceTerm {
                kind,
                tau_c_s: None,
                q_c: None,
                sigma: value(t).map(|v| v.value),
                note: note.to_string(),
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn px4_parameter_gives_the_white_noise_variance_per_step() {
        // The delta-angle variance PX4 predicts, sq(dt·EKF2_GYR_NOISE),
        // equals the angle random walk's N²·dt over one step.
        let (n, dt) = (1.5e-4, PX4_DT_S);
        let p = n / dt.sqrt();
        assert!(((p * dt).powi(2) / (n * n * dt) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn ekf3_bias_parameter_gives_the_random_walk_variance_per_step() {
        // ArduPilot adds sq(sq(dt)·p) to a bias held in delta-angle units
        // (rate bias × dt): that is dt² times the rate bias's K²·dt.
        let (k, dt) = (2e-6, ARDUPILOT_DT_S);
        let p = k / dt.sqrt();
        assert!(((dt * dt * p).powi(2) / (dt * dt * k * k * dt) - 1.0).abs() < 1e-12);
    }
}
