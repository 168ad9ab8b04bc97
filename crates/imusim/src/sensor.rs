//! The MPU-9250's output stage: sensitivity per full scale, 16-bit
//! quantization and clipping, and the temperature sensor (PS-MPU-9250A-01
//! §3.1, §3.2, §3.4; RM-MPU-9250A-00 §4.22).

use std::f64::consts::PI;

/// Standard gravity, m/s².
pub const G: f64 = 9.806_65;

/// Gyroscope sensitivity, LSB per °/s, for a full scale of ±`range_dps`.
pub fn gyro_lsb_per_dps(range_dps: f64) -> f64 {
    match range_dps as u32 {
        250 => 131.0,
        500 => 65.5,
        1000 => 32.8,
        _ => 16.4,
    }
}

/// Accelerometer sensitivity, LSB per g, for a full scale of ±`range_g`.
pub fn accel_lsb_per_g(range_g: f64) -> f64 {
    16384.0 * 2.0 / range_g
}

/// Temperature sensitivity, LSB per °C.
pub const TEMP_LSB_PER_C: f64 = 333.87;
/// Temperature sensor offset: 0 LSB reads 21 °C.
pub const TEMP_OFFSET_C: f64 = 21.0;

/// Rounds `value` to a multiple of `lsb` and clips it to the signed 16-bit
/// range, as the chip's ADC and output register do.
pub fn quantize(value: f64, lsb: f64) -> f64 {
    (value / lsb).round().clamp(-32768.0, 32767.0) * lsb
}

/// One LSB of the gyroscope in rad/s.
pub fn gyro_lsb_rad(range_dps: f64) -> f64 {
    PI / 180.0 / gyro_lsb_per_dps(range_dps)
}

/// One LSB of the accelerometer in m/s².
pub fn accel_lsb_si(range_g: f64) -> f64 {
    G / accel_lsb_per_g(range_g)
}

/// What the temperature sensor reports for a die temperature, °C.
pub fn temperature_reading(t: f64) -> f64 {
    ((t - TEMP_OFFSET_C) * TEMP_LSB_PER_C)
        .round()
        .clamp(-32768.0, 32767.0)
        / TEMP_LSB_PER_C
        + TEMP_OFFSET_C
}

/// Specific force on a static sensor at `roll` and `pitch` (radians), with
/// z up reading +1 g when level (as the MPU-9250 does face up).
pub fn gravity(roll: f64, pitch: f64) -> [f64; 3] {
    [
        -G * pitch.sin(),
        G * roll.sin() * pitch.cos(),
        G * roll.cos() * pitch.cos(),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn datasheet_figures() {
        assert_eq!(gyro_lsb_per_dps(250.0), 131.0);
        assert_eq!(gyro_lsb_per_dps(2000.0), 16.4);
        assert_eq!(accel_lsb_per_g(2.0), 16384.0);
        assert_eq!(accel_lsb_per_g(16.0), 2048.0);
        // 333.87 LSB/°C around 21 °C: 35 °C is 4674 LSB.
        assert!((temperature_reading(35.0) - (4674.0 / 333.87 + 21.0)).abs() < 1e-12);
        // Clipping at full scale.
        let lsb = accel_lsb_si(2.0);
        assert!((quantize(100.0, lsb) - 32767.0 * lsb).abs() < 1e-12);
        let g = gravity(0.0, 0.0);
        assert_eq!(g, [-0.0, 0.0, G]);
    }
}
