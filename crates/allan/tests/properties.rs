//! Laws every statistic must obey, and the thesis's own two formulas.

use allan::{DataType, Options, PhaseSeries, Stat, TauSpec, analyze, stats};
use proptest::prelude::*;

mod common;
use common::Gauss;

/// The thesis slide, non-overlapped: σ² = 1/(2(M−1)) Σ (ȳ_{i+1} − ȳ_i)² over
/// the M averages of m samples.
fn thesis_non_overlapped(y: &[f64], m: usize) -> f64 {
    let avgs: Vec<f64> = y
        .chunks_exact(m)
        .map(|c| c.iter().sum::<f64>() / m as f64)
        .collect();
    let s: f64 = avgs.windows(2).map(|w| (w[1] - w[0]).powi(2)).sum();
    (s / (2.0 * (avgs.len() - 1) as f64)).sqrt()
}

/// The thesis slide, overlapped:
/// σ² = 1/(2m²(M−2m+1)) Σ_{j=1}^{M−2m+1} (Σ_{i=j}^{j+m−1} (y_{i+m} − y_i))².
fn thesis_overlapped(y: &[f64], m: usize) -> f64 {
    let big_m = y.len();
    let terms = big_m - 2 * m + 1;
    let s: f64 = (0..terms)
        .map(|j| (j..j + m).map(|i| y[i + m] - y[i]).sum::<f64>().powi(2))
        .sum();
    (s / (2.0 * (m * m) as f64 * terms as f64)).sqrt()
}

fn rel(a: f64, b: f64) -> f64 {
    ((a - b) / b).abs()
}

#[test]
fn thesis_formulas_equal_adev_and_oadev() {
    let y = Gauss::series(7, 1000, 0.01);
    let s = PhaseSeries::new(&y, DataType::Freq, 1.0).unwrap();
    for m in [1, 2, 3, 7, 16, 50, 200] {
        let a = stats::adev(&s, m).unwrap().dev;
        // The slide's non-overlapped form uses only whole blocks, as ADEV does.
        assert!(rel(a, thesis_non_overlapped(&y, m)) < 1e-12, "adev m={m}");
        let o = stats::oadev(&s, m).unwrap().dev;
        assert!(rel(o, thesis_overlapped(&y, m)) < 1e-12, "oadev m={m}");
    }
}

#[test]
fn constant_gives_zero() {
    let y = vec![3.25; 500];
    // All but the O(N·m) family, whose modules hold this law themselves.
    for stat in Stat::ALL
        .into_iter()
        .filter(|s| !matches!(s, Stat::Mtotdev | Stat::Ttotdev | Stat::Htotdev | Stat::Theo1))
    {
        let c = analyze(
            &y,
            &Options {
                stat,
                ..Options::default()
            },
        )
        .unwrap();
        assert!(!c.points.is_empty());
        for p in &c.points {
            assert!(p.dev.abs() < 1e-12, "{stat} at m={}: {}", p.m, p.dev);
        }
    }
}

#[test]
fn white_rate_noise_follows_s_over_sqrt_tau() {
    // White FM of standard deviation s at 100 Hz: σ(τ) = s·√(τ0/τ).
    let s = 0.02;
    let rate = 100.0;
    let y = Gauss::series(11, 200_000, s);
    let opts = Options {
        rate_hz: rate,
        ..Options::default()
    };
    let c = analyze(&y, &opts).unwrap();
    let mut outside = 0;
    for p in &c.points {
        let theory = s * (1.0 / rate / p.tau).sqrt();
        if theory < p.dev_lo || theory > p.dev_hi {
            outside += 1;
        }
        // Independent of the interval: within 4 standard errors.
        let se = p.dev / (2.0 * p.edf).sqrt();
        assert!(
            (p.dev - theory).abs() < 4.0 * se,
            "tau {}: {} vs {theory}",
            p.tau,
            p.dev
        );
    }
    // 68.3 % intervals: about a third of the points may miss; most must hit.
    assert!(
        outside * 2 < c.points.len(),
        "{outside} of {} outside",
        c.points.len()
    );
}

#[test]
fn gaps_in_rate_data_skip_exactly_the_terms_that_cross_them() {
    let mut y = Gauss::series(3, 600, 1.0);
    for i in [50, 51, 300, 599] {
        y[i] = f64::NAN;
    }
    let s = PhaseSeries::new(&y, DataType::Freq, 1.0).unwrap();
    assert_eq!(s.nan_samples(), 4);
    assert_eq!(s.trimmed_samples(), 1);
    let body = &y[..599];
    let mean = {
        let v: Vec<f64> = body.iter().copied().filter(|v| !v.is_nan()).collect();
        v.iter().sum::<f64>() / v.len() as f64
    };
    for m in [1, 4, 10] {
        // Direct definition: differences of adjacent m-sample averages, skipped
        // when either average touches a gap.
        let mut sum = 0.0;
        let mut n = 0;
        for j in 0..=body.len() - 2 * m {
            let w = &body[j..j + 2 * m];
            if w.iter().any(|v| v.is_nan()) {
                continue;
            }
            let a: f64 = w[..m].iter().map(|v| v - mean).sum::<f64>() / m as f64;
            let b: f64 = w[m..].iter().map(|v| v - mean).sum::<f64>() / m as f64;
            sum += (b - a).powi(2);
            n += 1;
        }
        let want = (sum / (2.0 * n as f64)).sqrt();
        let got = stats::oadev(&s, m).unwrap();
        assert_eq!(got.n, n, "m={m}");
        assert!(rel(got.dev, want) < 1e-12, "m={m}");
    }
    // MDEV skips whole windows of 3m points too.
    let md = stats::mdev(&s, 4).unwrap();
    let clean_windows = (0..=body.len() + 1 - 12)
        .filter(|&j| !body[j..(j + 11).min(body.len())].iter().any(|v| v.is_nan()))
        .count();
    assert_eq!(md.n, clean_windows);
    // Total deviations refuse gaps instead of guessing.
    let err = analyze(
        &y,
        &Options {
            stat: Stat::Totdev,
            ..Options::default()
        },
    )
    .unwrap_err();
    assert!(err.to_string().contains("gaps"), "{err}");
}

