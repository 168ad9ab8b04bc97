//! The simulation's configuration, as written in TOML. Every value is SI
//! (rad/s and m/s² based), temperatures in °C, times in s.
//!
//! ```toml
//! rate_hz = 100.0
//! duration_s = 3600.0
//! seed = 1
//! t_ref_c = 25.0          # reference temperature of the bias polynomials
//! sensor_lag_s = 60.0     # the die's temperature lags the chamber's (first order)
//!
//! [profile]
//! kind = "cooling"        # constant | cooling | ramp | steps | file
//! start_c = 100.0         # constant: temp_c, fluctuation_c, fluctuation_tau_s
//! ambient_c = 20.0        # ramp: from_c, to_c, duration_s
//! tau_s = 1800.0          # steps: levels_c = [..], hold_s, heater_tau_s; file: path
//!
//! [sensor]
//! gyro_range_dps = 250.0  # 250 | 500 | 1000 | 2000
//! accel_range_g = 2.0     # 2 | 4 | 8 | 16
//! quantize = true         # 16-bit LSB rounding and clipping, temperature sensor too
//! roll_deg = 0.0          # static orientation: gravity on the accelerometers
//! pitch_deg = 0.0
//! # heading_deg = 0.0     # clockwise from north; with latitude_deg, the Earth
//! # latitude_deg = 48.0   # rotates: gyros read its rate, accels normal gravity
//!
//! [gyro]                  # per axis x, y, z; rad/s
//! # IEEE 952 terms: q rad, n rad/√s, b rad/s, k rad/s/√s, r rad/s²
//! terms = [{ n = 1.5e-4, b = 6e-5, k = 5e-6 }, { n = 1.5e-4 }, { n = 1.5e-4 }]
//! bias = [[-0.036, 3e-4], [0.023], [0.019]]   # polynomial in (T − t_ref), ascending powers
//! scale_factor = [0.0, 0.0, 0.0]              # 0.01 = +1 % on the true input
//! flicker_tau_s = [1.0, 1000.0]               # where B is flat
//! noise_scale = [[34.0, 1.0], [82.0, 1.13]]   # (°C, factor) on Q, N, B and K; interpolated
//!
//! [accel]                 # m/s²: q m/s, n m/s/√s, b m/s², k m/s²/√s, r m/s³
//! terms = [{ n = 4.6e-3 }, { n = 4.5e-3 }, { n = 7.2e-3 }]
//! ```

use serde::{Deserialize, Serialize};

use crate::SimError;
use crate::terms::NoiseTerms;
use crate::thermal::Profile;

/// Everything about one simulated recording.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimConfig {
    /// Output sample rate, Hz.
    pub rate_hz: f64,
    /// Duration, s.
    pub duration_s: f64,
    /// Seed of every random stream.
    #[serde(default)]
    pub seed: u64,
    /// Reference temperature of the bias polynomials, °C.
    #[serde(default = "default_t_ref")]
    pub t_ref_c: f64,
    /// First-order lag of the sensor's temperature behind the chamber's, s.
    #[serde(default)]
    pub sensor_lag_s: f64,
    /// The chamber temperature.
    pub profile: Profile,
    /// The MPU-9250 output stage.
    #[serde(default)]
    pub sensor: SensorConfig,
    /// The three gyroscope axes, rad/s.
    pub gyro: GroupConfig,
    /// The three accelerometer axes, m/s².
    pub accel: GroupConfig,
}

fn default_t_ref() -> f64 {
    25.0
}

/// The sensor's output stage.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorConfig {
    /// Gyroscope full scale, °/s.
    pub gyro_range_dps: f64,
    /// Accelerometer full scale, g.
    pub accel_range_g: f64,
    /// Quantize to the full scale's LSB and clip at it, as the chip does.
    pub quantize: bool,
    /// Static roll, degrees.
    #[serde(default)]
    pub roll_deg: f64,
    /// Static pitch, degrees.
    #[serde(default)]
    pub pitch_deg: f64,
    /// Static heading, degrees clockwise from north (only matters with a
    /// latitude: it decides where the Earth's rotation shows).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub heading_deg: f64,
    /// Geodetic latitude, degrees. When given, the Earth rotates: the gyros
    /// read its rate for the latitude and attitude, and the accelerometers
    /// read the normal gravity there instead of standard gravity.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub latitude_deg: Option<f64>,
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

