//! Named configurations.
//!
//! ## `mpu9250-thesis`
//!
//! Calibrated to the thesis *Temperature Dependency of a Low-cost IMU*
//! (Y. Duan, University of Stuttgart): its result tables of one-hour runs at
//! 34, 43, 62 and 82 °C, its sample log rows, and the MPU-9250 datasheet
//! (PS-MPU-9250A-01 rev 1.1).
//!
//! - **White noise N** per axis: the 34 °C column of the ARW/VRW tables
//!   (gyro 0.0084, 0.0087, 0.0088 °/√s; accel 0.0046, 0.0045, 0.0072
//!   m/s/√s), read as IEEE 952's N (the −1/2 line at τ = 1 s).
//! - **Bias instability B and rate random walk K.** The thesis's "bias
//!   instability" columns are the *raw* ADEV minimum σ_min at its τ (gyro
//!   0.0042 °/s at 19.9 s, 0.0036 at 33.7 s, 0.0041 at 27.3 s; accel 0.0016
//!   m/s² at 46.1 s, 0.0015 at 37.4 s, 0.0016 at 86.6 s), not IEEE 952's B =
//!   σ_min/0.664: there, white noise and rate random walk lift the curve
//!   above the flicker floor 0.664·B. This preset takes neither reading as
//!   B directly: it solves the IEEE 952 model σ²(τ) = N²/τ + (0.664·B)² +
//!   K²τ/3 for the B and K that put the minimum at the thesis's σ_min *and*
//!   at its τ: K = √3·N/τ_min, (0.664·B)² = σ_min² − 2N²/τ_min (see
//!   [`calibrate`]). That gives 0.664·B = 0.72–0.81·σ_min, i.e. B =
//!   1.09–1.22·σ_min (the IEEE reading σ_min/0.664 would be 1.51·σ_min), and K
//!   of 4.5–7.3e-4 °/s/√s (gyro), 1.4–2.1e-4 m/s²/√s (accel).
//! - **Noise over temperature**: every term scales with the die
//!   temperature by the mean growth of the ARW/VRW tables over the three
//!   axes (gyro ×1.031, ×1.073, ×1.131 and accel ×1.067, ×1.080, ×1.129 at
//!   43, 62, 82 °C against 34 °C), held beyond 34 and 82 °C.
//! - **Output stage**: ±500 °/s and ±8 g, the full scales of the thesis's
//!   logs (their values step by 1/65.5 °/s and 1/4096 g).
//! - **Attitude and offsets** from the thesis's sample rows (accel ≈ 0.88,
//!   0.21, 9.36 m/s²; gyro ≈ −0.0368, 0.0233, 0.0195 rad/s): the board
//!   pitched −5.14° and rolled 1.23° (which puts 0.88 and 0.21 m/s² of
//!   gravity on x and y), a z zero-g offset of −41 mg (datasheet: ±80 mg),
//!   gyro zero-rate offsets of −2.1, 1.33, 1.1 °/s (datasheet: ±5 °/s).
//! - **Bias over temperature**, datasheet-sized: gyro offsets drifting
//!   0.01–0.02 °/s/°C with a small curvature (the datasheet bounds the
//!   zero-rate output to ±30 °/s over −40…85 °C), accelerometer zero-g
//!   drifting 0.6–1.2 mg/°C at 34 °C and under 1.5 mg/°C anywhere in
//!   20…100 °C (datasheet: ±1.5 mg/°C). Polynomials in T − 34 °C, so that
//!   the constant terms are the offsets of the sample rows, at 34 °C.
//! - **Run**: one hour at 20 Hz, the chamber at 34 °C ± 0.05 °C, the die
//!   lagging it by 120 s; flicker flat from 1 s to 2000 s. 20 Hz is the
//!   thesis's own rate: its analysis scripts set Fs = 20 Hz
//!   (`DataAnalysisCode/para_main.m` and `cooling_main.m` in the public
//!   repository dyx1994/Temperature-dependency-of-a-low-cost-IMU), and its
//!   3D ADEV takes windows of 36 001 samples (30 min) stepped by 1800
//!   samples (90 s) at that rate. The noise terms are densities, so the
//!   rate changes none of them; the LSB rounding adds less white noise
//!   (LSB²·τ0/12 grows with τ0 but stays under 1 % of N² here).
//!
//! ## `white`
//!
//! White noise only (N = 1.5e-4 rad/√s, 5e-3 m/s/√s), no bias, no
//! temperature dependence, no output quantization, level: the simplest
//! truth to test an analysis against.

use std::f64::consts::PI;

use crate::SimError;
use crate::config::{GroupConfig, SensorConfig, SimConfig};
use crate::simulate::FLICKER_FLOOR;
use crate::terms::NoiseTerms;
use crate::thermal::Profile;

/// The thesis's sample rate, Hz (`Fs = 20` in its analysis scripts).
pub const THESIS_RATE_HZ: f64 = 20.0;

/// The preset names.
pub const NAMES: [&str; 2] = ["mpu9250-thesis", "white"];

const DEG: f64 = PI / 180.0;
const MG: f64 = earth::STANDARD_GRAVITY * 1e-3;

/// The thesis's 34 °C tables per axis x, y, z: N (°/√s), the ADEV minimum
/// σ_min (°/s) and the τ where it was found (s).
pub const THESIS_GYRO_34C: [(f64, f64, f64); 3] = [
    (0.0084, 0.0042, 19.9),
    (0.0087, 0.0036, 33.7),
    (0.0088, 0.0041, 27.3),
];
/// As [`THESIS_GYRO_34C`] for the accelerometer: m/s/√s, m/s², s.
pub const THESIS_ACCEL_34C: [(f64, f64, f64); 3] = [
    (0.0046, 0.0016, 46.1),
    (0.0045, 0.0015, 37.4),
    (0.0072, 0.0016, 86.6),
];

