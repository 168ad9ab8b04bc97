//! The simulator against the theory it claims: each IEEE 952 term alone
//! follows its Allan deviation, the preset follows its model, the bias
//! follows its polynomial of temperature, the output stage is the chip's,
//! seeds reproduce, bad configurations are refused.

use allan::confidence::chi2_interval;
use allan::edf::edf_for;
use allan::{Options, Point, Stat, TauSpec, analyze};
use imusim::config::SimConfig;
use imusim::terms::NoiseTerms;
use imusim::thermal::Profile;
use imusim::{Simulator, presets, sensor};

/// Per-point confidence of the interval the theory must fall in. A dozen
/// octave points are tested per curve, so a per-point 99.9 % interval makes
/// a correct generator fail about once in a hundred seeds; at 68.3 % it
/// would miss four points of every curve.
const CONFIDENCE: f64 = 0.999;

/// No noise at all: the other terms of a test of one term.
const SILENT: NoiseTerms = NoiseTerms {
    q: 0.0,
    n: 0.0,
    b: 0.0,
    k: 0.0,
    r: 0.0,
};

/// The gyro x channel of a 2 h, 10 Hz recording whose only error is
/// `terms` (no bias, no output quantization, constant temperature).
fn one_term(terms: NoiseTerms, seed: u64) -> Vec<f64> {
    let mut cfg = presets::preset("white").unwrap();
    cfg.rate_hz = 10.0;
    cfg.duration_s = 7200.0;
    cfg.seed = seed;
    cfg.gyro.terms[0] = terms;
    cfg.gyro.flicker_tau_s = [1.0, 2000.0];
    gyro_x(&cfg)
}

fn column(cfg: &SimConfig, k: usize) -> Vec<f64> {
    let sim = Simulator::new(cfg.clone()).unwrap();
    let mut y = Vec::with_capacity(cfg.samples() as usize);
    sim.run(|chunk| {
        y.extend_from_slice(&chunk.columns[k]);
        Ok(())
    })
    .unwrap();
    y
}

fn gyro_x(cfg: &SimConfig) -> Vec<f64> {
    column(cfg, 3)
}

fn oadev(y: &[f64], rate: f64) -> Vec<Point> {
    let opts = Options {
        rate_hz: rate,
        taus: TauSpec::Octave,
        ..Options::default()
    };
    analyze(y, &opts).unwrap().points
}

/// The power-law exponent of the term that dominates σ²(τ): the noise type
/// is known here, so the interval does not depend on identifying it from
/// the data (which needs ≥ 30 points after decimation and fails at the
/// largest τ).
fn dominant_alpha(t: &NoiseTerms, tau: f64) -> i32 {
    let parts = [
        (3.0 * t.q * t.q / (tau * tau), 2),
        (t.n * t.n / tau, 0),
        (0.4413 * t.b * t.b, -1),
        (t.k * t.k * tau / 3.0, -2),
    ];
    parts
        .iter()
        .fold((0.0, 0), |best, &(v, a)| if v > best.0 { (v, a) } else { best })
        .1
}

/// Every octave τ selected by `taus`: the theory of `terms` inside the
/// interval (chi-squared, with Greenhall's EDF for the dominant noise type
/// at that τ), widened by `slack` (the generator's stated flatness, for B).
fn follows(y: &[f64], rate: f64, what: &str, terms: NoiseTerms, taus: impl Fn(f64) -> bool, slack: f64) {
    let pts = oadev(y, rate);
    let mut checked = 0;
    for p in pts.iter().filter(|p| taus(p.tau)) {
        let theory = terms.allan_variance(p.tau).sqrt();
        let alpha = dominant_alpha(&terms, p.tau);
        let edf = edf_for(Stat::Oadev, alpha, p.m, y.len() + 1).unwrap();
        let (lo, hi) = chi2_interval(p.dev, edf, CONFIDENCE);
        assert!(
            lo / slack <= theory && theory <= hi * slack,
            "{what}, τ = {} s: theory {theory:.4e} outside [{lo:.4e}, {hi:.4e}] (measured {:.4e}, α {alpha}, edf {edf:.1})",
            p.tau,
            p.dev
        );
        checked += 1;
    }
    assert!(checked >= 8, "{what}: only {checked} taus checked");
}

fn follows_theory(terms: NoiseTerms, seed: u64, taus: impl Fn(f64) -> bool, slack: f64) {
    let y = one_term(terms, seed);
    follows(&y, 10.0, &format!("{terms:?}"), terms, taus, slack);
}

