//! Allan curves that behave like real recordings: a gyro's white noise and
//! rate random walk with, on top, what real curves carry and simulators
//! leave out — a periodic disturbance (a 0.6 s bump in the ADEV, as a
//! thermostat or a vibration makes), a tone at a quarter of the sample
//! rate (an aliased rotor or switching frequency), and coarse quantization
//! (0.05 °/s per LSB). The model may not report quantization, and N must
//! come out within 10 % of the truth, or the model must say that no
//! candidate fits the curve (none fits it, or none keeps the rules on it).
//!
//! Truth: N = 0.0084 °/√s (the thesis's 34 °C gyro x), generated as white
//! samples of N·√fs; K = 5e-4 °/s/√s as a random walk of K·√τ0 per sample.

use std::f64::consts::PI;

use allan::noise_terms::{Term, TermEstimate, analyze_terms};

mod common;
use common::Gauss;

const RATE: f64 = 100.0;
const N: f64 = 0.0084;
const K: f64 = 5e-4;

/// 30 min of white noise and random walk, plus `extra(k)` at sample k,
/// quantized to `lsb` when given.
fn gyro(seed: u64, extra: &dyn Fn(usize) -> f64, lsb: Option<f64>) -> Vec<f64> {
    let mut g = Gauss(seed);
    let mut walk = 0.0;
    (0..30 * 60 * RATE as usize)
        .map(|k| {
            walk += K / RATE.sqrt() * g.normal();
            let v = N * RATE.sqrt() * g.normal() + walk + extra(k);
            lsb.map_or(v, |q| (v / q).round() * q)
        })
        .collect()
}

fn check(case: &str, y: &[f64]) {
    let (_, terms) = analyze_terms(y, RATE, 0.95).unwrap();
    let q = terms.model.get(Term::Quantization);
    assert!(q.value().is_none(), "{case}: Q {q:?}");
    match terms.model.get(Term::WhiteNoise) {
        TermEstimate::Value(v) => {
            assert!((v.value / N - 1.0).abs() < 0.10, "{case}: N {} vs {N}", v.value)
        }
        TermEstimate::NotIdentifiable(why) => {
            assert!(
                !terms.model.fits && why.starts_with("no candidate model fits"),
                "{case}: {why}"
            )
        }
    }
}

#[test]
fn a_periodic_bump_near_tau_0_6_s() {
    // A sine's ADEV peaks at τ ≈ 0.371/f: f = 0.62 Hz puts it at 0.6 s.
    let f = 0.62;
    check(
        "bump",
        &gyro(1, &|k| 0.03 * (2.0 * PI * f * k as f64 / RATE).sin(), None),
    );
}

#[test]
fn a_tone_at_a_quarter_of_the_sample_rate() {
    check(
        "tone",
        &gyro(2, &|k| 0.1 * (PI / 2.0 * k as f64 + 0.3).sin(), None),
    );
}

#[test]
fn coarse_quantization_of_0_05_deg_s_per_lsb() {
    check("quantization", &gyro(3, &|_| 0.0, Some(0.05)));
}

#[test]
fn all_three_at_once() {
    let f = 0.62;
    let extra =
        |k: usize| 0.03 * (2.0 * PI * f * k as f64 / RATE).sin() + 0.1 * (PI / 2.0 * k as f64 + 0.3).sin();
    check("bump, tone and quantization", &gyro(4, &extra, Some(0.05)));
}

#[test]
fn a_periodic_bump_is_named_with_its_period_and_amplitude() {
    // The sine of `a_periodic_bump_near_tau_0_6_s`, three times as large:
    // its bump carries most of σ² at τ = 0.32–1.28 s, where no process of
    // the family has one.
    // Ten minutes of it: the bump lies at the short end, far from the
    // random walk.
    let (f, a) = (0.62, 0.09);
    let mut y = gyro(5, &|k| a * (2.0 * PI * f * k as f64 / RATE).sin(), None);
    y.truncate(10 * 60 * RATE as usize);
    let (_, terms) = analyze_terms(&y, RATE, 0.95).unwrap();
    let m = &terms.model;
    let tone = m
        .periodic
        .unwrap_or_else(|| panic!("no periodic term: {} {:?}", m.label, m.defeat));
    assert!((tone.period * f - 1.0).abs() < 0.05, "period {} s", tone.period);
    assert!(
        (tone.amplitude / a - 1.0).abs() < 0.10,
        "amplitude {}",
        tone.amplitude
    );
    match m.get(Term::WhiteNoise) {
        TermEstimate::Value(v) => assert!((v.value / N - 1.0).abs() < 0.10, "N {} vs {N}", v.value),
        other => panic!("N {other:?}"),
    }
    assert!(m.gauss_markov.is_empty(), "a GM stands for the sine: {}", m.label);
}