/// The preset called `name`.
pub fn preset(name: &str) -> Result<SimConfig, SimError> {
    match name {
        "mpu9250-thesis" => Ok(thesis()),
        "white" => Ok(white()),
        other => Err(SimError::UnknownPreset(other.to_string())),
    }
}

/// B and K such that the IEEE 952 curve N²/τ + (0.664·B)² + K²τ/3 has its
/// minimum σ_min at τ_min: d/dτ = 0 gives τ_min = √3·N/K, and the value there
/// is (0.664·B)² + 2N²/τ_min. None when N alone already exceeds σ_min there.
pub fn calibrate(n: f64, sigma_min: f64, tau_min: f64) -> Option<(f64, f64)> {
    let k = 3f64.sqrt() * n / tau_min;
    let floor2 = sigma_min * sigma_min - 2.0 * n * n / tau_min;
    (floor2 > 0.0).then(|| (floor2.sqrt() / FLICKER_FLOOR, k))
}

fn thesis_terms(table: [(f64, f64, f64); 3], unit: f64) -> [NoiseTerms; 3] {
    table.map(|(n, sigma_min, tau_min)| {
        // Every row of the tables leaves room for a flicker floor (a test
        // checks it); white noise alone is the fallback.
        let (b, k) = calibrate(n, sigma_min, tau_min).unwrap_or((0.0, 0.0));
        NoiseTerms {
            q: 0.0,
            n: n * unit,
            b: b * unit,
            k: k * unit,
            r: 0.0,
        }
    })
}

fn thesis() -> SimConfig {
    SimConfig {
        rate_hz: THESIS_RATE_HZ,
        duration_s: 3600.0,
        seed: 1,
        t_ref_c: 34.0,
        sensor_lag_s: 120.0,
        profile: Profile::constant(34.0, 0.05),
        sensor: SensorConfig {
            gyro_range_dps: 500.0,
            accel_range_g: 8.0,
            quantize: true,
            roll_deg: 1.23,
            pitch_deg: -5.14,
            ..SensorConfig::default()
        },
        gyro: GroupConfig {
            terms: thesis_terms(THESIS_GYRO_34C, DEG),
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
            terms: thesis_terms(THESIS_ACCEL_34C, 1.0),
            bias: [
                vec![0.0, 0.8 * MG, 2e-5],
                vec![0.0, -0.6 * MG, -1e-5],
                vec![-41.0 * MG, 1.2 * MG, 1.5e-5],
            ],
            scale_factor: [0.0; 3],
            flicker_tau_s: [1.0, 2000.0],
            noise_scale: vec![[34.0, 1.0], [43.0, 1.067], [62.0, 1.080], [82.0, 1.129]],
        },
    }
}

fn white() -> SimConfig {
    // White noise of density `n` on each axis, nothing else.
    let white_group = |n: f64| GroupConfig {
        terms: [NoiseTerms {
            n,
            ..NoiseTerms::default()
        }; 3],
        bias: Default::default(),
        scale_factor: [0.0; 3],
        flicker_tau_s: [1.0, 1000.0],
        noise_scale: Vec::new(),
    };
    SimConfig {
        rate_hz: 100.0,
        duration_s: 600.0,
        seed: 1,
        t_ref_c: 25.0,
        sensor_lag_s: 0.0,
        profile: Profile::constant(25.0, 0.0),
        sensor: SensorConfig {
            quantize: false,
            ..SensorConfig::default()
        },
        gyro: white_group(1.5e-4),
        accel: white_group(5e-3),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_model_minimum_is_the_thesis_minimum() {
        let cfg = thesis();
        for (group, table, unit) in [
            (&cfg.gyro, THESIS_GYRO_34C, DEG),
            (&cfg.accel, THESIS_ACCEL_34C, 1.0),
        ] {
            for (t, (n, sigma_min, tau_min)) in group.terms.iter().zip(table) {
                assert!(t.b > 0.0 && t.k > 0.0, "{t:?}");
                assert!((t.n / unit - n).abs() < 1e-12);
                // Search the IEEE 952 curve on a fine grid for its minimum.
                let (tau, dev) = (0..4000)
                    .map(|i| {
                        let tau = 10f64.powf(-1.0 + 4.0 * i as f64 / 4000.0);
                        (tau, t.allan_variance(tau).sqrt() / unit)
                    })
                    .fold((0.0, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a });
                assert!((dev / sigma_min - 1.0).abs() < 1e-4, "{dev} vs {sigma_min}");
                assert!((tau / tau_min - 1.0).abs() < 0.01, "{tau} vs {tau_min}");
            }
        }
    }

    #[test]
    fn bias_drift_is_of_datasheet_size() {
        let cfg = thesis();
        for axis in 0..3 {
            for i in 0..=80 {
                let t = 20.0 + i as f64;
                let bias = |t: f64| cfg.accel.bias_at(axis, t, cfg.t_ref_c);
                let slope = (bias(t + 0.5) - bias(t - 0.5)) / MG;
                assert!(slope.abs() < 1.5, "accel {axis} at {t} °C: {slope} mg/°C");
                let gyro = cfg.gyro.bias_at(axis, t, cfg.t_ref_c) / DEG;
                assert!(gyro.abs() < 5.0, "gyro {axis} at {t} °C: {gyro} °/s");
            }
        }
    }

    #[test]
    fn unknown_names_are_refused_with_the_known_ones() {
        let e = preset("mpu6050").unwrap_err().to_string();
        assert!(
            e.contains("'mpu6050'") && e.contains("mpu9250-thesis, white"),
            "{e}"
        );
    }
}