#[test]
fn white_quantization_and_rate_random_walk_noise_each_alone() {
    // A failure names the terms (follows_theory prints them).
    for (t, seed) in [
        (NoiseTerms { n: 2e-3, ..SILENT }, 3),
        (NoiseTerms { q: 1e-4, ..SILENT }, 4),
        (NoiseTerms { k: 1e-4, ..SILENT }, 5),
    ] {
        follows_theory(t, seed, |_| true, 1.0);
    }
}

#[test]
fn bias_instability_alone_is_flat_over_its_range() {
    // Flat over the configured [1, 2000] s, within the ±5 % the bank
    // promises (its exact curve is checked in the flicker module).
    let t = NoiseTerms { b: 1e-3, ..SILENT };
    follows_theory(t, 6, |tau| (1.0..=2000.0).contains(&tau), 1.05);
}

#[test]
fn rate_ramp_alone_is_exact() {
    let t = NoiseTerms { r: 1e-6, ..SILENT };
    let y = one_term(t, 7);
    for p in oadev(&y, 10.0) {
        let theory = t.allan_variance(p.tau).sqrt();
        assert!(
            ((p.dev - theory) / theory).abs() < 1e-6,
            "τ = {}: {} vs {theory}",
            p.tau,
            p.dev
        );
    }
}

#[test]
fn the_terms_add_up() {
    // N, B and K together, each dominating its own part of the curve, at
    // 100 Hz over 2 h: the sum of their Allan variances at every τ.
    let t = NoiseTerms {
        n: 5e-4,
        b: 2e-4,
        k: 2e-5,
        ..NoiseTerms::default()
    };
    let mut cfg = presets::preset("white").unwrap();
    cfg.duration_s = 7200.0;
    cfg.seed = 8;
    cfg.gyro.terms[0] = t;
    cfg.gyro.flicker_tau_s = [0.1, 2000.0];
    let y = gyro_x(&cfg);
    follows(&y, 100.0, "N + B + K", t, |_| true, 1.05);
}

#[test]
fn the_thesis_preset_follows_its_model() {
    // One hour of the preset as it is (output quantization, tilt, bias,
    // the chamber's fluctuation): every axis follows N, B, K of its
    // configuration, the white noise of the LSB rounding included. The
    // model's minimum is the thesis's σ_min at its τ (a unit test of the
    // presets checks that).
    let cfg = presets::preset("mpu9250-thesis").unwrap();
    let tau0 = 1.0 / cfg.rate_hz;
    for k in 0..6 {
        let (group, lsb) = if k < 3 {
            (&cfg.accel, sensor::accel_lsb_si(cfg.sensor.accel_range_g))
        } else {
            (&cfg.gyro, sensor::gyro_lsb_rad(cfg.sensor.gyro_range_dps))
        };
        let mut t = group.terms[k % 3];
        t.n = (t.n * t.n + lsb * lsb * tau0 / 12.0).sqrt();
        let y = column(&cfg, k);
        follows(
            &y,
            cfg.rate_hz,
            &format!("mpu9250-thesis column {k}"),
            t,
            |tau| tau >= 0.05,
            1.05,
        );
    }
}

#[test]
fn same_seed_same_bytes_other_seed_independent() {
    let mut cfg = presets::preset("mpu9250-thesis").unwrap();
    cfg.duration_s = 30.0;
    let write = |cfg: &SimConfig| {
        let sim = Simulator::new(cfg.clone()).unwrap();
        let mut out = Vec::new();
        sim.write_log(&mut out, &sim.metadata(Some("mpu9250-thesis")), |_, _| {})
            .unwrap();
        out
    };
    let a = write(&cfg);
    assert_eq!(a, write(&cfg));
    let mut other = cfg.clone();
    other.seed = 2;
    assert_ne!(a, write(&other));

    // Independent: the white noise of two seeds, and of two axes of one
    // seed, is uncorrelated: |ρ| < 4/√n.
    let mut w = presets::preset("white").unwrap();
    w.duration_s = 100.0;
    let x = Simulator::new(w.clone()).unwrap().recording(None).unwrap();
    w.seed = 2;
    let y = Simulator::new(w).unwrap().recording(None).unwrap();
    let rho = |a: &[f64], b: &[f64]| {
        let n = a.len() as f64;
        let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
        let cov: f64 = a.iter().zip(b).map(|(p, q)| (p - ma) * (q - mb)).sum::<f64>();
        let va: f64 = a.iter().map(|p| (p - ma).powi(2)).sum();
        let vb: f64 = b.iter().map(|q| (q - mb).powi(2)).sum();
        (cov / (va * vb).sqrt(), 4.0 / n.sqrt())
    };
    let data = |r: &imu::Recording, c: &str| r.channel(c).unwrap().data.clone();
    for (a, b) in [
        (data(&x, "gyro_x"), data(&y, "gyro_x")),
        (data(&x, "gyro_x"), data(&x, "gyro_y")),
        (data(&x, "accel_z"), data(&x, "gyro_z")),
    ] {
        let (r, bound) = rho(&a, &b);
        assert!(r.abs() < bound, "ρ = {r}");
    }
}