impl Default for SensorConfig {
    fn default() -> Self {
        SensorConfig {
            gyro_range_dps: 250.0,
            accel_range_g: 2.0,
            quantize: true,
            roll_deg: 0.0,
            pitch_deg: 0.0,
            heading_deg: 0.0,
            latitude_deg: None,
        }
    }
}

/// Three axes of one sensor.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroupConfig {
    /// Noise terms at the reference noise scale, per axis.
    pub terms: [NoiseTerms; 3],
    /// Bias polynomial per axis in (T − t_ref), ascending powers, SI.
    #[serde(default)]
    pub bias: [Vec<f64>; 3],
    /// Scale-factor error per axis (0.01 = +1 %).
    #[serde(default)]
    pub scale_factor: [f64; 3],
    /// The τ range (s) over which bias instability is flat.
    #[serde(default = "default_flicker_range")]
    pub flicker_tau_s: [f64; 2],
    /// Noise scale over temperature: (°C, factor) points, linearly
    /// interpolated and held beyond the ends; empty means 1.
    #[serde(default)]
    pub noise_scale: Vec<[f64; 2]>,
}

fn default_flicker_range() -> [f64; 2] {
    [1.0, 1000.0]
}

impl GroupConfig {
    /// The noise factor at temperature `t`.
    pub fn noise_factor(&self, t: f64) -> f64 {
        let s = &self.noise_scale;
        match s.iter().position(|p| p[0] > t) {
            None => s.last().map_or(1.0, |p| p[1]),
            Some(0) => s[0][1],
            Some(i) => {
                let (a, b) = (s[i - 1], s[i]);
                a[1] + (b[1] - a[1]) * (t - a[0]) / (b[0] - a[0])
            }
        }
    }

    /// The bias at temperature `t` on `axis`.
    pub fn bias_at(&self, axis: usize, t: f64, t_ref: f64) -> f64 {
        let x = t - t_ref;
        self.bias[axis].iter().rev().fold(0.0, |acc, c| acc * x + c)
    }

    fn validate(&self, group: &str) -> Result<(), SimError> {
        for (i, t) in self.terms.iter().enumerate() {
            t.validate(&format!("{group}.terms[{i}]"))?;
        }
        let bad =
            |name: String, value: f64, why: &'static str| SimError::InvalidParameter { name, value, why };
        for (i, poly) in self.bias.iter().enumerate() {
            if let Some(&c) = poly.iter().find(|c| !c.is_finite()) {
                return Err(bad(format!("{group}.bias[{i}]"), c, "must be finite"));
            }
        }
        for (i, &sf) in self.scale_factor.iter().enumerate() {
            if !(sf.is_finite() && sf > -1.0) {
                return Err(bad(
                    format!("{group}.scale_factor[{i}]"),
                    sf,
                    "must be finite and above −1",
                ));
            }
        }
        let [lo, hi] = self.flicker_tau_s;
        if !(lo > 0.0 && hi >= lo && hi.is_finite()) {
            return Err(bad(
                format!("{group}.flicker_tau_s"),
                lo,
                "must be 0 < low ≤ high, in seconds",
            ));
        }
        if let Some(p) = self.noise_scale.iter().find(|p| !p[0].is_finite()) {
            return Err(bad(
                format!("{group}.noise_scale"),
                p[0],
                "temperatures must be finite numbers of °C",
            ));
        }
        for (i, w) in self.noise_scale.windows(2).enumerate() {
            if w[1][0] <= w[0][0] {
                return Err(bad(
                    format!("{group}.noise_scale[{}]", i + 1),
                    w[1][0],
                    "temperatures must increase",
                ));
            }
        }
        if let Some(p) = self
            .noise_scale
            .iter()
            .find(|p| !(p[1].is_finite() && p[1] >= 0.0))
        {
            return Err(bad(
                format!("{group}.noise_scale"),
                p[1],
                "factors must be finite and ≥ 0",
            ));
        }
        Ok(())
    }
}