#[test]
fn gaps_in_phase_data_follow_gradev() {
    let mut x: Vec<f64> = Gauss::series(5, 400, 1.0)
        .iter()
        .scan(0.0, |a, v| {
            *a += v;
            Some(*a)
        })
        .collect();
    x[100] = f64::NAN;
    x[250] = f64::NAN;
    let s = PhaseSeries::new(&x, DataType::Phase, 1.0).unwrap();
    for m in [1, 3, 8] {
        // AllanTools gradev: a term needs its three phase points, nothing more.
        let mut sum = 0.0;
        let mut n = 0;
        for j in 0..x.len() - 2 * m {
            let v = x[j + 2 * m] - 2.0 * x[j + m] + x[j];
            if v.is_finite() {
                sum += v * v;
                n += 1;
            }
        }
        let want = (sum / (2.0 * n as f64 * (m * m) as f64)).sqrt();
        let got = stats::oadev(&s, m).unwrap();
        assert_eq!(got.n, n);
        assert!(rel(got.dev, want) < 1e-12);
    }
}

#[test]
fn too_short_and_unusable_taus_are_errors_not_nan() {
    let err = analyze(&[1.0, 2.0], &Options::default()).unwrap_err();
    assert!(err.to_string().contains("needs at least"), "{err}");
    let opts = Options {
        taus: TauSpec::List(vec![1e6]),
        ..Options::default()
    };
    let err = analyze(&Gauss::series(1, 100, 1.0), &opts).unwrap_err();
    assert!(err.to_string().contains("no requested tau"), "{err}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn scaling_the_data_scales_every_deviation(seed in 0u64..1000, c in 1e-6f64..1e6, offset in -1e3f64..1e3) {
        let y = Gauss::series(seed, 256, 1.0);
        let scaled: Vec<f64> = y.iter().map(|v| c * v + offset).collect();
        for stat in [Stat::Adev, Stat::Oadev, Stat::Mdev, Stat::Tdev, Stat::Hdev, Stat::Ohdev, Stat::Totdev] {
            let opts = Options { stat, ..Options::default() };
            let a = analyze(&y, &opts).unwrap();
            let b = analyze(&scaled, &opts).unwrap();
            prop_assert_eq!(a.points.len(), b.points.len());
            for (p, q) in a.points.iter().zip(&b.points) {
                prop_assert!(rel(q.dev, c * p.dev) < 1e-8, "{} m={}: {} vs {}", stat, p.m, q.dev, c * p.dev);
                prop_assert!(rel(q.dev_hi, c * p.dev_hi) < 1e-8);
            }
        }
    }
}

#[test]
fn blocked_sweep_equals_tau_by_tau() {
    let y = Gauss::series(21, 20_000, 1.0);
    let s = PhaseSeries::new(&y, DataType::Freq, 10.0).unwrap();
    let ms: Vec<usize> = vec![1, 2, 3, 4, 8, 16, 100, 1024, 4096, 6000, 9999, 20_000];
    for stat in [Stat::Oadev, Stat::Ohdev] {
        let many = stats::compute_many(stat, &s, &ms);
        for (&m, got) in ms.iter().zip(&many) {
            let want = stats::compute(stat, &s, m);
            match (got, want) {
                (Some(g), Some(w)) => {
                    assert_eq!(g.n, w.n, "{stat} m={m}");
                    assert!(rel(g.dev, w.dev) < 1e-12, "{stat} m={m}: {} vs {}", g.dev, w.dev);
                }
                (None, None) => {}
                other => panic!("{stat} m={m}: {other:?}"),
            }
        }
    }
}

/// Coverage of the 95 % interval at the τ where noise identification has
/// few points: white FM of 2000 samples, 400 seeds, at m = 128 and 256
/// (15 and 7 averages, so B1 decides). The true ADEV is σ/√m. An interval
/// built on a noise type misread upwards (B1 taking white FM for a PM
/// noise) is several times too narrow and misses far more than 5 %.
#[test]
fn intervals_keep_their_coverage_where_b1_identifies_the_noise() {
    let seeds = 400;
    let mut missed = [0usize; 2];
    let mut capped = 0;
    for seed in 0..seeds {
        let y = Gauss::series(1000 + seed, 2000, 1.0);
        let c = analyze(
            &y,
            &Options {
                confidence: 0.95,
                taus: TauSpec::List(vec![1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0, 128.0, 256.0]),
                ..Options::default()
            },
        )
        .unwrap();
        for (k, m) in [128usize, 256].into_iter().enumerate() {
            let p = c.points.iter().find(|p| p.m == m).unwrap();
            let truth = 1.0 / (m as f64).sqrt();
            if !(p.dev_lo < truth && truth < p.dev_hi) {
                missed[k] += 1;
            }
            capped += usize::from(p.noise_id == allan::NoiseIdMethod::Capped);
        }
    }
    eprintln!("missed at m = 128, 256: {missed:?} of {seeds}; {capped} capped");
    // Binomial(400, 0.05): mean 20, sd 4.4; 38 is 4 sd above.
    for (k, miss) in missed.into_iter().enumerate() {
        assert!(miss <= 38, "m = {}: {miss} of {seeds} missed", [128, 256][k]);
    }
}
