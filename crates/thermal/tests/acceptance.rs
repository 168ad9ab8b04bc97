//! Compensation and ADEV over temperature on simulated runs with known truth.

use imusim::config::SimConfig;
use imusim::terms::NoiseTerms;
use imusim::thermal::Profile;
use imusim::{Simulator, presets};
use thermal::ThermalError;
use thermal::surface::{Slicing, surface};
use thermal::tcal::{FitOptions, Order, Run, TcalChannel, fit};

const DEG: f64 = std::f64::consts::PI / 180.0;

/// A 2 h, 10 Hz run of a gyro x with white noise and a cubic bias.
fn cubic_run(profile: Profile, seed: u64) -> (Vec<f64>, Vec<f64>, SimConfig) {
    let mut cfg = presets::preset("white").unwrap();
    cfg.rate_hz = 10.0;
    cfg.duration_s = 7200.0;
    cfg.seed = seed;
    cfg.profile = profile;
    cfg.sensor_lag_s = 30.0;
    cfg.t_ref_c = 60.0;
    cfg.gyro.terms[0] = NoiseTerms {
        n: 0.01 * DEG,
        ..NoiseTerms::default()
    };
    // Cubic in (T − 60 °C): a 1.5 °/s swing over 20…100 °C.
    cfg.gyro.bias[0] = vec![0.5 * DEG, 0.01 * DEG, 2e-4 * DEG, 3e-6 * DEG];
    let (g, t) = gyro_x_and_temperature(&cfg);
    (g, t, cfg)
}

/// The simulated gyro x and the die's true temperature of a run of `cfg`.
fn gyro_x_and_temperature(cfg: &SimConfig) -> (Vec<f64>, Vec<f64>) {
    let sim = Simulator::new(cfg.clone()).unwrap();
    let (mut t, mut g) = (Vec::new(), Vec::new());
    sim.run(|c| {
        t.extend_from_slice(&c.true_temperature);
        g.extend_from_slice(&c.columns[3]);
        Ok(())
    })
    .unwrap();
    (g, t)
}

fn cooling() -> Profile {
    Profile::Cooling {
        start_c: 100.0,
        ambient_c: 20.0,
        tau_s: 1800.0,
    }
}

