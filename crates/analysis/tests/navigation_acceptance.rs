//! The acceptance figures of the navigation, on simulated recordings whose
//! truth is known, against the closed forms written out here from the
//! formulas (not through the crate's prediction module).

use imusim::config::SensorConfig;
use imusim::terms::NoiseTerms;
use imusim::{SimConfig, Simulator, presets};

use analysis::monte_carlo::{MonteCarloSetup, monte_carlo};
use ins::drift::{CurvePoint, drift_over_windows, report_times};
use ins::prediction::{AxisNoise, NoiseModel, PredictionSetup, predict};
use ins::strapdown::{ImuData, NavOptions};

const G: f64 = earth::STANDARD_GRAVITY;
const RATE: f64 = 100.0;
const N_GYRO: f64 = 1.5e-4; // rad/√s
const N_ACCEL: f64 = 3e-3; // m/s/√s

/// A white-noise-only recording (no quantization, no bias) of `duration_s`.
fn white(duration_s: f64, seed: u64) -> [Vec<f64>; 7] {
    let mut cfg = presets::preset("white").unwrap();
    cfg.rate_hz = RATE;
    cfg.duration_s = duration_s;
    cfg.seed = seed;
    cfg.gyro.terms = [NoiseTerms {
        n: N_GYRO,
        ..Default::default()
    }; 3];
    cfg.accel.terms = [NoiseTerms {
        n: N_ACCEL,
        ..Default::default()
    }; 3];
    columns(cfg)
}

/// The noise model of [`white`]'s recordings: white noise only.
fn white_model() -> NoiseModel {
    NoiseModel {
        gyro: [AxisNoise {
            n: N_GYRO,
            ..Default::default()
        }; 3],
        accel: [AxisNoise {
            n: N_ACCEL,
            ..Default::default()
        }; 3],
    }
}

/// Holds the horizontal position RMS of each point within `tol`
/// (relative) of `want(t)`.
fn rms_follows(curve: &[CurvePoint], tol: f64, want: impl Fn(f64) -> f64, case: &str) {
    for p in curve {
        let want = want(p.t_s);
        let got = p.horizontal_position_m.rms;
        assert!(
            (got / want - 1.0).abs() < tol,
            "{case}t = {} s: RMS {got:.3} m against {want:.3} m",
            p.t_s
        );
    }
}

fn columns(cfg: SimConfig) -> [Vec<f64>; 7] {
    let n = cfg.samples() as usize;
    Simulator::new(cfg).unwrap().generator().next_chunk(n).columns
}

fn imu(c: &[Vec<f64>; 7]) -> ImuData<'_> {
    ImuData {
        accel: [&c[0], &c[1], &c[2]],
        gyro: [&c[3], &c[4], &c[5]],
        rate_hz: RATE,
    }
}

/// The closed form for white noise, per horizontal axis, levelling
/// only: gyro g·N_g·t^{5/2}/√20, accelerometer N_a·t^{3/2}/√3, levelling
/// ½·N_a·t²/√T_a; with the gyro's window mean taken out, also its bias
/// g·N_g·t³/(6·√T_a). Two axes: √2 times one.
fn closed_form(t: f64, align_s: f64, gyro_mean_removed: bool) -> f64 {
    let mut v = (G * N_GYRO * t.powf(2.5) / 20f64.sqrt()).powi(2)
        + (N_ACCEL * t.powf(1.5) / 3f64.sqrt()).powi(2)
        + (0.5 * N_ACCEL * t * t / align_s.sqrt()).powi(2);
    if gyro_mean_removed {
        v += (G * N_GYRO * t.powi(3) / (6.0 * align_s.sqrt())).powi(2);
    }
    (2.0 * v).sqrt()
}

#[test]
fn white_noise_drift_matches_the_closed_form_within_15_percent() {
    // 120 independent windows (each 10 s of alignment and 60 s of
    // navigation, one after the other): the RMS over them is within ±5 %
    // (1σ) of the truth.
    let c = white(120.0 * 70.0, 17);
    let times = [10.0, 30.0, 60.0];
    for removed in [false, true] {
        let opts = NavOptions {
            align_s: 10.0,
            latitude_deg: None,
            remove_gyro_bias: removed,
        };
        let d = drift_over_windows(&imu(&c), &opts, 70.0, &times).unwrap();
        assert_eq!(d.windows, 120);
        rms_follows(
            &d.curve,
            0.15,
            |t| closed_form(t, 10.0, removed),
            &format!("gyro mean removed {removed}, "),
        );
    }
}

#[test]
fn the_prediction_module_gives_the_closed_form() {
    let model = white_model();
    for removed in [false, true] {
        let setup = PredictionSetup::level(G, 10.0, removed);
        for t in [1.0, 10.0, 30.0, 60.0, 120.0] {
            let p = predict(&model, &setup, t).total_m;
            let want = closed_form(t, 10.0, removed);
            assert!((p / want - 1.0).abs() < 1e-12, "t = {t}: {p} against {want}");
        }
    }
}