#[test]
fn every_term_draws_from_its_own_stream() {
    // Adding the rate random walk to white noise leaves the white noise as
    // it was: the difference is exactly the walk a K-only run draws.
    let run = |n: f64, k: f64| {
        let mut cfg = presets::preset("white").unwrap();
        cfg.duration_s = 60.0;
        cfg.seed = 11;
        cfg.gyro.terms[2] = NoiseTerms {
            n,
            k,
            ..NoiseTerms::default()
        };
        column(&cfg, 5)
    };
    let (white, walk, both) = (run(1e-3, 0.0), run(0.0, 1e-4), run(1e-3, 1e-4));
    for ((w, k), b) in white.iter().zip(&walk).zip(&both) {
        assert!((w + k - b).abs() < 1e-15, "{w} + {k} ≠ {b}");
    }
    assert!(walk.iter().any(|&k| k != 0.0));
}

#[test]
fn chunks_of_any_size_give_the_same_series() {
    // The simulated chip pulls a few samples at a time: the series must not
    // depend on how it is cut.
    let mut cfg = presets::preset("mpu9250-thesis").unwrap();
    // 10 000 samples, whatever the preset's rate.
    cfg.rate_hz = 100.0;
    cfg.duration_s = 100.0;
    let sim = Simulator::new(cfg).unwrap();
    let mut whole = Vec::new();
    sim.run(|c| {
        whole.push(c.columns.clone());
        Ok(())
    })
    .unwrap();
    let mut g = sim.generator();
    let mut pieces: [Vec<f64>; 7] = Default::default();
    while g.position() < 10_000 {
        let c = g.next_chunk(37.min(10_000 - g.position() as usize));
        for (p, col) in pieces.iter_mut().zip(&c.columns) {
            p.extend_from_slice(col);
        }
    }
    for (k, piece) in pieces.iter().enumerate() {
        let joined: Vec<f64> = whole.iter().flat_map(|c| c[k].iter().copied()).collect();
        assert_eq!(&joined, piece, "column {k}");
    }
}

#[test]
fn cooling_run_bias_follows_its_polynomial() {
    let mut cfg = presets::preset("mpu9250-thesis").unwrap();
    cfg.rate_hz = 10.0;
    cfg.duration_s = 7200.0;
    cfg.profile = Profile::Cooling {
        start_c: 100.0,
        ambient_c: 20.0,
        tau_s: 1800.0,
    };
    // Only white noise, so that "within the noise" is a sharp statement.
    for g in [&mut cfg.gyro, &mut cfg.accel] {
        for t in &mut g.terms {
            *t = NoiseTerms { n: t.n, ..SILENT };
        }
    }
    let sim = Simulator::new(cfg.clone()).unwrap();
    let (mut temps, mut chamber) = (Vec::new(), Vec::new());
    let mut cols: Vec<Vec<f64>> = vec![Vec::new(); 6];
    sim.run(|chunk| {
        temps.extend_from_slice(&chunk.true_temperature);
        chamber.extend_from_slice(&chunk.chamber_temperature);
        for (c, src) in cols.iter_mut().zip(&chunk.columns) {
            c.extend_from_slice(src);
        }
        Ok(())
    })
    .unwrap();
    assert!(temps[0] > 99.0 && *temps.last().unwrap() < 30.0);
    // The die lags the chamber while it cools.
    assert!(temps[3000] > chamber[3000] + 1.0);
    let gravity = sensor::gravity(
        cfg.sensor.roll_deg.to_radians(),
        cfg.sensor.pitch_deg.to_radians(),
    );
    for (k, y) in cols.iter().enumerate() {
        let (group, input, lsb) = if k < 3 {
            (
                &cfg.accel,
                gravity[k],
                sensor::accel_lsb_si(cfg.sensor.accel_range_g),
            )
        } else {
            (&cfg.gyro, 0.0, sensor::gyro_lsb_rad(cfg.sensor.gyro_range_dps))
        };
        let axis = k % 3;
        // The output against input + polynomial at the die temperature,
        // averaged over blocks of 600 samples: within 4 standard errors.
        let per_sample = group.terms[axis].n * cfg.rate_hz.sqrt() * group.noise_factor(100.0);
        let se = (per_sample * per_sample + lsb * lsb / 12.0).sqrt() / 600f64.sqrt();
        let mut swing: f64 = 0.0;
        for (tb, yb) in temps.chunks(600).zip(y.chunks(600)) {
            let resid: f64 = tb
                .iter()
                .zip(yb)
                .map(|(&t, &v)| v - input - group.bias_at(axis, t, cfg.t_ref_c))
                .sum::<f64>()
                / yb.len() as f64;
            assert!(
                resid.abs() < 4.0 * se,
                "column {k}, T ≈ {:.1} °C: residual {resid:.3e} > 4·{se:.3e}",
                tb[0]
            );
            swing = swing.max(
                (group.bias_at(axis, tb[0], cfg.t_ref_c) - group.bias_at(axis, temps[0], cfg.t_ref_c)).abs(),
            );
        }
        // The test means something: the bias moves by many standard errors.
        assert!(
            swing > 20.0 * se,
            "column {k}: bias swing {swing:.3e} vs se {se:.3e}"
        );
    }
}

