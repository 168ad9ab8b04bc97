//! PX4's thermal compensation of the gyro and accelerometer.
//!
//! Facts from PX4-Autopilot:
//! - `src/modules/temperature_compensation/TemperatureCompensation.cpp`,
//!   `initialize_parameter_handles` and `parameters_update`: the
//!   `TC_G{n}_*` / `TC_A{n}_*` sets are read only when `TC_G_ENABLE` /
//!   `TC_A_ENABLE` is 1; a set applies to the sensor whose device id equals
//!   `TC_G{n}_ID` (`set_sensor_id`), else nothing is applied.
//!   `TemperatureCompensation.h`: four sets per sensor type (n = 0–3).
//! - same file, `calc_thermal_offsets_3D`, in float: T above TMAX or below
//!   TMIN is replaced by that end; dT = T − TREF;
//!   offset = X0 + X1·dT + X2·dT² + X3·dT³ per axis (`_0`/`_1`/`_2` = x/y/z).
//! - `src/lib/sensor_calibration/Gyroscope.hpp` and `Accelerometer.hpp`,
//!   `Correct`: rotation · (data − thermal_offset − offset): the offset is
//!   taken off in the sensor's own frame, before the rotation to the body.
//! - PX4's own fits (`Tools/process_sensor_caldata.py`, the on-board
//!   `temperature_calibration/accel.cpp`, `finish_sensor_instance`) keep the
//!   gyro's whole bias in X0 and normalise the accelerometer to zero at
//!   TREF (X0 = 0), so gravity stays in the reading and the accelerometer
//!   calibration keeps its job.
//!   The script writes QGroundControl's parameter file, ids as int32
//!   (type 6) and the rest as float32 (type 9).

use std::fmt::Write as _;

use super::params::{ParamFile, ParamValue, TYPE_INT32, TYPE_REAL32};
use super::{Export, Firmware, FirmwareError, Sensor, cubics, float32_text};
use crate::tcal::Model;
use imu::Setting;

/// PX4's calibration sets per sensor type (`TemperatureCompensation.h`).
pub const INSTANCES: std::ops::RangeInclusive<u8> = 0..=3;

fn prefix(sensor: Sensor, n: u8) -> String {
    match sensor {
        Sensor::Gyro => format!("TC_G{n}"),
        Sensor::Accel => format!("TC_A{n}"),
    }
}

fn enable_name(sensor: Sensor) -> &'static str {
    match sensor {
        Sensor::Gyro => "TC_G_ENABLE",
        Sensor::Accel => "TC_A_ENABLE",
    }
}

/// The device ids a set is matched to, per sensor: a gyro and an
/// accelerometer on one chip have different ids (their device type byte).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Ids {
    /// `TC_G{n}_ID`.
    pub gyro: Option<u32>,
    /// `TC_A{n}_ID`.
    pub accel: Option<u32>,
}

/// One sensor's model, the slot it goes to and the ids it is for.
#[derive(Debug, Clone, Copy)]
pub(super) struct Slot<'a> {
    /// The model.
    pub model: &'a Model,
    /// `n` of `TC_G{n}`/`TC_A{n}`.
    pub n: u8,
    /// The ids the sets are matched to.
    pub ids: Ids,
}

