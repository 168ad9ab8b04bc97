//! The Schuler-aware prediction against a numerical propagation of the
//! single-channel error dynamics (position, velocity, tilt and, for the
//! random walks and biases, the bias as a state): the covariance equation
//! Ṗ = A·P + P·Aᵀ + Q integrated by Runge–Kutta, which shares nothing with
//! the closed forms but the model (Titterton & Weston, 2nd ed., ch. 12).

use ins::prediction::{AxisNoise, NoiseModel, PredictedTerm, PredictionSetup, predict};

type M = [[f64; 5]; 5];

/// The dynamics of [x, v, φ, b_f, b_ω]: ẋ = v, v̇ = −g·φ + b_f (+ white
/// specific force), φ̇ = v/R + b_ω (+ white rate), the biases constant or
/// random walks.
fn dynamics(g: f64, r: f64) -> M {
    let mut a = [[0.0; 5]; 5];
    a[0][1] = 1.0;
    a[1][2] = -g;
    a[1][3] = 1.0;
    a[2][1] = 1.0 / r;
    a[2][4] = 1.0;
    a
}

fn derivative(a: &M, p: &M, q: &M) -> M {
    let mut d = *q;
    for i in 0..5 {
        for j in 0..5 {
            for k in 0..5 {
                d[i][j] += a[i][k] * p[k][j] + p[i][k] * a[j][k];
            }
        }
    }
    d
}

fn add(p: &M, d: &M, h: f64) -> M {
    std::array::from_fn(|i| std::array::from_fn(|j| p[i][j] + h * d[i][j]))
}

/// The position variance at each of `times` (ascending), from `p0`.
fn propagate(g: f64, r: f64, mut p: M, q: M, times: &[f64]) -> Vec<f64> {
    let a = dynamics(g, r);
    let h: f64 = 0.25;
    let mut t = 0.0;
    let mut out = Vec::new();
    for &stop in times {
        while t < stop - 1e-9 {
            let step = h.min(stop / 400.0).min(stop - t);
            let k1 = derivative(&a, &p, &q);
            let k2 = derivative(&a, &add(&p, &k1, step / 2.0), &q);
            let k3 = derivative(&a, &add(&p, &k2, step / 2.0), &q);
            let k4 = derivative(&a, &add(&p, &k3, step), &q);
            p = std::array::from_fn(|i| {
                std::array::from_fn(|j| {
                    p[i][j] + step / 6.0 * (k1[i][j] + 2.0 * (k2[i][j] + k3[i][j]) + k4[i][j])
                })
            });
            t += step;
        }
        out.push(p[0][0]);
    }
    out
}

const LATITUDE: f64 = 45.0;
const ALIGN_S: f64 = 10.0;
const TIMES: [f64; 6] = [1.0, 60.0, 600.0, 1800.0, 3600.0, 6000.0];

fn one(n: f64, b: f64, k: f64) -> [AxisNoise; 3] {
    [AxisNoise { n, b, k }; 3]
}

/// The propagated DRMS of one term: both level axes, north through the
/// meridian radius, west through the prime-vertical radius.
fn propagated(g: f64, initial: impl Fn(&mut M), q: impl Fn(&mut M)) -> Vec<f64> {
    let (meridian, prime) = earth::radii(LATITUDE.to_radians());
    let (mut p0, mut qm) = ([[0.0; 5]; 5], [[0.0; 5]; 5]);
    initial(&mut p0);
    q(&mut qm);
    let north = propagate(g, meridian, p0, qm, &TIMES);
    let west = propagate(g, prime, p0, qm, &TIMES);
    north.iter().zip(&west).map(|(a, b)| (a + b).sqrt()).collect()
}

fn check(name: &str, model: NoiseModel, term: PredictedTerm, want: &[f64]) {
    let g = earth::normal_gravity(LATITUDE.to_radians());
    let setup = PredictionSetup::level(g, ALIGN_S, true).with_latitude(Some(LATITUDE));
    for (t, w) in TIMES.iter().zip(want) {
        let p = predict(&model, &setup, *t);
        let got = p.terms.iter().find(|(k, _)| *k == term).unwrap().1;
        assert!(
            (got / w - 1.0).abs() < 1e-6,
            "{name} at {t} s: closed form {got} m, propagated {w} m"
        );
    }
}