/// A level, noise-free recording.
fn quiet(samples: usize) -> [Vec<f64>; 7] {
    let mut c: [Vec<f64>; 7] = std::array::from_fn(|_| vec![0.0; samples]);
    c[2] = vec![G; samples];
    c
}

#[test]
fn a_gyro_bias_after_alignment_drifts_g_eps_t3_over_6() {
    let eps = 2e-4;
    let mut c = quiet(130 * 100);
    // On gyro y: a tilt about y moves the position along x.
    for v in &mut c[4][1000..] {
        *v = eps;
    }
    let d = drift_over_windows(&imu(&c), &NavOptions::default(), 10.0, &[10.0, 60.0, 120.0]).unwrap();
    rms_follows(&d.curve, 0.02, |t| G * eps * t.powi(3) / 6.0, "");
}

#[test]
fn an_accelerometer_bias_from_the_start_is_absorbed_by_levelling() {
    let b = 0.05; // m/s², 5 mg
    let mut c = quiet(70 * 100);
    for v in &mut c[0] {
        *v += b;
    }
    for v in &mut c[1] {
        *v -= 0.5 * b;
    }
    let d = drift_over_windows(&imu(&c), &NavOptions::default(), 10.0, &[60.0]).unwrap();
    let got = d.curve[0].horizontal_position_m.rms;
    let unabsorbed = 0.5 * b * 60f64.powi(2);
    assert!(got < 0.01 * unabsorbed, "{got} m against 1 % of {unabsorbed} m");
}

/// A noise-free recording of a sensor at rest on the rotating Earth.
fn rotating(latitude_deg: f64, heading_deg: f64) -> [Vec<f64>; 7] {
    let mut cfg = presets::preset("white").unwrap();
    cfg.rate_hz = RATE;
    cfg.duration_s = 130.0;
    cfg.gyro.terms = [NoiseTerms::default(); 3];
    cfg.accel.terms = [NoiseTerms::default(); 3];
    cfg.sensor = SensorConfig {
        quantize: false,
        roll_deg: 1.23,
        pitch_deg: -5.14,
        heading_deg,
        latitude_deg: Some(latitude_deg),
        ..SensorConfig::default()
    };
    columns(cfg)
}

#[test]
fn with_the_latitude_the_rotating_earth_leaves_no_drift() {
    let times: Vec<f64> = (1..=12).map(|k| 10.0 * k as f64).collect();
    let c = rotating(48.0, 0.0);
    for removed in [false, true] {
        let opts = NavOptions {
            align_s: 10.0,
            latitude_deg: Some(48.0),
            remove_gyro_bias: removed,
        };
        let d = drift_over_windows(&imu(&c), &opts, 10.0, &times).unwrap();
        for p in &d.curve {
            // At rest the velocity is the truth's, zero: a term of the
            // rotating frame left out shows here first (a constant
            // acceleration of a few µm/s² would still pass the 0.1 m).
            assert!(
                p.horizontal_velocity_m_s.rms < 1e-6,
                "gyro mean removed {removed}: {} m/s at {} s",
                p.horizontal_velocity_m_s.rms,
                p.t_s
            );
            assert!(
                p.horizontal_position_m.rms < 0.1,
                "gyro mean removed {removed}: {} m at {} s",
                p.horizontal_position_m.rms,
                p.t_s
            );
        }
    }
    // Without the latitude and without the gyro's mean taken out, the same
    // recording tilts at the Earth's horizontal rate: g·Ω·cos L·t³/6.
    let opts = NavOptions {
        align_s: 10.0,
        latitude_deg: None,
        remove_gyro_bias: false,
    };
    let d = drift_over_windows(&imu(&c), &opts, 10.0, &[120.0]).unwrap();
    let want = G * earth::EARTH_RATE * 48f64.to_radians().cos() * 120f64.powi(3) / 6.0;
    let got = d.curve[0].horizontal_position_m.rms;
    assert!((got / want - 1.0).abs() < 0.02, "{got} m against {want} m");
}

#[test]
fn the_monte_carlo_of_the_model_agrees_with_its_prediction() {
    let model = white_model();
    let opts = NavOptions::default();
    let setup = MonteCarloSetup {
        rate_hz: RATE,
        runs: 120,
        seed: 5,
        roll_deg: 0.0,
        pitch_deg: 0.0,
    };
    let mc = monte_carlo(&model, &opts, &setup, &[30.0, 60.0]).unwrap();
    rms_follows(&mc.curve, 0.15, |t| closed_form(t, 10.0, true), "");
    // The interval holds the rms, and is as wide as 1.96/(2·√runs) says
    // (the squared distance of an isotropic 2-D error is exponential: its
    // relative standard deviation is 1).
    for (p, [lo, hi]) in mc.curve.iter().zip(&mc.horizontal_rms_95) {
        let rms = p.horizontal_position_m.rms;
        assert!(*lo < rms && rms < *hi);
        let half = (hi - lo) / 2.0 / rms;
        let want = 1.96 / (2.0 * (setup.runs as f64).sqrt());
        assert!(
            (half / want - 1.0).abs() < 0.3,
            "half-width {half} against {want}"
        );
    }
}

