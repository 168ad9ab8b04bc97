//! Why the full model leaves more than the floor on `imusim::history`
//! truths: least squares on every calibration sample of forms that know
//! more and more of the truth, each judged on the held-out run as
//! `tcal_dynamics` judges (the spread of 1 °C × direction cell means).
//!
//! - `truth`: the generator's own law, c(T_e + X/2·d) with its τ, X and
//!   direction time constant, only the cubic's coefficients fitted;
//! - `model@τ`: the earlier model form p(T_e) + (a0 + a1·u + a2·u²)·tanh(r/s),
//!   r smoothed over τ_d, at the true τ, τ_d and s the best on the held-out run;
//! - `relaxing`: the form now fitted, tanh(r/s) relaxed over τ_d, at the true
//!   τ, at the grid's best, and with τ chosen by the calibration runs' RSS;
//! - `shift`: the hysteresis as a shift H of T_e inside the cubic, at the
//!   true τ and with τ chosen by the calibration RSS;
//! - `fit`: `tcal fit`'s default.
//!
//!     cargo run --release -p thermal --example tcal_dynamics_diagnose -- [SEEDS…]

#[path = "tcal_dynamics_score.rs"]
#[allow(dead_code)]
mod score;

use imusim::history::{AXES, T_MID_C, Truth};
use nalgebra::{DMatrix, DVector};
use thermal::dynamics::{DIRECTION_GRID_S, RATE_SCALES_C_PER_S};
use thermal::element;
use thermal::tcal::FitOptions;

/// The generator's element and direction state, run on the logged
/// temperature (sub-stepped Euler, as imusim::history integrates).
fn truth_state(temp: &[f64], rate_hz: f64, lag_s: f64, dir_s: f64) -> (Vec<f64>, Vec<f64>) {
    let dt = 1.0 / rate_hz;
    let sub = 4;
    let h = dt / sub as f64;
    let (mut el, mut dir) = (temp[0], 0.0f64);
    let (mut e, mut d) = (Vec::new(), Vec::new());
    for i in 0..temp.len() {
        let (a, b) = (temp[i.saturating_sub(1)], temp[i]);
        for j in 0..sub {
            let x = a + (b - a) * (j + 1) as f64 / sub as f64;
            let rate = (x - el) / lag_s;
            el += h * rate;
            dir += h * ((rate / (0.05 / 60.0)).tanh() - dir) / dir_s;
        }
        e.push(el);
        d.push(dir);
    }
    (e, d)
}

/// Least squares of `y` on the rows, then the held-out spread.
fn judge(
    rows: &[Vec<f64>],
    y: &[f64],
    held_rows: &[Vec<f64>],
    held_x: &[f64],
    held_t: &[f64],
    rate_hz: f64,
) -> f64 {
    let p = rows[0].len();
    let mut a = DMatrix::<f64>::zeros(p, p);
    let mut b = DVector::<f64>::zeros(p);
    for (r, &v) in rows.iter().zip(y) {
        for i in 0..p {
            for j in 0..p {
                a[(i, j)] += r[i] * r[j];
            }
            b[i] += r[i] * v;
        }
    }
    let d: Vec<f64> = (0..p).map(|i| a[(i, i)].sqrt().max(1e-300)).collect();
    let s = DMatrix::from_fn(p, p, |i, j| a[(i, j)] / (d[i] * d[j]));
    let rhs = DVector::from_fn(p, |i, _| b[i] / d[i]);
    let svd = s.svd(true, true);
    let top = svd.singular_values.max();
    let c = svd.solve(&rhs, top * 1e-12).expect("solve");
    let left: Vec<f64> = held_rows
        .iter()
        .zip(held_x)
        .map(|(r, x)| {
            x - r
                .iter()
                .zip(c.iter().zip(&d))
                .map(|(a, (c, d))| a * c / d)
                .sum::<f64>()
        })
        .collect();
    let fit_ss: f64 = rows
        .iter()
        .zip(y)
        .map(|(r, v)| {
            (v - r
                .iter()
                .zip(c.iter().zip(&d))
                .map(|(a, (c, d))| a * c / d)
                .sum::<f64>())
            .powi(2)
        })
        .sum();
    LAST_RSS.with(|l| l.set(fit_ss));
    score::spread(held_t, &left, rate_hz)
}

thread_local! {
    /// The in-sample residual sum of the last `judge`.
    static LAST_RSS: std::cell::Cell<f64> = const { std::cell::Cell::new(0.0) };
}

fn last_rss() -> f64 {
    LAST_RSS.with(|l| l.get())
}

/// The model's rows; `relax`: the direction saturated first, then
/// relaxed over `sm` (else the rate smoothed over `sm`, then saturated).
fn model_rows(temp: &[f64], rate_hz: f64, tau: f64, sm: f64, sc: f64, relax: bool) -> Vec<Vec<f64>> {
    let te = element::lag(temp, rate_hz, tau);
    let h: Vec<f64> = if relax {
        let r = element::smoothed_rate(&te, rate_hz, 30.0);
        let sat: Vec<f64> = r.iter().map(|r| (r / sc).tanh()).collect();
        element::lag(&sat, rate_hz, sm)
    } else {
        let r = element::smoothed_rate(&te, rate_hz, sm);
        r.iter().map(|r| (r / sc).tanh()).collect()
    };
    te.iter()
        .zip(&h)
        .map(|(t, &h)| {
            let u = (t - T_MID_C) / 20.0;
            vec![1.0, u, u * u, u * u * u, h, h * u, h * u * u]
        })
        .collect()
}