/// Writes QGroundControl's parameter file holding each slot: one
/// `TC_x_ENABLE` per sensor type, then each slot's set.
pub(super) fn write(slots: &[Slot]) -> Result<Export, FirmwareError> {
    let all: Vec<_> = slots
        .iter()
        .map(|slot| cubics(slot.model, Firmware::Px4, slot.model.t_ref_c))
        .collect::<Result<_, _>>()?;
    let mut warnings = Vec::new();
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# PX4 thermal compensation from imutherm, QGroundControl parameter file"
    );
    let _ = writeln!(
        s,
        "# PX4 applies offset = X0 + X1*dT + X2*dT^2 + X3*dT^3, dT = T - TREF with T held within [TMIN, TMAX],"
    );
    let _ = writeln!(
        s,
        "# and corrected = raw - offset in the sensor's own frame, before the board rotation: x, y, z here"
    );
    let _ = writeln!(
        s,
        "# must be the sensor chip's axes, as the recording gave them. Gyro X0 is the whole bias at TREF;"
    );
    let _ = writeln!(
        s,
        "# accelerometer X0 is 0 (gravity stays; the accelerometer calibration removes the rest)."
    );
    let _ = writeln!(s, "# Reboot after loading: PX4 reads these at start.");
    let lines = |s: &mut String, name: &str, value: &str, kind: u8| {
        let _ = writeln!(s, "1\t1\t{name}\t{value}\t{kind}");
    };
    let _ = writeln!(s, "# Vehicle-Id\tComponent-Id\tName\tValue\tType");
    for sensor in [Sensor::Accel, Sensor::Gyro] {
        let has = |c: &super::Cubics| c[sensor as usize].iter().any(Option::is_some);
        if !all.iter().any(has) {
            continue;
        }
        lines(&mut s, enable_name(sensor), "1", TYPE_INT32);
        for (slot, cubics) in slots.iter().zip(&all) {
            if !has(cubics) {
                continue;
            }
            let (model, n, ids) = (slot.model, slot.n, slot.ids);
            let axes = &cubics[sensor as usize];
            let p = prefix(sensor, n);
            let (what, listener, cal) = match sensor {
                Sensor::Gyro => ("gyro", "sensor_gyro", "CAL_GYRO"),
                Sensor::Accel => ("accelerometer", "sensor_accel", "CAL_ACC"),
            };
            let device_id = match sensor {
                Sensor::Gyro => ids.gyro,
                Sensor::Accel => ids.accel,
            };
            match device_id {
                Some(id) => lines(&mut s, &format!("{p}_ID"), &(id as i32).to_string(), TYPE_INT32),
                None => {
                    let _ = writeln!(
                        s,
                        "# {p}_ID below is a placeholder (0 matches no sensor): set it to the {what}'s device id, read with"
                    );
                    // The file is the same whichever front end writes it
                    // (Python's export is compared with the command line's),
                    // so its comment names the command line's flag.
                    let _ = writeln!(
                        s,
                        "# `listener {listener}` (device_id) or from the parameter {cal}{n}_ID, or export with --device-id."
                    );
                    lines(&mut s, &format!("{p}_ID"), "0", TYPE_INT32);
                    warnings.push(format!(
                    "{p}_ID is a placeholder (0): PX4 applies nothing until it is the {what}'s device id (`listener {listener}`, or {cal}{n}_ID); export with {}",
                    Setting::DeviceId
                ));
                }
            }
            for (field, v) in [
                ("TMAX", model.t_max_c),
                ("TMIN", model.t_min_c),
                ("TREF", model.t_ref_c),
            ] {
                let name = format!("{p}_{field}");
                lines(&mut s, &name, &float32_text(&name, v)?, TYPE_REAL32);
            }
            for (axis, cubic) in axes.iter().enumerate() {
                let Some(mut c) = *cubic else {
                    warnings.push(format!(
                    "{p}: axis {axis} is not in the model; its coefficients are written as 0 (no correction)"
                ));
                    let zero = [0.0; 4];
                    for (k, v) in zero.iter().enumerate() {
                        let name = format!("{p}_X{k}_{axis}");
                        lines(&mut s, &name, &float32_text(&name, *v)?, TYPE_REAL32);
                    }
                    continue;
                };
                if sensor == Sensor::Accel {
                    c[0] = 0.0;
                }
                for (k, v) in c.iter().enumerate() {
                    let name = format!("{p}_X{k}_{axis}");
                    lines(&mut s, &name, &float32_text(&name, *v)?, TYPE_REAL32);
                }
            }
        }
    }
    Ok(Export { text: s, warnings })
}