#[test]
fn every_term_with_the_schuler_loop_is_the_propagated_one() {
    let g = earth::normal_gravity(LATITUDE.to_radians());
    let (na, ng, ka, kg) = (3e-3, 1.5e-4, 2e-4, 3e-6);
    let model = |gyro, accel| NoiseModel { gyro, accel };
    let zero = one(0.0, 0.0, 0.0);

    let want = propagated(g, |_| {}, |q| q[1][1] = na * na);
    check(
        "white specific force",
        model(zero, one(na, 0.0, 0.0)),
        PredictedTerm::AccelWhiteNoise,
        &want,
    );

    // The levelling error is an initial tilt of the window mean's error / g.
    let want = propagated(g, |p| p[2][2] = na * na / ALIGN_S / (g * g), |_| {});
    check(
        "levelling",
        model(zero, one(na, 0.0, 0.0)),
        PredictedTerm::Levelling,
        &want,
    );

    let want = propagated(g, |_| {}, |q| q[2][2] = ng * ng);
    check(
        "white rate",
        model(one(ng, 0.0, 0.0), zero),
        PredictedTerm::GyroWhiteNoise,
        &want,
    );

    // The gyro's window mean leaves a constant bias of variance N_g²/T_a.
    let want = propagated(g, |p| p[4][4] = ng * ng / ALIGN_S, |_| {});
    check(
        "gyro bias from alignment",
        model(one(ng, 0.0, 0.0), zero),
        PredictedTerm::GyroBiasFromAlignment,
        &want,
    );

    // A walk, and its lead on the window's mean when navigation starts
    // (variance K²·T_a/3: the walk's spread about its mean over the window).
    let want = propagated(g, |p| p[4][4] = kg * kg * ALIGN_S / 3.0, |q| q[4][4] = kg * kg);
    check(
        "rate random walk",
        model(one(0.0, 0.0, kg), zero),
        PredictedTerm::GyroRateRandomWalk,
        &want,
    );

    let want = propagated(g, |p| p[3][3] = ka * ka * ALIGN_S / 3.0, |q| q[3][3] = ka * ka);
    check(
        "specific-force random walk",
        model(zero, one(0.0, 0.0, ka)),
        PredictedTerm::AccelRateRandomWalk,
        &want,
    );
}

#[test]
fn without_a_latitude_the_prediction_keeps_the_flat_earth_law() {
    // The gyro white term at an hour: g·N_g·t^{5/2}/√20 on each axis.
    let model = NoiseModel {
        gyro: one(1.5e-4, 0.0, 0.0),
        accel: one(0.0, 0.0, 0.0),
    };
    let g = earth::STANDARD_GRAVITY;
    let p = predict(&model, &PredictionSetup::level(g, ALIGN_S, true), 3600.0);
    let got = p
        .terms
        .iter()
        .find(|(k, _)| *k == PredictedTerm::GyroWhiteNoise)
        .unwrap()
        .1;
    let want = 2f64.sqrt() * g * 1.5e-4 * 3600f64.powf(2.5) / 20f64.sqrt();
    assert!((got / want - 1.0).abs() < 1e-12);
}

/// The spectral integral of the bias instability, fed a white PSD (2N²
/// one-sided), must give the white term plus the window mean's bias: the
/// closed forms of a different derivation (to the 1e-5 the white PSD's
/// 1/f² tail leaves past the last piece).
#[test]
fn the_spectral_integral_of_a_white_noise_is_its_closed_form() {
    use ins::spectral::{Kernel, variance};
    let g = earth::normal_gravity(LATITUDE.to_radians());
    let (na, ng) = (3e-3, 1.5e-4);
    let model = NoiseModel {
        gyro: one(ng, 0.0, 0.0),
        accel: one(na, 0.0, 0.0),
    };
    for latitude in [None, Some(LATITUDE)] {
        let setup = PredictionSetup::level(g, ALIGN_S, true).with_latitude(latitude);
        for t in [1.0, 60.0, 600.0, 3600.0] {
            let w = setup.schuler_rate.map(|w| w[0]);
            let gyro = variance(
                Kernel::Gyro {
                    gravity: g,
                    schuler_rate: w,
                },
                t,
                ALIGN_S,
                true,
                |_| 2.0 * ng * ng,
            );
            // The north axis alone: both axes given the meridian's radius.
            let setup_n = PredictionSetup {
                schuler_rate: setup.schuler_rate.map(|w| [w[0], w[0]]),
                ..setup
            };
            let pn = predict(&model, &setup_n, t);
            let term_n = |k: PredictedTerm| pn.terms.iter().find(|(j, _)| *j == k).unwrap().1.powi(2) / 2.0;
            let want_n = term_n(PredictedTerm::GyroWhiteNoise) + term_n(PredictedTerm::GyroBiasFromAlignment);
            assert!(
                (gyro / want_n - 1.0).abs() < 1e-4,
                "gyro, latitude {latitude:?}, {t} s: spectral {gyro}, closed {want_n}"
            );
            let accel = variance(Kernel::Accel { schuler_rate: w }, t, ALIGN_S, true, |_| {
                2.0 * na * na
            });
            let want_n = term_n(PredictedTerm::AccelWhiteNoise) + term_n(PredictedTerm::Levelling);
            assert!(
                (accel / want_n - 1.0).abs() < 1e-4,
                "accel, latitude {latitude:?}, {t} s: spectral {accel}, closed {want_n}"
            );
        }
    }
}
