//! ArduPilot's IMU temperature calibration.
//!
//! Facts from ArduPilot (`libraries/AP_InertialSensor/`):
//! - `AP_InertialSensor_tempcal.cpp`: `SCALE_FACTOR` 1e6 (the parameters
//!   are the coefficients × 1e6), fixed `TEMP_REFERENCE` 35 °C;
//!   `polynomial_eval(tdiff)` = (c1 + (c2 + c3·tdiff)·tdiff)·tdiff·1e-6 in
//!   float, no constant term; `correct_sensor`, only when ENABLE is 1
//!   (Enabled): T and the calibration temperature are constrained to
//!   [TMIN, TMAX], then v −= poly(T − 35); v += poly(cal_temp − 35).
//!   `var_info`: `INS_TCALn_ENABLE`, `TMIN`, `TMAX` (@Range −70 80 °C),
//!   `ACC1..3_X/Y/Z`, `GYR1..3_X/Y/Z`.
//! - The calibration temperature is `INS_ACCn_CALTEMP` / `INS_GYRn_CALTEMP`
//!   (`AP_InertialSensor.cpp`, `caltemp_accel`/`caltemp_gyro`): the
//!   temperature at which the accelerometer and gyro calibrations found
//!   their offsets, so the correction is zero there and those offsets stay
//!   valid.
//! - `AP_InertialSensor_Backend.cpp`, `_rotate_and_correct_accel` and
//!   `_rotate_and_correct_gyro`: the reading is first rotated by the IMU's
//!   own orientation on the board, then temperature-corrected, offset, and
//!   finally rotated by the board orientation (AHRS_ORIENTATION): the axes
//!   of the coefficients are the flight controller board's.

use std::fmt::Write as _;

use super::params::ParamFile;
use super::{Export, Firmware, FirmwareError, Sensor, cubics, float32_text};
use crate::tcal::Model;

/// ArduPilot's `INS_TCALn` sets (one per IMU).
pub const INSTANCES: std::ops::RangeInclusive<u8> = 1..=3;
/// `TEMP_REFERENCE`, °C.
pub const TEMP_REFERENCE_C: f64 = 35.0;
/// `SCALE_FACTOR`.
pub const SCALE_FACTOR: f64 = 1.0e6;
/// The documented range of `INS_TCALn_TMIN`/`TMAX` (@Range), °C.
pub const DOCUMENTED_RANGE_C: (f64, f64) = (-70.0, 80.0);

fn key(sensor: Sensor) -> &'static str {
    match sensor {
        Sensor::Accel => "ACC",
        Sensor::Gyro => "GYR",
    }
}

const AXES: [&str; 3] = ["X", "Y", "Z"];

/// Writes the `NAME VALUE` file for `INS_TCAL{n}`.
/// `header`: the file's opening comments, written once per file.
pub(super) fn write(
    model: &Model,
    n: u8,
    ids: super::px4::Ids,
    header: bool,
) -> Result<Export, FirmwareError> {
    let cubics = cubics(model, Firmware::ArduPilot, TEMP_REFERENCE_C)?;
    let mut warnings = Vec::new();
    let (lo, hi) = DOCUMENTED_RANGE_C;
    let (t_min, t_max) = (model.t_min_c, model.t_max_c);
    let mut s = String::new();
    if header {
        let _ = writeln!(
            s,
            "# ArduPilot IMU temperature calibration from imutherm (INS_TCAL{n}_*)"
        );
        let _ = writeln!(
            s,
            "# ArduPilot applies v -= poly(T - 35) and v += poly(CALTEMP - 35), poly(d) = (C1 + (C2 + C3*d)*d)*d / 1e6,"
        );
        let _ = writeln!(
            s,
            "# with T and CALTEMP held within [TMIN, TMAX]; CALTEMP is INS_ACC{n}_CALTEMP / INS_GYR{n}_CALTEMP, set by the"
        );
        let _ = writeln!(
            s,
            "# accelerometer and gyro calibrations: leave them, the correction is zero at that temperature."
        );
        let _ = writeln!(
            s,
            "# Axes: the correction comes after the IMU's rotation onto the board and before AHRS_ORIENTATION, so"
        );
        let _ = writeln!(
            s,
            "# x, y, z here must be the flight controller board's axes. Reboot after loading."
        );
    }
    // `correct_sensor` applies set n to the IMU of index n − 1, whatever
    // sensor that is: the ids the log carried only let the user check
    // that the vehicle's IMU order is the log's.
    let suffix = if n == 1 { String::new() } else { n.to_string() };
    match (ids.gyro, ids.accel.or(ids.gyro)) {
        (Some(g), Some(a)) => {
            let _ = writeln!(
                s,
                "# INS_TCAL{n} is applied to IMU {n}; it was fitted on the IMU whose INS_GYR{suffix}_ID is {g} and INS_ACC{suffix}_ID is {a}: check that the vehicle's are these."
            );
        }
        _ => {
            let _ = writeln!(
                s,
                "# INS_TCAL{n} is applied to IMU {n} (INS_GYR{suffix}_ID / INS_ACC{suffix}_ID); the recording gave no device id to check it against."
            );
        }
    }
    // @Range is documentation for ground stations: `AP_Param` stores any
    // float and `correct_sensor` constrains T to whatever TMIN/TMAX hold.
    // Holding the range to it would leave the part of the fit beyond it
    // uncorrected, so the fitted range is written and the user told.
    if model.t_min_c < lo || model.t_max_c > hi {
        let _ = writeln!(
            s,
            "# TMIN/TMAX below span the fit, {:.2} to {:.2} degC, beyond their documented range {lo} to {hi} degC:",
            model.t_min_c, model.t_max_c
        );
        let _ = writeln!(
            s,
            "# the firmware applies them as stored, but a ground station may flag them as out of range."
        );
        warnings.push(format!(
            "the fit spans {:.2} to {:.2} °C, beyond the documented range of INS_TCAL{n}_TMIN/TMAX ({lo} to {hi} °C): written as fitted, which ArduPilot applies as stored, but a ground station may flag them; refit over a range within it to avoid that",
            model.t_min_c, model.t_max_c
        ));
    }
    let p = format!("INS_TCAL{n}");
    let _ = writeln!(s, "{p}_ENABLE 1");
    for (field, v) in [("TMIN", t_min), ("TMAX", t_max)] {
        let name = format!("{p}_{field}");
        let _ = writeln!(s, "{name} {}", float32_text(&name, v)?);
    }
    for sensor in [Sensor::Accel, Sensor::Gyro] {
        let axes = &cubics[sensor as usize];
        for (axis, cubic) in axes.iter().enumerate() {
            if cubic.is_none() && axes.iter().any(Option::is_some) {
                warnings.push(format!(
                    "{p}_{}: axis {} is not in the model; written as 0 (no correction)",
                    key(sensor),
                    AXES[axis]
                ));
            }
        }
        for k in 1..=3 {
            for (axis, cubic) in axes.iter().enumerate() {
                let name = format!("{p}_{}{k}_{}", key(sensor), AXES[axis]);
                let v = cubic.map_or(0.0, |c| c[k] * SCALE_FACTOR);
                let _ = writeln!(s, "{name} {}", float32_text(&name, v)?);
            }
        }
    }
    Ok(Export { text: s, warnings })
}

