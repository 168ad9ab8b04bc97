//! The MPU-9250's output stage: sensitivity per full scale, 16-bit
//! quantization and clipping, and the temperature sensor (PS-MPU-9250A-01
//! §3.1, §3.2, §3.4; RM-MPU-9250A-00 §4.22).

use std::f64::consts::PI;

/// Standard gravity, m/s² ([`earth::STANDARD_GRAVITY`], named here as the
/// simulator has always named it).
pub const G: f64 = earth::STANDARD_GRAVITY;

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
#[inline]
pub fn quantize(value: f64, lsb: f64) -> f64 {
    to_counts(value / lsb) * lsb
}

/// The 16-bit register value (as a float) for a reading of `counts` LSB:
/// rounded to the nearest integer and clipped to −32768…32767.
#[inline]
pub fn to_counts(counts: f64) -> f64 {
    // Adding and removing 1.5·2^52 rounds to the nearest integer (ties to
    // even) in two additions, where f64::round is a library call on
    // baseline x86-64: a fifth of the simulator's time. Exact for the
    // clipped range.
    const ROUND: f64 = 6_755_399_441_055_744.0;
    (counts.clamp(-32768.0, 32767.0) + ROUND) - ROUND
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
#[inline]
pub fn temperature_reading(t: f64) -> f64 {
    to_counts((t - TEMP_OFFSET_C) * TEMP_LSB_PER_C) / TEMP_LSB_PER_C + TEMP_OFFSET_C
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
    fn gravity_agrees_with_the_earth_frame() {
        // The specific force (up) in the sensor's axes is the level frame's
        // up axis seen from the body, times g.
        let (r, p, h) = (0.3, -0.2, 1.1);
        let c = earth::body_to_level(r, p, h);
        for (j, w) in gravity(r, p).iter().enumerate() {
            assert!((c[2][j] * G - w).abs() < 1e-12);
        }
    }

    #[test]
    fn datasheet_figures() {
        assert_eq!(gyro_lsb_per_dps(250.0), 131.0);
        assert_eq!(gyro_lsb_per_dps(500.0), 65.5);
        assert_eq!(gyro_lsb_per_dps(1000.0), 32.8);
        assert_eq!(gyro_lsb_per_dps(2000.0), 16.4);
        assert_eq!(accel_lsb_per_g(2.0), 16384.0);
        assert_eq!(accel_lsb_per_g(4.0), 8192.0);
        assert_eq!(accel_lsb_per_g(8.0), 4096.0);
        assert_eq!(accel_lsb_per_g(16.0), 2048.0);
        // 333.87 LSB/°C around 21 °C: 35 °C is 4674 LSB.
        assert!((temperature_reading(35.0) - (4674.0 / 333.87 + 21.0)).abs() < 1e-12);
        assert_eq!(temperature_reading(21.0), 21.0);
        // Clipping at full scale.
        let lsb = accel_lsb_si(2.0);
        assert!((quantize(100.0, lsb) - 32767.0 * lsb).abs() < 1e-12);
        assert!((quantize(-100.0, lsb) + 32768.0 * lsb).abs() < 1e-12);
        let g = gravity(0.0, 0.0);
        assert_eq!(g, [-0.0, 0.0, G]);
    }

    #[test]
    fn rounding_matches_the_library() {
        for i in -70_000..70_000 {
            let x = i as f64 * 0.4999 + 0.123;
            let want = x.round_ties_even().clamp(-32768.0, 32767.0);
            assert_eq!(to_counts(x), want, "{x}");
        }
        // The thesis's logs: ±500 °/s and ±8 g steps (65.5 LSB/(°/s),
        // 4096 LSB/g), read off consecutive values of its sample rows (its
        // logger converted degrees with π = 3.14159: 8e-7 off).
        let gyro = 0.023_182_216_284_987_275 - 0.022_915_754_028_837_994;
        assert!((gyro / gyro_lsb_rad(500.0) - 1.0).abs() < 1e-5);
        let accel = 0.881_066_210_937_499_9 - 0.878_672_009_277_343_7;
        assert!((accel / accel_lsb_si(8.0) - 1.0).abs() < 1e-9);
    }
}