#[test]
fn the_output_stage_is_the_chips() {
    let mut cfg = presets::preset("mpu9250-thesis").unwrap();
    cfg.duration_s = 20.0;
    // A gyro y offset beyond ±500 °/s clips at the register's end.
    cfg.gyro.bias[1] = vec![600f64.to_radians()];
    let rec = Simulator::new(cfg.clone()).unwrap().recording(None).unwrap();
    let a_lsb = sensor::accel_lsb_si(8.0);
    let g_lsb = sensor::gyro_lsb_rad(500.0);
    let on_grid = |v: f64, lsb: f64| ((v / lsb) - (v / lsb).round()).abs() < 1e-6;
    for name in ["accel_x", "accel_y", "accel_z"] {
        assert!(
            rec.channel(name).unwrap().data.iter().all(|&v| on_grid(v, a_lsb)),
            "{name}"
        );
    }
    for name in ["gyro_x", "gyro_z"] {
        assert!(
            rec.channel(name).unwrap().data.iter().all(|&v| on_grid(v, g_lsb)),
            "{name}"
        );
    }
    assert!(
        rec.channel("gyro_y")
            .unwrap()
            .data
            .iter()
            .all(|&v| v == 32767.0 * g_lsb)
    );
    // The temperature sensor: 333.87 LSB/°C, 21 °C at 0 LSB.
    let temps = &rec.channel("temp").unwrap().data;
    assert!(temps.iter().all(|&t| on_grid(t - 21.0, 1.0 / 333.87)));
    assert!(temps.iter().all(|&t| (t - 34.0).abs() < 0.5));
    // Gravity for the tilt, plus the zero-g offset at the die temperature.
    let g = sensor::gravity(
        cfg.sensor.roll_deg.to_radians(),
        cfg.sensor.pitch_deg.to_radians(),
    );
    for (k, name) in ["accel_x", "accel_y", "accel_z"].iter().enumerate() {
        let d = &rec.channel(name).unwrap().data;
        let mean = d.iter().sum::<f64>() / d.len() as f64;
        let want = g[k] + cfg.accel.bias_at(k, 34.0, cfg.t_ref_c);
        assert!((mean - want).abs() < 0.01, "{name}: {mean} vs {want}");
    }
    // The thesis's sample row: ≈ 0.88, 0.21, 9.36 m/s².
    let az = &rec.channel("accel_z").unwrap().data;
    assert!((az.iter().sum::<f64>() / az.len() as f64 - 9.36).abs() < 0.02);
}

#[test]
fn the_die_lags_the_chamber() {
    // A ramp of 1 °C/min and a 120 s lag: once settled, the die is 2 °C
    // behind. Steps: each level is reached through the heater's response.
    let mut cfg = presets::preset("white").unwrap();
    cfg.rate_hz = 10.0;
    cfg.duration_s = 2400.0;
    cfg.sensor_lag_s = 120.0;
    cfg.profile = Profile::parse("ramp:20:60:2400").unwrap();
    let sim = Simulator::new(cfg.clone()).unwrap();
    let mut g = sim.generator();
    let c = g.next_chunk(24_000);
    for i in [12_000, 18_000, 23_999] {
        let lag = c.chamber_temperature[i] - c.true_temperature[i];
        assert!((lag - 2.0).abs() < 0.01, "sample {i}: lag {lag}");
    }
    cfg.profile = Profile::parse("steps:30,45:1200").unwrap();
    cfg.sensor_lag_s = 0.0;
    let c = Simulator::new(cfg).unwrap().generator().next_chunk(24_000);
    assert_eq!(c.true_temperature[0], 30.0);
    assert!((c.true_temperature[11_999] - 30.0).abs() < 1e-9);
    // 120 s heater: 63 % of the step after 120 s, all of it by the end.
    assert!((c.true_temperature[12_000 + 1200] - (30.0 + 15.0 * (1.0 - (-1f64).exp()))).abs() < 0.02);
    assert!((c.true_temperature[23_999] - 45.0).abs() < 1e-3);
}