/// The bias-instability term against a Monte Carlo of a flicker that is
/// flat in Allan deviation from 1 to 1000 s: a bound that holds at 60 s
/// and at 600 s, where the old one (a constant bias B) was passed by 17 %,
/// and not far above the runs.
#[test]
fn the_bias_instability_bound_holds() {
    let b = 5e-5;
    let model = NoiseModel {
        gyro: [AxisNoise { n: 0.0, b, k: 0.0 }; 3],
        accel: [AxisNoise {
            n: 0.0,
            b: 1e-3,
            k: 0.0,
        }; 3],
    };
    let opts = NavOptions::default();
    let setup = MonteCarloSetup {
        rate_hz: 10.0,
        runs: 400,
        seed: 11,
        roll_deg: 0.0,
        pitch_deg: 0.0,
    };
    let times = [60.0, 600.0];
    let mc = monte_carlo(&model, &opts, &setup, &times).unwrap();
    for (p, [lo, hi]) in mc.curve.iter().zip(&mc.horizontal_rms_95) {
        let bound = predict(&model, &PredictionSetup::level(G, 10.0, true), p.t_s).total_m;
        assert!(
            *lo <= bound,
            "t = {} s: the runs' rms is at least {lo} m, the bound {bound} m",
            p.t_s
        );
        assert!(
            bound < 1.5 * hi,
            "t = {} s: the bound {bound} m against the runs' {hi} m",
            p.t_s
        );
    }
}

#[test]
fn windows_across_a_gap_are_left_out_and_counted() {
    let mut c = quiet(100 * 100);
    // One NaN sample at 45 s: windows of 10 + 20 s starting every 10 s
    // begin at 0, 10, …, 70 s; those starting at 20, 30 and 40 s hold it.
    c[4][4500] = f64::NAN;
    let d = drift_over_windows(&imu(&c), &NavOptions::default(), 10.0, &[20.0]).unwrap();
    assert_eq!((d.windows, d.windows_with_gaps), (5, 3));
    for v in &mut c[4] {
        *v = f64::NAN;
    }
    assert!(matches!(
        drift_over_windows(&imu(&c), &NavOptions::default(), 10.0, &[20.0]),
        Err(ins::InsError::NoWindow)
    ));
}

/// `ins --horizon 3600` on white noise with a latitude: the prediction
/// within 10 % of the Monte Carlo at every time it prints.
#[test]
fn an_hour_with_the_latitude_is_predicted_within_ten_percent() {
    let model = white_model();
    let latitude = 48.0;
    let opts = NavOptions {
        latitude_deg: Some(latitude),
        ..NavOptions::default()
    };
    let setup = MonteCarloSetup {
        rate_hz: 10.0,
        runs: RUNS_AN_HOUR,
        seed: 3,
        roll_deg: 0.0,
        pitch_deg: 0.0,
    };
    let times = report_times(3600.0);
    let mc = monte_carlo(&model, &opts, &setup, &times).unwrap();
    let at = PredictionSetup::level(opts.gravity(), 10.0, true).with_latitude(Some(latitude));
    for p in &mc.curve {
        let predicted = predict(&model, &at, p.t_s).total_m;
        let got = p.horizontal_position_m.rms;
        assert!(
            (predicted / got - 1.0).abs() < 0.1,
            "t = {} s: predicted {predicted} m, Monte Carlo {got} m",
            p.t_s
        );
    }
}

/// Runs of the hour's Monte Carlo: at 300 the rms is known to ±5.7 % (95 %),
/// which leaves room for the closed form's own 3 % at an hour (measured
/// with 2,000 runs: 0.98–1.03 of the runs at every time) inside the 10 %;
/// the flat-Earth form is 2.7 times the runs there.
const RUNS_AN_HOUR: usize = 300;

/// The rate random walks against a Monte Carlo: with the walk's lead on
/// the alignment window's mean (K·√(T_a/3) when navigation starts), which
/// the walk-only law g·K·t^{7/2}/√252 left out, and was then 0.56 of the
/// runs at 10 s and 0.86 at 60 s (now 1.00–1.03).
#[test]
fn the_random_walks_are_predicted_with_their_lead_on_the_window() {
    let model = NoiseModel {
        gyro: [AxisNoise {
            n: 0.0,
            b: 0.0,
            k: 2.9e-5,
        }; 3],
        accel: [AxisNoise {
            n: 0.0,
            b: 0.0,
            k: 3e-4,
        }; 3],
    };
    let setup = MonteCarloSetup {
        rate_hz: 20.0,
        runs: 600,
        seed: 21,
        roll_deg: 0.0,
        pitch_deg: 0.0,
    };
    let mc = monte_carlo(&model, &NavOptions::default(), &setup, &[10.0, 30.0, 60.0]).unwrap();
    for (p, [lo, hi]) in mc.curve.iter().zip(&mc.horizontal_rms_95) {
        let predicted = predict(&model, &PredictionSetup::level(G, 10.0, true), p.t_s).total_m;
        assert!(
            *lo * 0.95 < predicted && predicted < *hi * 1.05,
            "t = {} s: predicted {predicted} m, the runs' rms {lo}…{hi} m",
            p.t_s
        );
    }
}
