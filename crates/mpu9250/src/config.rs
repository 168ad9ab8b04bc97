//! Configuration: full scales, low-pass filter, sample rate, and the
//! conversion of raw counts to SI that follows from them.

use crate::frame::{RawFrame, Sample};
use crate::regs;

/// Gyroscope full scale.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GyroRange {
    /// ±250 °/s.
    Dps250,
    /// ±500 °/s.
    Dps500,
    /// ±1000 °/s.
    Dps1000,
    /// ±2000 °/s.
    Dps2000,
}

impl GyroRange {
    /// From °/s.
    pub fn from_dps(dps: f64) -> Option<GyroRange> {
        match dps as u32 {
            250 => Some(GyroRange::Dps250),
            500 => Some(GyroRange::Dps500),
            1000 => Some(GyroRange::Dps1000),
            2000 => Some(GyroRange::Dps2000),
            _ => None,
        }
    }

    /// GYRO_FS_SEL, bits 4:3 of GYRO_CONFIG.
    pub fn bits(self) -> u8 {
        (self as u8) << 3
    }

    /// Sensitivity, LSB per °/s (PS-MPU-9250A-01 Table 1).
    pub fn lsb_per_dps(self) -> f64 {
        match self {
            GyroRange::Dps250 => 131.0,
            GyroRange::Dps500 => 65.5,
            GyroRange::Dps1000 => 32.8,
            GyroRange::Dps2000 => 16.4,
        }
    }

    /// One LSB in rad/s.
    pub fn lsb_rad(self) -> f64 {
        core::f64::consts::PI / 180.0 / self.lsb_per_dps()
    }
}

/// Accelerometer full scale.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AccelRange {
    /// ±2 g.
    G2,
    /// ±4 g.
    G4,
    /// ±8 g.
    G8,
    /// ±16 g.
    G16,
}

impl AccelRange {
    /// From g.
    pub fn from_g(g: f64) -> Option<AccelRange> {
        match g as u32 {
            2 => Some(AccelRange::G2),
            4 => Some(AccelRange::G4),
            8 => Some(AccelRange::G8),
            16 => Some(AccelRange::G16),
            _ => None,
        }
    }

    /// ACCEL_FS_SEL, bits 4:3 of ACCEL_CONFIG.
    pub fn bits(self) -> u8 {
        (self as u8) << 3
    }

    /// Sensitivity, LSB per g (PS-MPU-9250A-01 Table 2).
    pub fn lsb_per_g(self) -> f64 {
        16384.0 / f64::from(1u16 << (self as u8))
    }

    /// One LSB in m/s².
    pub fn lsb_si(self) -> f64 {
        earth::STANDARD_GRAVITY / self.lsb_per_g()
    }
}

/// What to set up.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Config {
    /// Gyroscope full scale.
    pub gyro_range: GyroRange,
    /// Accelerometer full scale.
    pub accel_range: AccelRange,
    /// Wanted output rate, Hz (1 kHz / (1 + SMPLRT_DIV): 3.9 Hz to 1 kHz).
    pub rate_hz: f64,
    /// Gyro low-pass bandwidth, Hz; `None`: the widest below half the rate.
    pub dlpf_hz: Option<f64>,
}

impl Default for Config {
    fn default() -> Self {
        Config {
            gyro_range: GyroRange::Dps250,
            accel_range: AccelRange::G2,
            rate_hz: 200.0,
            dlpf_hz: None,
        }
    }
}

/// Gyro DLPF_CFG 1–6 and their bandwidths, Hz (RM-MPU-9250A-00 §4.6).
pub const DLPF_BANDWIDTHS: [(u8, f64); 6] =
    [(1, 184.0), (2, 92.0), (3, 41.0), (4, 20.0), (5, 10.0), (6, 5.0)];

impl Config {
    /// SMPLRT_DIV for the rate, if the rate can be made.
    pub fn divider(&self) -> Option<u8> {
        if !(self.rate_hz.is_finite() && self.rate_hz > 0.0) {
            return None;
        }
        // Rounded to the nearest divisor by hand: `f64::round` needs std, and
        // the quotient is positive, so adding ½ and truncating is the same.
        let div = (regs::INTERNAL_RATE_HZ / self.rate_hz + 0.5) as u64 as f64 - 1.0;
        (0.0..=255.0).contains(&div).then_some(div as u8)
    }

    /// The rate the divider actually gives, Hz.
    pub fn actual_rate_hz(&self) -> Option<f64> {
        self.divider()
            .map(|d| regs::INTERNAL_RATE_HZ / (1.0 + f64::from(d)))
    }

    /// DLPF_CFG: the given bandwidth, or the widest below half the rate so
    /// the output is not aliased.
    pub fn dlpf_cfg(&self) -> u8 {
        let limit = self
            .dlpf_hz
            .unwrap_or(self.actual_rate_hz().unwrap_or(1000.0) / 2.0);
        DLPF_BANDWIDTHS
            .iter()
            .find(|(_, bw)| *bw <= limit)
            .map_or(6, |(cfg, _)| *cfg)
    }

    /// A frame of raw counts in SI units.
    pub fn sample(&self, raw: &RawFrame) -> Sample {
        let a = self.accel_range.lsb_si();
        let g = self.gyro_range.lsb_rad();
        Sample {
            accel: raw.accel.map(|c| f64::from(c) * a),
            gyro: raw.gyro.map(|c| f64::from(c) * g),
            temp_c: f64::from(raw.temp) / regs::TEMP_LSB_PER_C + regs::TEMP_OFFSET_C,
        }
    }
}