#[test]
fn a_profile_from_a_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("chamber.csv");
    std::fs::write(
        &path,
        "# logged by the chamber\ntime_s, temp_C\n0, 20\n100, 30\n200, 30\n",
    )
    .unwrap();
    let mut cfg = presets::preset("white").unwrap();
    cfg.rate_hz = 1.0;
    cfg.duration_s = 300.0;
    cfg.profile = Profile::parse(&format!("file:{}", path.display())).unwrap();
    let c = Simulator::new(cfg.clone()).unwrap().generator().next_chunk(300);
    assert_eq!(c.true_temperature[0], 20.0);
    assert!((c.true_temperature[50] - 25.0).abs() < 1e-12);
    assert_eq!(c.true_temperature[299], 30.0);
    // A bad row is named by its line.
    std::fs::write(&path, "0, 20\n100, 30\n50, 25\n").unwrap();
    let e = Simulator::new(cfg.clone()).unwrap_err().to_string();
    assert!(
        e.contains("chamber.csv:3") && e.contains("does not increase"),
        "{e}"
    );
    std::fs::write(&path, "0, 20\n100, thirty\n").unwrap();
    let e = Simulator::new(cfg.clone()).unwrap_err().to_string();
    assert!(e.contains("chamber.csv:2"), "{e}");
    cfg.profile = Profile::parse("file:/nonexistent/chamber.csv").unwrap();
    assert!(Simulator::new(cfg).is_err());
}

#[test]
fn bad_configurations_are_refused() {
    let mut cfg = presets::preset("white").unwrap();
    cfg.gyro.terms[1].n = -1e-3;
    let e = Simulator::new(cfg).unwrap_err();
    assert!(e.to_string().contains("gyro.terms[1].n = -0.001"), "{e}");
    let e = presets::preset("mpu6050-dream").unwrap_err();
    assert!(e.to_string().contains("unknown preset 'mpu6050-dream'"), "{e}");
    let mut cfg = presets::preset("white").unwrap();
    cfg.rate_hz = 0.0;
    let e = Simulator::new(cfg).unwrap_err().to_string();
    assert!(e.contains("rate_hz = 0"), "{e}");
    let mut cfg = presets::preset("white").unwrap();
    cfg.t_ref_c = f64::NAN;
    assert!(Simulator::new(cfg).is_err());
    let mut cfg = presets::preset("mpu9250-thesis").unwrap();
    cfg.accel.noise_scale[0][0] = f64::NAN;
    assert!(Simulator::new(cfg.clone()).is_err());
    cfg.accel.noise_scale[0][0] = 50.0;
    let e = Simulator::new(cfg).unwrap_err().to_string();
    assert!(
        e.contains("accel.noise_scale[1]") && e.contains("increase"),
        "{e}"
    );
    let mut cfg = presets::preset("white").unwrap();
    cfg.gyro.flicker_tau_s = [10.0, 1.0];
    assert!(Simulator::new(cfg).is_err());
    let mut cfg = presets::preset("white").unwrap();
    cfg.sensor.gyro_range_dps = 300.0;
    let e = Simulator::new(cfg).unwrap_err().to_string();
    assert!(e.contains("250, 500, 1000 or 2000"), "{e}");
    let e = SimConfig::from_toml("rate_hz = 100\nduration_s = 1\n").unwrap_err();
    assert!(e.to_string().starts_with("configuration:"), "{e}");
    for bad in [
        "cooling:100:20",
        "ramp:20:80:-5",
        "constant",
        "steps::600",
        "heat:30",
        "constant:hot",
    ] {
        assert!(Profile::parse(bad).is_err(), "{bad}");
    }
    assert_eq!(
        Profile::parse("steps:30,45:600").unwrap(),
        Profile::Steps {
            levels_c: vec![30.0, 45.0],
            hold_s: 600.0,
            heater_tau_s: 120.0
        }
    );
}

#[test]
fn a_toml_configuration_round_trips() {
    let cfg = presets::preset("mpu9250-thesis").unwrap();
    let text = toml::to_string(&cfg).unwrap();
    let back = SimConfig::from_toml(&text).unwrap();
    assert_eq!(back, cfg);
}
