//! Scores a compensation on `imusim::history` truths: fitted on the
//! calibration runs (a heating ramp and a Newton cooling), judged on a
//! held-out run at twice the heating rate with a plateau. Shared by
//! `bench/tcal_dynamics.rs` and `crates/thermal/tests/dynamics.rs`.

use imusim::history::{self, AXES, Recording, Truth};
use thermal::tcal::{FitOptions, Model, Run, TcalChannel, fit};

/// Per axis: what imutherm's model leaves, what a least-squares cubic of
/// the logged temperature leaves (numpy's polyfit of every sample), and
/// what the truth leaves (the floor), each the spread over the held-out
/// run's cells (1 °C of logged temperature, each direction) of the mean
/// residual, the level removed.
#[derive(Debug, Clone)]
pub struct Score {
    pub model: Model,
    pub full: [f64; 6],
    pub cubic: [f64; 6],
    pub floor: [f64; 6],
}

/// The seeds named on the command line, else 1..=`default`.
pub fn seeds(default: u64) -> Vec<u64> {
    let seeds: Vec<u64> = std::env::args().skip(1).filter_map(|a| a.parse().ok()).collect();
    if seeds.is_empty() {
        (1..=default).collect()
    } else {
        seeds
    }
}

pub fn recordings(truth: &Truth, rate_hz: f64, seed: u64) -> (Vec<Recording>, Recording) {
    // IMUTHERM_CALIBRATION=hold: the heating held 20 min at 40 °C.
    let calibration = match std::env::var("IMUTHERM_CALIBRATION").as_deref() {
        Ok("hold") => history::calibration_runs_with_hold(),
        _ => history::calibration_runs(),
    };
    let fitted = calibration
        .iter()
        .enumerate()
        .map(|(i, (start, legs))| history::record(truth, *start, legs, rate_hz, seed * 10 + i as u64))
        .collect();
    let (start, legs) = history::held_out_run();
    (
        fitted,
        history::record(truth, start, &legs, rate_hz, seed * 10 + 7),
    )
}

/// The spread of the cells' mean residual (samples weighted), level removed.
pub fn spread(temp: &[f64], resid: &[f64], rate_hz: f64) -> f64 {
    let heating = thermal::branch::heating(temp, rate_hz);
    let mut cells: std::collections::BTreeMap<(i64, bool), (f64, f64)> = Default::default();
    for i in 0..temp.len() {
        if temp[i].is_finite() && resid[i].is_finite() {
            let e = cells.entry((temp[i].floor() as i64, heating[i])).or_default();
            e.0 += resid[i];
            e.1 += 1.0;
        }
    }
    let n: f64 = cells.values().map(|c| c.1).sum();
    let level = cells.values().map(|c| c.0).sum::<f64>() / n;
    (cells
        .values()
        .map(|(s, m)| m * (s / m - level).powi(2))
        .sum::<f64>()
        / n)
        .sqrt()
}

/// Least-squares cubic of `x` on `t` over every sample (on a scaled
/// temperature, as numpy's polyfit conditions it), evaluated at `at`.
pub fn cubic_fit(t: &[f64], x: &[f64]) -> impl Fn(f64) -> f64 {
    let (lo, hi) = t.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
        (a.min(*v), b.max(*v))
    });
    let (c, s) = (0.5 * (lo + hi), 0.5 * (hi - lo));
    let mut a = nalgebra::Matrix4::<f64>::zeros();
    let mut y = nalgebra::Vector4::<f64>::zeros();
    for (&ti, &xi) in t.iter().zip(x) {
        let u = (ti - c) / s;
        let p = [1.0, u, u * u, u * u * u];
        for i in 0..4 {
            for j in 0..4 {
                a[(i, j)] += p[i] * p[j];
            }
            y[i] += p[i] * xi;
        }
    }
    let coef = a
        .lu()
        .solve(&y)
        .expect("a cubic through a spread of temperatures");
    move |t: f64| {
        let u = (t - c) / s;
        coef[0] + u * (coef[1] + u * (coef[2] + u * coef[3]))
    }
}

pub fn score(truth: &Truth, rate_hz: f64, seed: u64, opts: &FitOptions) -> Score {
    let (fitted, held) = recordings(truth, rate_hz, seed);
    let columns: Vec<Vec<TcalChannel>> = fitted
        .iter()
        .map(|r| {
            AXES.iter()
                .zip(&r.channels)
                .map(|(name, d)| {
                    TcalChannel::new(
                        *name,
                        if name.starts_with("gyro") {
                            "rad/s"
                        } else {
                            "m/s^2"
                        },
                        d,
                    )
                })
                .collect()
        })
        .collect();
    let runs: Vec<Run> = fitted
        .iter()
        .zip(&columns)
        .map(|(r, c)| Run {
            channels: c,
            temp: &r.temp,
            rate_hz: r.rate_hz,
        })
        .collect();
    let model = fit(&runs, opts).expect("a fit of the calibration runs");
    let all_t: Vec<f64> = fitted.iter().flat_map(|r| r.temp.iter().copied()).collect();
    let (mut full, mut cubic, mut floor) = ([0.0; 6], [0.0; 6], [0.0; 6]);
    for (k, name) in AXES.iter().enumerate() {
        let mut left = held.channels[k].clone();
        model
            .apply(name, &mut left, &held.temp, held.rate_hz)
            .expect("apply");
        full[k] = spread(&held.temp, &left, held.rate_hz);
        let all_x: Vec<f64> = fitted
            .iter()
            .flat_map(|r| r.channels[k].iter().copied())
            .collect();
        let p = cubic_fit(&all_t, &all_x);
        let left: Vec<f64> = held.channels[k]
            .iter()
            .zip(&held.temp)
            .map(|(x, t)| x - p(*t))
            .collect();
        cubic[k] = spread(&held.temp, &left, held.rate_hz);
        let left: Vec<f64> = held.channels[k]
            .iter()
            .zip(&held.truth[k])
            .map(|(x, b)| x - b)
            .collect();
        floor[k] = spread(&held.temp, &left, held.rate_hz);
    }
    Score {
        model,
        full,
        cubic,
        floor,
    }
}
