//! The simulator against the theory it claims: each IEEE 952 term alone
//! follows its Allan deviation, the bias follows its polynomial of
//! temperature, seeds reproduce, bad configurations are refused.

use allan::{Options, Point, TauSpec, analyze};
use imusim::config::{GroupConfig, SimConfig};
use imusim::terms::NoiseTerms;
use imusim::thermal::Profile;
use imusim::{Simulator, presets};

/// A 2 h, 10 Hz recording whose gyro x has only `terms`, without output
/// quantization.
fn one_term(terms: NoiseTerms, seed: u64) -> (Vec<f64>, f64) {
    let mut cfg = presets::preset("white").unwrap();
    cfg.rate_hz = 10.0;
    cfg.duration_s = 7200.0;
    cfg.seed = seed;
    cfg.gyro.terms[0] = terms;
    cfg.gyro.flicker_tau_s = [1.0, 2000.0];
    let rec = Simulator::new(cfg).unwrap().recording(None).unwrap();
    (rec.channel("gyro_x").unwrap().data.clone(), 10.0)
}

fn oadev(y: &[f64], rate: f64, confidence: f64) -> Vec<Point> {
    let opts = Options {
        rate_hz: rate,
        taus: TauSpec::Octave,
        confidence,
        ..Options::default()
    };
    analyze(y, &opts).unwrap().points
}

/// Every octave tau of a term alone: the theory inside the 99.9 % interval
/// (so that a dozen points all hitting is what a correct generator does).
fn follows_theory(terms: NoiseTerms, seed: u64, taus: impl Fn(f64) -> bool, slack: f64) {
    let (y, rate) = one_term(terms, seed);
    let pts = oadev(&y, rate, 0.999);
    let mut checked = 0;
    for p in pts.iter().filter(|p| taus(p.tau)) {
        let theory = terms.allan_variance(p.tau).sqrt();
        assert!(
            p.dev_lo / slack <= theory && theory <= p.dev_hi * slack,
            "{terms:?} τ = {}: theory {theory:.4e} outside [{:.4e}, {:.4e}] (dev {:.4e})",
            p.tau,
            p.dev_lo,
            p.dev_hi,
            p.dev
        );
        checked += 1;
    }
    assert!(checked >= 5, "only {checked} taus checked");
}

#[test]
fn white_noise_alone() {
    let t = NoiseTerms {
        n: 2e-3,
        ..NoiseTerms::default()
    };
    follows_theory(t, 3, |_| true, 1.0);
}

#[test]
fn quantization_noise_alone() {
    let t = NoiseTerms {
        q: 1e-4,
        ..NoiseTerms::default()
    };
    follows_theory(t, 4, |_| true, 1.0);
}

#[test]
fn rate_random_walk_alone() {
    let t = NoiseTerms {
        k: 1e-4,
        ..NoiseTerms::default()
    };
    follows_theory(t, 5, |_| true, 1.0);
}

#[test]
fn bias_instability_alone_is_flat_within_ten_percent() {
    // Flat over the stated range [1, 2000] s; the test looks inside it,
    // allowing the ±10 % the generator promises on top of the interval.
    let t = NoiseTerms {
        b: 1e-3,
        ..NoiseTerms::default()
    };
    follows_theory(t, 6, |tau| (2.0..=800.0).contains(&tau), 1.1);
}

#[test]
fn rate_ramp_alone_is_exact() {
    let t = NoiseTerms {
        r: 1e-6,
        ..NoiseTerms::default()
    };
    let (y, rate) = one_term(t, 7);
    for p in oadev(&y, rate, 0.683) {
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
    // Independent: the white parts of two seeds are uncorrelated.
    let mut w = presets::preset("white").unwrap();
    w.duration_s = 100.0;
    let x = Simulator::new(w.clone()).unwrap().recording(None).unwrap();
    w.seed = 2;
    let y = Simulator::new(w).unwrap().recording(None).unwrap();
    let (a, b) = (
        &x.channel("gyro_x").unwrap().data,
        &y.channel("gyro_x").unwrap().data,
    );
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let cov: f64 = a.iter().zip(b).map(|(p, q)| (p - ma) * (q - mb)).sum::<f64>() / n;
    let sa = (a.iter().map(|p| (p - ma).powi(2)).sum::<f64>() / n).sqrt();
    let sb = (b.iter().map(|q| (q - mb).powi(2)).sum::<f64>() / n).sqrt();
    let rho = cov / (sa * sb);
    // 10^4 samples: |ρ| < 4/√n for independent series.
    assert!(rho.abs() < 4.0 / n.sqrt(), "ρ = {rho}");
    // And the axes of one seed are independent of each other.
    let c = &x.channel("gyro_y").unwrap().data;
    let mc = c.iter().sum::<f64>() / n;
    let cov2: f64 = a.iter().zip(c).map(|(p, q)| (p - ma) * (q - mc)).sum::<f64>() / n;
    assert!(
        (cov2 / (sa * (c.iter().map(|q| (q - mc).powi(2)).sum::<f64>() / n).sqrt())).abs() < 4.0 / n.sqrt()
    );
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
            *t = NoiseTerms {
                n: t.n,
                ..NoiseTerms::default()
            };
        }
    }
    let sim = Simulator::new(cfg.clone()).unwrap();
    let mut temps = Vec::new();
    let mut gx = Vec::new();
    sim.run(|chunk| {
        temps.extend_from_slice(&chunk.true_temperature);
        gx.extend_from_slice(&chunk.columns[3]);
        Ok(())
    })
    .unwrap();
    assert!(temps[0] > 99.0 && *temps.last().unwrap() < 30.0);
    let g: &GroupConfig = &cfg.gyro;
    // Residual of the output against the polynomial at the die temperature,
    // averaged over blocks of 600 samples: within 4 standard errors.
    let per_sample = g.terms[0].n * cfg.rate_hz.sqrt() * g.noise_factor(100.0);
    let lsb = imusim::sensor::gyro_lsb_rad(250.0);
    for (tb, yb) in temps.chunks(600).zip(gx.chunks(600)) {
        let resid: f64 = tb
            .iter()
            .zip(yb)
            .map(|(&t, &y)| y - g.bias_at(0, t, cfg.t_ref_c))
            .sum::<f64>()
            / yb.len() as f64;
        let se = (per_sample * per_sample + lsb * lsb / 12.0).sqrt() / (yb.len() as f64).sqrt();
        assert!(
            resid.abs() < 4.0 * se,
            "T ≈ {:.1} °C: residual {resid:.3e} > 4·{se:.3e}",
            tb[0]
        );
    }
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
    assert!(
        Simulator::new(cfg)
            .unwrap_err()
            .to_string()
            .contains("rate_hz = 0")
    );
    let e = SimConfig::from_toml("rate_hz = 100\nduration_s = 1\n").unwrap_err();
    assert!(e.to_string().starts_with("configuration:"), "{e}");
    assert!(Profile::parse("cooling:100:20").is_err());
    assert!(Profile::parse("ramp:20:80:-5").is_err());
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
