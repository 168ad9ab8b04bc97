//! The cross-check of the navigation's closed form: simulate the identified
//! model (the imusim generator, same terms, no temperature effect, no
//! quantization), navigate each run exactly as a recording is navigated
//! (`ins`), and take the statistics over the runs.
//!
//! It lives here, above both the simulator and the navigation, so that the
//! navigation crate does not link the simulator.

use rayon::prelude::*;

use imusim::config::{GroupConfig, SensorConfig};
use imusim::terms::NoiseTerms;
use imusim::thermal::Profile;
use imusim::{SimConfig, Simulator};

use ins::InsError;
use ins::drift::{CurvePoint, curve_of, rms_interval_95};
use ins::prediction::{AxisNoise, NoiseModel};
use ins::strapdown::{ImuData, NavOptions, StaticError, align_samples, navigate_window};

/// Why a Monte Carlo gave no figures.
#[derive(Debug, thiserror::Error)]
pub enum MonteCarloError {
    /// The setup or a simulated run's navigation was refused.
    #[error(transparent)]
    Navigation(#[from] InsError),
    /// The simulator refused the identified model.
    #[error("simulating the identified model: {0}")]
    Simulation(#[from] imusim::SimError),
}

/// What to simulate besides the noise.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MonteCarloSetup {
    /// Sample rate, Hz.
    pub rate_hz: f64,
    /// Runs.
    pub runs: usize,
    /// Seed of the first run; run i uses seed + i.
    pub seed: u64,
    /// Static roll and pitch of the simulated sensor, degrees.
    pub roll_deg: f64,
    pub pitch_deg: f64,
}

fn group(axes: &[AxisNoise; 3]) -> GroupConfig {
    GroupConfig {
        terms: axes.map(|a| NoiseTerms {
            n: a.n,
            b: a.b,
            k: a.k,
            ..NoiseTerms::default()
        }),
        bias: Default::default(),
        scale_factor: [0.0; 3],
        flicker_tau_s: [1.0, 1000.0],
        noise_scale: Vec::new(),
    }
}

/// What the runs give at each time.
#[derive(Debug, Clone, PartialEq)]
pub struct MonteCarlo {
    /// The spreads over the runs, one point per time.
    pub curve: Vec<CurvePoint>,
    /// The 95 % confidence interval of the horizontal position rms (the
    /// DRMS), m, per time: how far the runs' figure may be from the model's.
    /// Its half-width is about 1.96/(2·√runs) of the rms.
    pub horizontal_rms_95: Vec<[f64; 2]>,
    /// The same for the height's rms.
    pub vertical_rms_95: Vec<[f64; 2]>,
}

/// The error spreads over `setup.runs` simulated runs of `model`, at each
/// time of `times_s`.
pub fn monte_carlo(
    model: &NoiseModel,
    opts: &NavOptions,
    setup: &MonteCarloSetup,
    times_s: &[f64],
) -> Result<MonteCarlo, MonteCarloError> {
    opts.validate()?;
    if setup.runs == 0 {
        return Err(InsError::Invalid("a Monte Carlo needs at least one run".into()).into());
    }
    let mut times = times_s.to_vec();
    times.sort_by(f64::total_cmp);
    let horizon = times.last().copied().unwrap_or(0.0);
    let samples = align_samples(opts.align_s, setup.rate_hz) + (horizon * setup.rate_hz).round() as usize;
    let base = SimConfig {
        rate_hz: setup.rate_hz,
        duration_s: samples as f64 / setup.rate_hz,
        seed: setup.seed,
        t_ref_c: 25.0,
        sensor_lag_s: 0.0,
        profile: Profile::constant(25.0, 0.0),
        sensor: SensorConfig {
            quantize: false,
            roll_deg: setup.roll_deg,
            pitch_deg: setup.pitch_deg,
            latitude_deg: opts.latitude_deg,
            ..SensorConfig::default()
        },
        gyro: group(&model.gyro),
        accel: group(&model.accel),
    };
    // Checks the model once, before the runs.
    Simulator::new(base.clone())?;
    let runs: Vec<Vec<_>> = (0..setup.runs)
        .into_par_iter()
        .map(|i| -> Result<_, MonteCarloError> {
            let mut cfg = base.clone();
            cfg.seed = setup.seed.wrapping_add(i as u64);
            let chunk = Simulator::new(cfg)?.generator().next_chunk(samples);
            let c = &chunk.columns;
            let imu = ImuData {
                accel: [&c[0], &c[1], &c[2]],
                gyro: [&c[3], &c[4], &c[5]],
                rate_hz: setup.rate_hz,
            };
            navigate_window(&imu, 0, opts, &times)
                .ok_or_else(|| InsError::Invalid("a simulated run could not be navigated".into()).into())
        })
        .collect::<Result<_, _>>()?;
    let interval = |f: fn(&StaticError) -> f64| -> Vec<[f64; 2]> {
        (0..times.len())
            .map(|j| rms_interval_95(&runs.iter().map(|r| f(&r[j])).collect::<Vec<_>>()))
            .collect()
    };
    Ok(MonteCarlo {
        curve: curve_of(&runs, &times),
        horizontal_rms_95: interval(|e| e.horizontal_position_m),
        vertical_rms_95: interval(|e| e.vertical_position_m),
    })
}