fn main() {
    let seeds = score::seeds(4);
    let rate = 2.0;
    println!(
        "| seed | axis | floor | truth / floor | model@τ / floor | relaxing@τ / floor | relaxing@best grid τ / floor (τ, s) | shift@τ / floor | relaxing, τ by calibration RSS: held-out / floor (τ) | shift, τ by calibration RSS (τ) | fit / floor | fit's τ, s (truth) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for &seed in &seeds {
        let truth = Truth::draw(seed);
        let (fitted, held) = score::recordings(&truth, rate, seed);
        let s = score::score(&truth, rate, seed, &FitOptions::default());
        let state = |t: &[f64]| truth_state(t, rate, truth.lag_s, truth.direction_s);
        let truth_rows = |t: &[f64]| -> Vec<Vec<f64>> {
            let (e, d) = state(t);
            e.iter()
                .zip(&d)
                .map(|(e, d)| {
                    let x = (e + 0.5 * truth.hysteresis_c * d - T_MID_C) / 20.0;
                    vec![1.0, x, x * x, x * x * x, (e - T_MID_C) / 20.0]
                })
                .collect()
        };
        for (k, axis) in AXES.iter().enumerate() {
            let y: Vec<f64> = fitted
                .iter()
                .flat_map(|r| r.channels[k].iter().copied())
                .collect();
            let rows: Vec<Vec<f64>> = fitted.iter().flat_map(|r| truth_rows(&r.temp)).collect();
            let t_truth = judge(
                &rows,
                &y,
                &truth_rows(&held.temp),
                &held.channels[k],
                &held.temp,
                rate,
            );
            let mut best = [f64::INFINITY; 3];
            for (e, relax) in [false, true].into_iter().enumerate() {
                for &sm in &DIRECTION_GRID_S {
                    for &sc in &RATE_SCALES_C_PER_S {
                        let rows: Vec<Vec<f64>> = fitted
                            .iter()
                            .flat_map(|r| model_rows(&r.temp, rate, truth.lag_s, sm, sc, relax))
                            .collect();
                        let hr = model_rows(&held.temp, rate, truth.lag_s, sm, sc, relax);
                        best[e] = best[e].min(judge(&rows, &y, &hr, &held.channels[k], &held.temp, rate));
                    }
                }
            }
            // The relaxing form, τ on the fit's grid (the best held-out).
            let mut at = (f64::INFINITY, 0.0);
            let mut by_rss = (f64::INFINITY, 0.0, 0.0);
            for &tau in &thermal::dynamics::LAG_GRID_S {
                for &sm in &DIRECTION_GRID_S {
                    let sc = RATE_SCALES_C_PER_S[0];
                    let rows: Vec<Vec<f64>> = fitted
                        .iter()
                        .flat_map(|r| model_rows(&r.temp, rate, tau, sm, sc, true))
                        .collect();
                    let hr = model_rows(&held.temp, rate, tau, sm, sc, true);
                    let v = judge(&rows, &y, &hr, &held.channels[k], &held.temp, rate);
                    if v < at.0 {
                        at = (v, tau);
                    }
                    if last_rss() < by_rss.0 {
                        by_rss = (last_rss(), tau, v);
                    }
                }
            }
            best[2] = at.0;
            // The hysteresis as a shift H of the element's temperature
            // inside the polynomial, at the true τ, H on a grid.
            let mut shift = f64::INFINITY;
            let mut shift_rss = (f64::INFINITY, 0.0, 0.0);
            let taus: Vec<f64> = thermal::dynamics::LAG_GRID_S
                .iter()
                .copied()
                .chain([truth.lag_s])
                .collect();
            for (sm, tau) in DIRECTION_GRID_S
                .iter()
                .flat_map(|&s| taus.iter().map(move |&t| (s, t)))
            {
                let rows_of = |t: &[f64], hh: f64| -> Vec<Vec<f64>> {
                    let te = element::lag(t, rate, tau);
                    let d = thermal::dynamics::direction(&te, rate, 30.0, RATE_SCALES_C_PER_S[0], Some(sm));
                    te.iter()
                        .zip(&d)
                        .map(|(e, d)| {
                            let x = (e + hh * d - T_MID_C) / 20.0;
                            vec![1.0, x, x * x, x * x * x, (e - T_MID_C) / 20.0]
                        })
                        .collect()
                };
                for j in 0..=16 {
                    let hh = 0.5 * j as f64;
                    for sign in [1.0, -1.0] {
                        let rows: Vec<Vec<f64>> =
                            fitted.iter().flat_map(|r| rows_of(&r.temp, sign * hh)).collect();
                        let v = judge(
                            &rows,
                            &y,
                            &rows_of(&held.temp, sign * hh),
                            &held.channels[k],
                            &held.temp,
                            rate,
                        );
                        if tau == truth.lag_s {
                            shift = shift.min(v);
                        } else if last_rss() < shift_rss.0 {
                            shift_rss = (last_rss(), tau, v);
                        }
                    }
                }
            }
            let f = s.floor[k];
            println!(
                "| {seed} | {} | {:.2e} | {:.2} | {:.2} | {:.2} | {:.2} ({:.0}) | {:.2} | {:.2} ({:.0}) | {:.2} ({:.0}) | {:.2} | {} ({:.0}) |",
                axis,
                f,
                t_truth / f,
                best[0] / f,
                best[1] / f,
                best[2] / f,
                at.1,
                shift / f,
                by_rss.2 / f,
                by_rss.1,
                shift_rss.2 / f,
                shift_rss.1,
                s.full[k] / f,
                s.model.channels[k]
                    .lag_s
                    .map_or("none".into(), |l| format!("{l:.0}")),
                truth.lag_s
            );
        }
    }
}