/// Bin means of `x` over 1 °C temperature bins, with their standard errors.
fn bin_means(x: &[f64], t: &[f64]) -> Vec<(f64, f64, f64)> {
    let mut bins: std::collections::BTreeMap<i64, Vec<(f64, f64)>> = Default::default();
    for (&v, &tt) in x.iter().zip(t) {
        bins.entry(tt.floor() as i64).or_default().push((v, tt));
    }
    bins.values()
        .filter(|v| v.len() > 10)
        .map(|v| {
            let n = v.len() as f64;
            let m = v.iter().map(|p| p.0).sum::<f64>() / n;
            let tm = v.iter().map(|p| p.1).sum::<f64>() / n;
            let sd = (v.iter().map(|p| (p.0 - m).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
            (tm, m, sd / n.sqrt())
        })
        .collect()
}

/// The compensation of one channel, gyro_x in rad/s, fitted on one run.
fn fit_gyro_x(x: &[f64], t: &[f64], rate_hz: f64) -> Result<thermal::tcal::Model, ThermalError> {
    fit_gyro_x_of(x, t, rate_hz, Order::Auto)
}

/// [`fit_gyro_x`] at `order`.
fn fit_gyro_x_of(
    x: &[f64],
    t: &[f64],
    rate_hz: f64,
    order: Order,
) -> Result<thermal::tcal::Model, ThermalError> {
    let channels = vec![TcalChannel::new("gyro_x", "rad/s", x)];
    let run = Run {
        channels: &channels,
        temp: t,
        rate_hz,
    };
    let opts = FitOptions {
        order,
        ..FitOptions::default()
    };
    fit(&[run], &opts)
}

#[test]
fn a_cubic_bias_is_recovered_and_order_3_chosen() {
    let (g, t, cfg) = cubic_run(cooling(), 1);
    let model = fit_gyro_x(&g, &t, cfg.rate_hz).unwrap();
    let c = model.channel("gyro_x").unwrap();
    assert_eq!(c.order, 3, "cross-validation: {:?}", c.cross_validation);
    // The fitted curve against the true polynomial, over the bins: within
    // 1.2 × the noise floor of the bin means.
    let bins = bin_means(&g, &t);
    let resid: Vec<f64> = bins
        .iter()
        .map(|&(tm, _, _)| c.bias(&model, tm) - cfg.gyro.bias_at(0, tm, cfg.t_ref_c))
        .collect();
    let rms = (resid.iter().map(|r| r * r).sum::<f64>() / resid.len() as f64).sqrt();
    let floor = (bins.iter().map(|b| b.2 * b.2).sum::<f64>() / bins.len() as f64).sqrt();
    println!("fit vs truth: RMS {rms:.3e} rad/s, noise floor of the bin means {floor:.3e} rad/s");
    assert!(rms <= 1.2 * floor, "{rms} > 1.2 × {floor}");
}

#[test]
fn noise_alone_does_not_buy_a_high_order() {
    let (g, t, cfg) = cubic_run(cooling(), 2);
    // Remove the bias: what is left is white noise over a cooling run.
    let flat: Vec<f64> = g
        .iter()
        .zip(&t)
        .map(|(&x, &tt)| x - cfg.gyro.bias_at(0, tt, cfg.t_ref_c))
        .collect();
    let model = fit_gyro_x(&flat, &t, cfg.rate_hz).unwrap();
    let order = model.channel("gyro_x").unwrap().order;
    assert!(order <= 1, "noise picked order {order}");
}

#[test]
fn fitted_on_cooling_it_corrects_a_heating_run() {
    let (g, t, cfg) = cubic_run(cooling(), 3);
    let model = fit_gyro_x(&g, &t, cfg.rate_hz).unwrap();
    let heating = Profile::Ramp {
        from_c: 25.0,
        to_c: 95.0,
        duration_s: 6000.0,
    };
    let (mut h, ht, _) = cubic_run(heating, 4);
    let spread = |x: &[f64]| {
        let b = bin_means(x, &ht);
        let mean = b.iter().map(|v| v.1).sum::<f64>() / b.len() as f64;
        (b.iter().map(|v| (v.1 - mean).powi(2)).sum::<f64>() / b.len() as f64).sqrt()
    };
    let raw = spread(&h);
    let report = model.apply("gyro_x", &mut h, &ht, cfg.rate_hz).unwrap();
    let after = spread(&h);
    println!(
        "residual bias RMS over temperature on the held-out heating run: raw {raw:.3e}, compensated {after:.3e} rad/s"
    );
    assert!(after <= 0.1 * raw, "{after} vs {raw}");
    assert_eq!(report.out_of_range, 0);
}

#[test]
fn the_3d_adev_shows_noise_growing_with_temperature() {
    let mut cfg = presets::preset("mpu9250-thesis").unwrap();
    // 64 Hz puts τ = 1 s on the octave grid.
    cfg.rate_hz = 64.0;
    cfg.duration_s = 6000.0;
    cfg.sensor_lag_s = 10.0;
    cfg.profile = Profile::Ramp {
        from_c: 30.0,
        to_c: 86.0,
        duration_s: 6000.0,
    };
    let (g, t) = gyro_x_and_temperature(&cfg);
    let rows = surface(
        &g,
        &t,
        cfg.rate_hz,
        Slicing::Temperature { bin_width_c: 8.0 },
        0.95,
    )
    .unwrap();
    let at_1s =
        |r: &thermal::surface::SurfaceRow| r.points.iter().find(|p| (p.tau - 1.0).abs() < 1e-9).copied();
    let full: Vec<_> = rows.iter().filter(|r| r.samples > 30_000).collect();
    let (cold, hot) = (full[0], full[full.len() - 1]);
    let (c1, h1) = (at_1s(cold).unwrap(), at_1s(hot).unwrap());
    let expected = cfg.gyro.noise_factor(hot.t_mean_c) / cfg.gyro.noise_factor(cold.t_mean_c);
    let (lo, hi) = (h1.dev_lo / c1.dev_hi, h1.dev_hi / c1.dev_lo);
    println!(
        "σ(1 s) at {:.1} °C over {:.1} °C: {:.4} (configured {expected:.4}, interval [{lo:.4}, {hi:.4}])",
        hot.t_mean_c,
        cold.t_mean_c,
        h1.dev / c1.dev
    );
    assert!(lo <= expected && expected <= hi);
    assert!(h1.dev > c1.dev);
}

#[test]
fn degenerate_inputs_are_clear_errors() {
    let t = vec![34.0; 1000];
    let x = vec![0.0; 1000];
    let e = fit_gyro_x(&x, &t, 10.0).unwrap_err();
    assert!(matches!(e, ThermalError::NoSpread { .. }), "{e}");
    assert!(e.to_string().contains("nothing to fit"));

    let t: Vec<f64> = (0..1000).map(|i| 30.0 + i as f64 * 0.003).collect();
    let e = fit_gyro_x_of(&x, &t, 10.0, Order::Fixed(5)).unwrap_err();
    assert!(matches!(e, ThermalError::TooFewBins { .. }), "{e}");

    let model = fit_gyro_x_of(&x, &t, 10.0, Order::Fixed(1)).unwrap();
    let mut other = vec![0.0; 1000];
    let e = model.apply("accel_z", &mut other, &t, 10.0).unwrap_err();
    assert!(e.to_string().contains("'accel_z'"), "{e}");
}
