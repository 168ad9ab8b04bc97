//! Noise-term identification against curves and series with known terms.

use allan::noise_terms::{Term, TermEstimate, analyze_terms, fit_model, slope_method};
use allan::{NoiseIdMethod, Options, Point, analyze};

mod common;
use common::Gauss;

/// Exact model points at octave taus with a given EDF.
fn model_points(q: f64, n: f64, b: f64, k: f64, r: f64, tau0: f64, count: usize) -> Vec<Point> {
    (0..count)
        .map(|i| {
            let tau = tau0 * 2f64.powi(i as i32);
            let var = [q, n, b, k, r]
                .iter()
                .zip(Term::ALL)
                .map(|(v, t)| v * v * t.variance_basis(tau))
                .sum::<f64>();
            let dev = var.sqrt();
            Point {
                tau,
                m: 1 << i,
                dev,
                n: 100,
                edf: 200.0,
                dev_lo: dev * 0.95,
                dev_hi: dev * 1.05,
                alpha: 0,
                noise_id: NoiseIdMethod::Assumed,
            }
        })
        .collect()
}

fn value(e: &TermEstimate) -> f64 {
    e.value()
        .map_or_else(|| panic!("not identified: {e:?}"), |v| v.value)
}

#[test]
fn fit_recovers_an_exact_model() {
    let pts = model_points(0.0, 1e-3, 5e-4, 1e-5, 0.0, 0.01, 20);
    let fit = fit_model(&pts, 0.95);
    for (term, want) in [
        (Term::WhiteNoise, 1e-3),
        (Term::BiasInstability, 5e-4),
        (Term::RateRandomWalk, 1e-5),
    ] {
        let got = value(fit.get(term));
        assert!(((got - want) / want).abs() < 1e-6, "{term:?}: {got} vs {want}");
    }
    for term in [Term::Quantization, Term::RateRamp] {
        match fit.get(term) {
            TermEstimate::NotIdentifiable(why) => assert!(why.starts_with("not identifiable"), "{why}"),
            v => panic!("{term:?} should not be identified: {v:?}"),
        }
    }
}

#[test]
fn slope_method_reads_the_lines_like_ieee_952() {
    // White noise alone: σ(τ) = N/√τ everywhere, so N is read exactly.
    let pts = model_points(0.0, 2e-3, 0.0, 0.0, 0.0, 0.01, 16);
    let s = slope_method(&pts);
    assert!((value(s.get(Term::WhiteNoise)) - 2e-3).abs() < 1e-12);
    assert!(
        matches!(s.get(Term::RateRandomWalk), TermEstimate::NotIdentifiable(w) if w.contains("longer recording"))
    );
    // With B and K the minimum lies above the flicker floor 0.664·B, so
    // σ_min/0.664 over-reads B a little — the known bias of the method.
    let pts = model_points(0.0, 1e-3, 5e-4, 1e-5, 0.0, 0.01, 20);
    let s = slope_method(&pts);
    let b = value(s.get(Term::BiasInstability));
    assert!(b > 5e-4 && b < 5e-4 * 1.5, "{b}");
    let min = s.sigma_min.unwrap();
    assert!((min.value / allan::noise_terms::flicker_floor() - b).abs() < 1e-15);
    assert!(min.tau.unwrap() > 1.0);
}

/// Coverage of the fit's intervals on white noise plus rate random walk
/// with known N and K: at least 90 % of seeds must bracket the truth.
#[test]
fn fit_intervals_cover_the_truth() {
    let (n_true, k_true) = (2e-3, 2e-4);
    let rate: f64 = 10.0;
    let samples = 2 * 3600 * 10; // 2 h at 10 Hz
    let seeds = 40;
    let (mut hit_n, mut hit_k) = (0, 0);
    for seed in 0..seeds {
        let mut g = Gauss(1000 + seed);
        let mut walk = 0.0;
        let y: Vec<f64> = (0..samples)
            .map(|_| {
                // White: N/√τ0 per sample; RRW: K·√τ0 per step of the walk.
                walk += k_true * (1.0 / rate).sqrt() * g.normal();
                n_true * rate.sqrt() * g.normal() + walk
            })
            .collect();
        let (_, terms) = analyze_terms(&y, rate, 0.95).unwrap();
        let inside = |t: Term, truth: f64| {
            terms
                .fit
                .get(t)
                .value()
                .is_some_and(|v| v.lo <= truth && truth <= v.hi)
        };
        hit_n += usize::from(inside(Term::WhiteNoise, n_true));
        hit_k += usize::from(inside(Term::RateRandomWalk, k_true));
    }
    let (cn, ck) = (hit_n as f64 / seeds as f64, hit_k as f64 / seeds as f64);
    println!(
        "coverage of 95 % intervals over {seeds} seeds: N {:.0} %, K {:.0} %",
        100.0 * cn,
        100.0 * ck
    );
    assert!(cn >= 0.9 && ck >= 0.9, "coverage N {cn}, K {ck}");
}

#[test]
fn a_short_series_says_what_it_would_need() {
    let mut g = Gauss(9);
    let y: Vec<f64> = (0..600).map(|_| 1e-3 * g.normal()).collect();
    let opts = Options {
        rate_hz: 10.0,
        ..Options::default()
    };
    let pts = analyze(&y, &opts).unwrap().points;
    let fit = fit_model(&pts, 0.95);
    assert!(fit.get(Term::WhiteNoise).value().is_some());
    match fit.get(Term::RateRandomWalk) {
        TermEstimate::NotIdentifiable(why) => assert!(why.contains("needs τ up to"), "{why}"),
        v => panic!("K identified from 60 s of white noise: {v:?}"),
    }
}