/// What ArduPilot holds after loading a file: one `INS_TCALn` set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Calibration {
    /// `ENABLE` is 1 (2 learns instead of correcting).
    pub enabled: bool,
    /// `TMIN`, °C.
    pub t_min: f32,
    /// `TMAX`, °C.
    pub t_max: f32,
    /// `ACC{k+1}_{axis}` as `accel[k][axis]`, scaled by 1e6.
    pub accel: [[f32; 3]; 3],
    /// `GYR{k+1}_{axis}` as `gyro[k][axis]`, scaled by 1e6.
    pub gyro: [[f32; 3]; 3],
}

/// `constrain_float` for ordered bounds: below low gives low, above high
/// gives high.
fn constrain(v: f32, low: f32, high: f32) -> f32 {
    if v < low {
        low
    } else if v > high {
        high
    } else {
        v
    }
}

impl Calibration {
    /// Reads `INS_TCAL{n}` from a parameter file; absent coefficients are
    /// 0, their default in `var_info`.
    pub fn from_params(file: &ParamFile, n: u8) -> Result<Calibration, FirmwareError> {
        let p = format!("INS_TCAL{n}");
        let enabled = file.get(&format!("{p}_ENABLE")).map(|v| v.as_f32()) == Some(1.0);
        let coeff = |sensor: Sensor| -> [[f32; 3]; 3] {
            std::array::from_fn(|k| {
                std::array::from_fn(|axis| {
                    file.get(&format!("{p}_{}{}_{}", key(sensor), k + 1, AXES[axis]))
                        .map_or(0.0, |v| v.as_f32())
                })
            })
        };
        Ok(Calibration {
            enabled,
            t_min: file.float(&format!("{p}_TMIN"))?,
            t_max: file.float(&format!("{p}_TMAX"))?,
            accel: coeff(Sensor::Accel),
            gyro: coeff(Sensor::Gyro),
        })
    }

    /// `polynomial_eval` for one axis.
    fn poly(c: &[[f32; 3]; 3], axis: usize, tdiff: f32) -> f32 {
        (c[0][axis] + (c[1][axis] + c[2][axis] * tdiff) * tdiff) * tdiff * (1.0 / SCALE_FACTOR) as f32
    }

    /// `correct_sensor` for one axis: `raw` at temperature `temp`, with
    /// the calibration temperature `cal_temp`.
    pub fn correct(&self, sensor: Sensor, axis: usize, raw: f32, temp: f32, cal_temp: f32) -> f32 {
        if !self.enabled || axis >= 3 {
            return raw;
        }
        let c = match sensor {
            Sensor::Accel => &self.accel,
            Sensor::Gyro => &self.gyro,
        };
        let t = constrain(temp, self.t_min, self.t_max);
        let cal = constrain(cal_temp, self.t_min, self.t_max);
        // `temperature - TEMP_REFERENCE` is taken in double (35.0 is a
        // double literal) and passed on as a float.
        let mut v = raw;
        v -= Self::poly(c, axis, (t as f64 - TEMP_REFERENCE_C) as f32);
        v += Self::poly(c, axis, (cal as f64 - TEMP_REFERENCE_C) as f32);
        v
    }
}
