//! One FIFO frame, named: raw counts as the chip stores them, and the same
//! sample in SI units.
//!
//! The chip's FIFO holds ACCEL_X..Z, TEMP_OUT, GYRO_X..Z (register order),
//! while a log row is ax, ay, az, gx, gy, gz, temperature. The two orders
//! differ only in where the temperature sits; naming the fields keeps that
//! move in one place ([`Sample::to_log_row`]).

use crate::regs;

/// One frame of raw counts, as the FIFO delivers it (big-endian words in
/// register order: accelerometer, temperature, gyroscope).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct RawFrame {
    /// ACCEL_XOUT..ZOUT, counts.
    pub accel: [i16; 3],
    /// TEMP_OUT, counts.
    pub temp: i16,
    /// GYRO_XOUT..ZOUT, counts.
    pub gyro: [i16; 3],
}

impl RawFrame {
    /// Decodes the 14 bytes of one frame.
    pub fn from_be_bytes(b: &[u8; regs::FRAME_BYTES]) -> RawFrame {
        let w = |k: usize| i16::from_be_bytes([b[2 * k], b[2 * k + 1]]);
        RawFrame {
            accel: [w(0), w(1), w(2)],
            temp: w(3),
            gyro: [w(4), w(5), w(6)],
        }
    }

    /// The 14 bytes the chip writes for this frame.
    pub fn to_be_bytes(&self) -> [u8; regs::FRAME_BYTES] {
        let words: [i16; 7] = (*self).into();
        let mut out = [0u8; regs::FRAME_BYTES];
        for (k, w) in words.iter().enumerate() {
            out[2 * k..2 * k + 2].copy_from_slice(&w.to_be_bytes());
        }
        out
    }
}

/// Register order: ACCEL_X..Z, TEMP, GYRO_X..Z.
impl From<RawFrame> for [i16; 7] {
    fn from(f: RawFrame) -> [i16; 7] {
        [
            f.accel[0], f.accel[1], f.accel[2], f.temp, f.gyro[0], f.gyro[1], f.gyro[2],
        ]
    }
}

/// From register order: ACCEL_X..Z, TEMP, GYRO_X..Z.
impl From<[i16; 7]> for RawFrame {
    fn from(w: [i16; 7]) -> RawFrame {
        RawFrame {
            accel: [w[0], w[1], w[2]],
            temp: w[3],
            gyro: [w[4], w[5], w[6]],
        }
    }
}

/// One sample in SI units.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Sample {
    /// Specific force, m/s².
    pub accel: [f64; 3],
    /// Angular rate, rad/s.
    pub gyro: [f64; 3],
    /// Die temperature, °C.
    pub temp_c: f64,
}

impl Sample {
    /// The sample as a log row: ax, ay, az (m/s²), gx, gy, gz (rad/s),
    /// temperature (°C).
    pub fn to_log_row(&self) -> [f64; 7] {
        let [ax, ay, az] = self.accel;
        let [gx, gy, gz] = self.gyro;
        [ax, ay, az, gx, gy, gz, self.temp_c]
    }

    /// The sample from a log row (ax, ay, az, gx, gy, gz, temperature).
    pub fn from_log_row(r: [f64; 7]) -> Sample {
        Sample {
            accel: [r[0], r[1], r[2]],
            gyro: [r[3], r[4], r[5]],
            temp_c: r[6],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bytes_round_trip_in_register_order() {
        let f = RawFrame {
            accel: [1, -2, 16384],
            temp: -300,
            gyro: [32767, -32768, 7],
        };
        let b = f.to_be_bytes();
        // TEMP_OUT is the fourth word, bytes 6 and 7.
        assert_eq!(i16::from_be_bytes([b[6], b[7]]), -300);
        assert_eq!(RawFrame::from_be_bytes(&b), f);
        let words: [i16; 7] = f.into();
        assert_eq!(words, [1, -2, 16384, -300, 32767, -32768, 7]);
        assert_eq!(RawFrame::from(words), f);
    }

    #[test]
    fn log_row_puts_temperature_last() {
        let s = Sample {
            accel: [1.0, 2.0, 3.0],
            gyro: [4.0, 5.0, 6.0],
            temp_c: 25.0,
        };
        assert_eq!(s.to_log_row(), [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 25.0]);
        assert_eq!(Sample::from_log_row(s.to_log_row()), s);
    }
}
