//! Named configurations.
//!
//! `mpu9250-thesis` is calibrated to the thesis *Temperature Dependency of a
//! Low-cost IMU* (result tables, 34/43/62/82 °C runs of one hour):
//! - white noise N per axis at 34 °C from its ARW/VRW tables (gyro 0.0084,
//!   0.0087, 0.0088 °/√s; accel 0.0046, 0.0045, 0.0072 m/s/√s), scaled over
//!   temperature by the mean growth of those tables (gyro ×1.13, accel ×1.13
//!   at 82 °C);
//! - bias instability: the thesis quotes the raw ADEV minimum σ_min "at τ s",
//!   which N and K lift above the flicker floor 0.664·B; B is set so that
//!   0.664·B is 85 % of the quoted σ_min (gyro 0.0042, 0.0036, 0.0041 °/s;
//!   accel 0.0016, 0.0015, 0.0016 m/s²), which puts the simulated minimum
//!   near the quoted one;
//! - rate random walk sized so that the ADEV turns up after a few hundred
//!   seconds, as in the thesis's plots;
//! - bias over temperature of datasheet size (PS-MPU-9250A-01): gyro offsets
//!   of the thesis's sample rows (−2.1, 1.3, 1.1 °/s) drifting by
//!   0.01–0.02 °/s/°C (well inside the ±30 °/s zero-rate output over
//!   −40…85 °C), accelerometer zero-g drifting by 0.6–1.2 mg/°C (inside
//!   ±1.5 mg/°C);
//! - ±250 °/s and ±2 g full scale, level orientation, one hour at 100 Hz at
//!   34 °C ± 0.05 °C, sensor temperature lagging the chamber by 120 s.
//!
//! `white` is a sensor with white noise only and no output quantization:
//! the simplest truth to test an analysis against.

use std::f64::consts::PI;

use crate::SimError;
use crate::config::{GroupConfig, SensorConfig, SimConfig};
use crate::terms::NoiseTerms;
use crate::thermal::Profile;

/// The preset names.
pub const NAMES: [&str; 2] = ["mpu9250-thesis", "white"];

const DEG: f64 = PI / 180.0;
const MG: f64 = 9.806_65e-3;

/// The preset called `name`.
pub fn preset(name: &str) -> Result<SimConfig, SimError> {
    match name {
        "mpu9250-thesis" => Ok(thesis()),
        "white" => Ok(white()),
        other => Err(SimError::UnknownPreset(other.to_string())),
    }
}

fn terms(n: f64, b: f64, k: f64) -> NoiseTerms {
    NoiseTerms {
        q: 0.0,
        n,
        b,
        k,
        r: 0.0,
    }
}

fn thesis() -> SimConfig {
    let b = |sigma_min: f64| sigma_min * 0.85 / 0.664;
    SimConfig {
        rate_hz: 100.0,
        duration_s: 3600.0,
        seed: 1,
        t_ref_c: 25.0,
        sensor_lag_s: 120.0,
        profile: Profile::Constant {
            temp_c: 34.0,
            fluctuation_c: 0.05,
            fluctuation_tau_s: 60.0,
        },
        sensor: SensorConfig::default(),
        gyro: GroupConfig {
            terms: [
                terms(0.0084 * DEG, b(0.0042) * DEG, 3.6e-4 * DEG),
                terms(0.0087 * DEG, b(0.0036) * DEG, 3.6e-4 * DEG),
                terms(0.0088 * DEG, b(0.0041) * DEG, 3.6e-4 * DEG),
            ],
            bias: [
                vec![-2.1 * DEG, 0.02 * DEG, 1e-4 * DEG],
                vec![1.33 * DEG, -0.015 * DEG, -5e-5 * DEG],
                vec![1.1 * DEG, 0.01 * DEG, 8e-5 * DEG],
            ],
            scale_factor: [0.0; 3],
            flicker_tau_s: [1.0, 2000.0],
            noise_scale: vec![[34.0, 1.0], [43.0, 1.031], [62.0, 1.073], [82.0, 1.131]],
        },
        accel: GroupConfig {
            terms: [
                terms(0.0046, b(0.0016), 1.5e-4),
                terms(0.0045, b(0.0015), 1.5e-4),
                terms(0.0072, b(0.0016), 1.5e-4),
            ],
            bias: [
                vec![0.88, 0.8 * MG, 2e-5],
                vec![0.21, -0.6 * MG, -1e-5],
                vec![-0.45, 1.2 * MG, 3e-5],
            ],
            scale_factor: [0.0; 3],
            flicker_tau_s: [1.0, 2000.0],
            noise_scale: vec![[34.0, 1.0], [43.0, 1.067], [62.0, 1.080], [82.0, 1.129]],
        },
    }
}

fn white() -> SimConfig {
    let w = |n: f64| NoiseTerms {
        n,
        ..NoiseTerms::default()
    };
    SimConfig {
        rate_hz: 100.0,
        duration_s: 600.0,
        seed: 1,
        t_ref_c: 25.0,
        sensor_lag_s: 0.0,
        profile: Profile::Constant {
            temp_c: 25.0,
            fluctuation_c: 0.0,
            fluctuation_tau_s: 60.0,
        },
        sensor: SensorConfig {
            quantize: false,
            ..SensorConfig::default()
        },
        gyro: GroupConfig {
            terms: [w(1.5e-4); 3],
            bias: Default::default(),
            scale_factor: [0.0; 3],
            flicker_tau_s: [1.0, 1000.0],
            noise_scale: Vec::new(),
        },
        accel: GroupConfig {
            terms: [w(5e-3); 3],
            bias: Default::default(),
            scale_factor: [0.0; 3],
            flicker_tau_s: [1.0, 1000.0],
            noise_scale: Vec::new(),
        },
    }
}