impl SimConfig {
    /// Reads a TOML configuration.
    pub fn from_toml(text: &str) -> Result<SimConfig, SimError> {
        let c: SimConfig = toml::from_str(text).map_err(|e| SimError::Config(e.to_string()))?;
        c.validate()?;
        Ok(c)
    }

    /// Checks every parameter; an error names the first wrong one.
    pub fn validate(&self) -> Result<(), SimError> {
        if !(self.rate_hz.is_finite() && self.rate_hz > 0.0) {
            return Err(SimError::InvalidParameter {
                name: "rate_hz".into(),
                value: self.rate_hz,
                why: "the sample rate must be a positive number of Hz",
            });
        }
        if !(self.duration_s.is_finite() && self.duration_s > 0.0) {
            return Err(SimError::InvalidParameter {
                name: "duration_s".into(),
                value: self.duration_s,
                why: "the duration must be a positive number of seconds",
            });
        }
        for (name, v) in [
            ("t_ref_c", self.t_ref_c),
            ("sensor.roll_deg", self.sensor.roll_deg),
            ("sensor.pitch_deg", self.sensor.pitch_deg),
            ("sensor.heading_deg", self.sensor.heading_deg),
        ] {
            if !v.is_finite() {
                return Err(SimError::InvalidParameter {
                    name: name.into(),
                    value: v,
                    why: "must be a finite number",
                });
            }
        }
        if let Some(lat) = self.sensor.latitude_deg
            && !(lat.is_finite() && lat.abs() <= 90.0)
        {
            return Err(SimError::InvalidParameter {
                name: "sensor.latitude_deg".into(),
                value: lat,
                why: "must be a latitude from −90 to 90 degrees",
            });
        }
        if !(self.sensor_lag_s.is_finite() && self.sensor_lag_s >= 0.0) {
            return Err(SimError::InvalidParameter {
                name: "sensor_lag_s".into(),
                value: self.sensor_lag_s,
                why: "must be ≥ 0 s",
            });
        }
        if ![250.0, 500.0, 1000.0, 2000.0].contains(&self.sensor.gyro_range_dps) {
            return Err(SimError::InvalidParameter {
                name: "sensor.gyro_range_dps".into(),
                value: self.sensor.gyro_range_dps,
                why: "the MPU-9250 has 250, 500, 1000 or 2000 °/s",
            });
        }
        if ![2.0, 4.0, 8.0, 16.0].contains(&self.sensor.accel_range_g) {
            return Err(SimError::InvalidParameter {
                name: "sensor.accel_range_g".into(),
                value: self.sensor.accel_range_g,
                why: "the MPU-9250 has 2, 4, 8 or 16 g",
            });
        }
        self.profile.validate()?;
        self.gyro.validate("gyro")?;
        self.accel.validate("accel")
    }

    /// Number of samples.
    pub fn samples(&self) -> u64 {
        (self.duration_s * self.rate_hz).round() as u64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_documented_example_is_a_valid_configuration() {
        let source = include_str!("config.rs");
        let start = source.find("//! ```toml\n").map(|i| i + 12).unwrap_or(0);
        let end = start + source[start..].find("//! ```").unwrap_or(0);
        let toml: String = source[start..end]
            .lines()
            .map(|l| l.trim_start_matches("//!").trim_start_matches(' '))
            .collect::<Vec<_>>()
            .join("\n");
        let cfg = SimConfig::from_toml(&toml).unwrap();
        assert_eq!(cfg.samples(), 360_000);
        assert_eq!(cfg.gyro.terms[0].k, 5e-6);
        assert_eq!(cfg.accel.bias[2], Vec::<f64>::new());
        assert!((cfg.gyro.noise_factor(58.0) - 1.065).abs() < 1e-12);
        assert_eq!(cfg.gyro.noise_factor(0.0), 1.0);
        assert_eq!(cfg.gyro.noise_factor(100.0), 1.13);
    }
}