/// One sensor's set, as PX4 holds it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SensorCalibration {
    /// `TC_x{n}_ID`.
    pub id: i32,
    /// `TC_x{n}_TREF`, °C.
    pub t_ref: f32,
    /// `TC_x{n}_TMIN`, °C.
    pub t_min: f32,
    /// `TC_x{n}_TMAX`, °C.
    pub t_max: f32,
    /// `TC_x{n}_X{k}_{axis}` as `x[axis][k]`.
    pub x: [[f32; 4]; 3],
}

impl SensorCalibration {
    /// The offsets at `temp`: `calc_thermal_offsets_3D`, operation by
    /// operation in float.
    pub fn offsets(&self, temp: f32) -> [f32; 3] {
        let delta = if temp > self.t_max {
            self.t_max - self.t_ref
        } else if temp < self.t_min {
            self.t_min - self.t_ref
        } else {
            temp - self.t_ref
        };
        let d2 = delta * delta;
        let d3 = d2 * delta;
        std::array::from_fn(|i| {
            let x = self.x[i];
            x[0] + x[1] * delta + x[2] * d2 + x[3] * d3
        })
    }
}

/// What PX4 holds after loading a file: a set per enabled sensor type.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Calibration {
    /// The gyro's set, when `TC_G_ENABLE` is 1.
    pub gyro: Option<SensorCalibration>,
    /// The accelerometer's set, when `TC_A_ENABLE` is 1.
    pub accel: Option<SensorCalibration>,
}

impl Calibration {
    /// Reads slot `n` from a parameter file. A sensor type whose ENABLE is
    /// absent or not 1 is not applied, as in `parameters_update`; an
    /// enabled one needs every parameter of its set.
    pub fn from_params(file: &ParamFile, n: u8) -> Result<Calibration, FirmwareError> {
        let set = |sensor: Sensor| -> Result<Option<SensorCalibration>, FirmwareError> {
            if file.get(enable_name(sensor)) != Some(ParamValue::Int(1)) {
                return Ok(None);
            }
            let p = prefix(sensor, n);
            let id = match file.get(&format!("{p}_ID")) {
                Some(ParamValue::Int(i)) => i,
                Some(ParamValue::Float(_)) => {
                    return Err(FirmwareError::Parse {
                        line: 0,
                        message: format!("{p}_ID must be an int32 (type 6)"),
                    });
                }
                None => return Err(FirmwareError::Missing(format!("{p}_ID"))),
            };
            let mut x = [[0f32; 4]; 3];
            for (axis, row) in x.iter_mut().enumerate() {
                for (k, v) in row.iter_mut().enumerate() {
                    *v = file.float(&format!("{p}_X{k}_{axis}"))?;
                }
            }
            Ok(Some(SensorCalibration {
                id,
                t_ref: file.float(&format!("{p}_TREF"))?,
                t_min: file.float(&format!("{p}_TMIN"))?,
                t_max: file.float(&format!("{p}_TMAX"))?,
                x,
            }))
        };
        Ok(Calibration {
            gyro: set(Sensor::Gyro)?,
            accel: set(Sensor::Accel)?,
        })
    }

    /// The set applied to `sensor`, if any.
    pub fn sensor(&self, sensor: Sensor) -> Option<&SensorCalibration> {
        match sensor {
            Sensor::Gyro => self.gyro.as_ref(),
            Sensor::Accel => self.accel.as_ref(),
        }
    }

    /// `raw − thermal_offset`, as `Correct` takes it (before the rotation
    /// and with the sensor's own calibration offset left aside).
    pub fn correct(&self, sensor: Sensor, axis: usize, raw: f32, temp: f32) -> f32 {
        match self.sensor(sensor) {
            Some(c) if axis < 3 => raw - c.offsets(temp)[axis],
            _ => raw,
        }
    }
}
