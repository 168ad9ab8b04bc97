//! A compensation model as flight stacks load it: PX4's `TC_*` parameters
//! in QGroundControl's parameter file, ArduPilot's `INS_TCALn_*` in a
//! `NAME VALUE` file; and the other way round, a parameter file read back
//! and applied to samples exactly as the firmware applies it, in float32,
//! so that a run shows before flashing what the vehicle will do.
//!
//! Both stacks take a cubic in temperature and no dT/dt term; a model they
//! cannot represent is refused with what to refit, never truncated.

pub mod ardupilot;
mod params;
pub mod px4;
pub mod verdict;

use thiserror::Error;

use imu::Quantity;
use imu::log_file::classify_header;
use imu::setting::{FitCall, Setting, Value, Without};

use crate::ModelError;
use crate::tcal::Model;

pub use params::{ParamFile, ParamValue};

/// The flight stacks imutherm writes for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Firmware {
    /// PX4 (`TC_G*`, `TC_A*`).
    Px4,
    /// ArduPilot (`INS_TCALn_*`).
    ArduPilot,
}

impl Firmware {
    /// Highest polynomial order the firmware evaluates.
    pub const MAX_ORDER: usize = 3;

    /// The name used on the command line (`px4`, `ardupilot`).
    pub fn key(self) -> &'static str {
        match self {
            Firmware::Px4 => "px4",
            Firmware::ArduPilot => "ardupilot",
        }
    }

    /// The name a user reads (`PX4`, `ArduPilot`).
    pub fn name(self) -> &'static str {
        match self {
            Firmware::Px4 => "PX4",
            Firmware::ArduPilot => "ArduPilot",
        }
    }

    /// Calibration slots the firmware has, in its own numbering.
    pub fn instances(self) -> std::ops::RangeInclusive<u8> {
        match self {
            Firmware::Px4 => px4::INSTANCES,
            Firmware::ArduPilot => ardupilot::INSTANCES,
        }
    }
}

/// The inertial sensors a calibration covers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sensor {
    /// Rate gyroscope.
    Gyro,
    /// Accelerometer.
    Accel,
}

/// The sensor and axis index (0 = x) of an imutherm channel name.
pub fn sensor_axis(name: &str) -> Option<(Sensor, usize)> {
    let kind = classify_header(name, None);
    let sensor = match kind.quantity {
        Quantity::AngularRate => Sensor::Gyro,
        Quantity::Acceleration => Sensor::Accel,
        _ => return None,
    };
    let axis = match kind.axis? {
        imu::Axis::X => 0,
        imu::Axis::Y => 1,
        imu::Axis::Z => 2,
    };
    Some((sensor, axis))
}

/// Which calibration slot, and which sensor it is for.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Target {
    /// The firmware's calibration slot (PX4 0–3, ArduPilot 1–3); the first
    /// when `None`.
    pub instance: Option<u8>,
    /// The sensor's device id; the model's when `None`.
    pub device_id: Option<u32>,
}

/// A written parameter file and what the user must know about it.
#[derive(Debug, Clone, PartialEq)]
pub struct Export {
    /// The file, as the ground station loads it.
    pub text: String,
    /// Things to act on (placeholder id, range beyond the documented one).
    pub warnings: Vec<String>,
}

/// Why a model cannot be written for, or a file read by, a firmware.
#[derive(Debug, Error)]
pub enum FirmwareError {
    /// A polynomial above the firmware's cubic.
    #[error(
        "{channel} has order {order}, and {firmware} evaluates a cubic at most: refit with {} (or {})",
        FitCall(Setting::FitFirmware.given(Value::text(*key))),
        Setting::FitOrder.given(Value::number(3))
    )]
    OrderTooHigh {
        /// Channel name.
        channel: String,
        /// Its order.
        order: usize,
        /// Firmware name.
        firmware: &'static str,
        /// Firmware key.
        key: &'static str,
    },
    /// A dT/dt term, which neither stack evaluates.
    #[error(
        "{channel} has a dT/dt term, which {firmware} cannot apply: refit {} ({})",
        Without(&[Setting::RateTerm]),
        FitCall(Setting::FitFirmware.given(Value::text(*key)))
    )]
    RateTerm {
        /// Channel name.
        channel: String,
        /// Firmware name.
        firmware: &'static str,
        /// Firmware key.
        key: &'static str,
    },
    /// A lag or hysteresis term, which neither stack evaluates.
    #[error(
        "{channel} has a thermal lag or hysteresis term, which {firmware} cannot apply: refit {}, which keeps the full model's equilibrium curve",
        FitCall(Setting::FitFirmware.given(Value::text(*key)))
    )]
    Dynamics {
        /// Channel name.
        channel: String,
        /// Firmware name.
        firmware: &'static str,
        /// Firmware key.
        key: &'static str,
    },
    /// A slot the firmware does not have.
    #[error("instance {instance}: {firmware} has calibration instances {lo} to {hi}")]
    Instance {
        /// Requested slot.
        instance: u8,
        /// Firmware name.
        firmware: &'static str,
        /// First slot.
        lo: u8,
        /// Last slot.
        hi: u8,
    },
    /// A coefficient beyond float32, the parameters' type.
    #[error("{parameter} = {value:e} does not fit a float32 parameter")]
    TooLarge {
        /// Parameter name.
        parameter: String,
        /// Its value.
        value: f64,
    },
    /// A slot or id given for a model of several instances, whose
    /// instances each go to their own slot with their own ids.
    #[error(
        "the model holds instances {instances:?}, each written to its own slot with its own ids: export it {}",
        Without(&[Setting::CalibrationSlot, Setting::DeviceId])
    )]
    TargetOfMany {
        /// The model's instance numbers.
        instances: Vec<u32>,
    },
    /// No gyro or accelerometer axis in the model.
    #[error("the model has no gyro or accelerometer axis to calibrate")]
    Nothing,
    /// The model itself is unusable.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// A line of a parameter file the ground station would not load.
    #[error("line {line}: {message}")]
    Parse {
        /// 1-based line.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A parameter the calibration needs, absent from the file.
    #[error("{0} is missing from the parameter file")]
    Missing(String),
}

/// Writes the model as the firmware's parameter file. A model of several
/// instances (`tcal fit --instance all`) is written whole, each instance to
/// the slot of its number (PX4 `TC_x{n}`, ArduPilot `INS_TCAL{n+1}`, the
/// firmware's IMU order), and takes no target.
pub fn export(model: &Model, firmware: Firmware, target: Target) -> Result<Export, FirmwareError> {
    model.validate()?;
    if !model.instances.is_empty() {
        if target != Target::default() {
            return Err(FirmwareError::TargetOfMany {
                instances: model.instances.iter().filter_map(|m| m.instance).collect(),
            });
        }
        let slots: Vec<(&Model, u8)> = model
            .instances
            .iter()
            .map(|m| {
                let number = m.instance.unwrap_or(0);
                let slot = match firmware {
                    Firmware::Px4 => number,
                    Firmware::ArduPilot => number.saturating_add(1),
                };
                let slot = u8::try_from(slot).unwrap_or(u8::MAX);
                instance(firmware, Some(slot)).map(|n| (m, n))
            })
            .collect::<Result<_, _>>()?;
        return write(firmware, &slots, None);
    }
    let n = instance(firmware, target.instance)?;
    write(firmware, &[(model, n)], target.device_id)
}

/// The file for each (model, slot), ids from the models unless `device_id`
/// overrides them.
fn write(
    firmware: Firmware,
    slots: &[(&Model, u8)],
    device_id: Option<u32>,
) -> Result<Export, FirmwareError> {
    match firmware {
        Firmware::Px4 => {
            let slots: Vec<px4::Slot> = slots
                .iter()
                .map(|&(model, n)| px4::Slot {
                    model,
                    n,
                    ids: px4::Ids {
                        gyro: device_id.or(model.device_id),
                        accel: device_id.or(model.accel_device_id).or(model.device_id),
                    },
                })
                .collect();
            px4::write(&slots)
        }
        Firmware::ArduPilot => {
            let mut out = Export {
                text: String::new(),
                warnings: Vec::new(),
            };
            for (k, &(model, n)) in slots.iter().enumerate() {
                let gyro = device_id.or(model.device_id);
                let ids = px4::Ids {
                    gyro,
                    accel: device_id.or(model.accel_device_id).or(gyro),
                };
                let one = ardupilot::write(model, n, ids, k == 0)?;
                out.text += &one.text;
                out.warnings.extend(one.warnings);
            }
            Ok(out)
        }
    }
}

/// A parameter file as the firmware holds it after loading.
#[derive(Debug, Clone, PartialEq)]
pub enum Calibration {
    /// PX4's.
    Px4(px4::Calibration),
    /// ArduPilot's.
    ArduPilot(ardupilot::Calibration),
}

/// Reads a parameter file as the ground station loads it and the firmware
/// holds it (float32), for the given slot.
pub fn load(firmware: Firmware, text: &str, instance_: Option<u8>) -> Result<Calibration, FirmwareError> {
    let n = instance(firmware, instance_)?;
    Ok(match firmware {
        Firmware::Px4 => Calibration::Px4(px4::Calibration::from_params(&ParamFile::parse_qgc(text)?, n)?),
        Firmware::ArduPilot => Calibration::ArduPilot(ardupilot::Calibration::from_params(
            &ParamFile::parse_name_value(text)?,
            n,
        )?),
    })
}

impl Calibration {
    /// One sample corrected as the firmware corrects it: `raw` of `sensor`
    /// axis `axis` at temperature `temp_c`. `cal_temp_c` is ArduPilot's
    /// calibration temperature (`INS_ACCn_CALTEMP`/`INS_GYRn_CALTEMP`);
    /// PX4 has none. A sensor the file does not enable is returned as read.
    pub fn correct(&self, sensor: Sensor, axis: usize, raw: f64, temp_c: f64, cal_temp_c: f64) -> f64 {
        match self {
            Calibration::Px4(c) => c.correct(sensor, axis, raw as f32, temp_c as f32) as f64,
            Calibration::ArduPilot(c) => {
                c.correct(sensor, axis, raw as f32, temp_c as f32, cal_temp_c as f32) as f64
            }
        }
    }

    /// Whether the firmware applies anything to `sensor`.
    pub fn enabled(&self, sensor: Sensor) -> bool {
        match self {
            Calibration::Px4(c) => c.sensor(sensor).is_some(),
            Calibration::ArduPilot(c) => c.enabled,
        }
    }
}

fn instance(firmware: Firmware, given: Option<u8>) -> Result<u8, FirmwareError> {
    let range = firmware.instances();
    let n = given.unwrap_or(*range.start());
    if range.contains(&n) {
        Ok(n)
    } else {
        Err(FirmwareError::Instance {
            instance: n,
            firmware: firmware.name(),
            lo: *range.start(),
            hi: *range.end(),
        })
    }
}

/// Per sensor and axis, the cubic in (T − t0), ascending, of each channel
/// the model has; refuses what the firmware cannot evaluate.
type Cubics = [[Option<[f64; 4]>; 3]; 2];

fn cubics(model: &Model, firmware: Firmware, t0: f64) -> Result<Cubics, FirmwareError> {
    let mut out: Cubics = Default::default();
    let mut any = false;
    for c in &model.channels {
        let Some((sensor, axis)) = sensor_axis(&c.name) else {
            continue;
        };
        if c.rate_coefficient.is_some() {
            return Err(FirmwareError::RateTerm {
                channel: c.name.clone(),
                firmware: firmware.name(),
                key: firmware.key(),
            });
        }
        if c.order > Firmware::MAX_ORDER {
            return Err(FirmwareError::OrderTooHigh {
                channel: c.name.clone(),
                order: c.order,
                firmware: firmware.name(),
                key: firmware.key(),
            });
        }
        if c.lag_s.is_some() || c.hysteresis_term.is_some() {
            return Err(FirmwareError::Dynamics {
                channel: c.name.clone(),
                firmware: firmware.name(),
                key: firmware.key(),
            });
        }
        let p = c.power_coefficients_about(model, t0);
        out[sensor as usize][axis] = Some(std::array::from_fn(|k| p.get(k).copied().unwrap_or(0.0)));
        any = true;
    }
    if any { Ok(out) } else { Err(FirmwareError::Nothing) }
}

/// A value as the float32 parameter will hold it, printed with the
/// shortest digits that read back to that same float32.
fn float32_text(parameter: &str, value: f64) -> Result<String, FirmwareError> {
    let v = value as f32;
    if !v.is_finite() {
        return Err(FirmwareError::TooLarge {
            parameter: parameter.to_string(),
            value,
        });
    }
    // Rust's Display of f32 is the shortest round-trip decimal, never in
    // exponent form, which every ground station parses.
    Ok(format!("{v}"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tcal::{FitOptions, Order, Run, TcalChannel, fit};

    /// Gyro and accelerometer x whose bias is a cubic over 20 → 70 °C.
    fn model(order: usize, t_ref: Option<f64>) -> Model {
        let temp: Vec<f64> = (0..5000).map(|i| 20.0 + i as f64 * 0.01).collect();
        let bias = |t: f64| 2e-3 + 3e-5 * (t - 40.0) - 4e-7 * (t - 40.0).powi(3);
        let gyro: Vec<f64> = temp.iter().map(|&t| bias(t)).collect();
        let accel: Vec<f64> = temp.iter().map(|&t| 9.81 + 20.0 * bias(t)).collect();
        let channels = vec![
            TcalChannel::new("gyro_x", "rad/s", gyro.as_slice()),
            TcalChannel::new("accel_x", "m/s^2", accel.as_slice()),
        ];
        let run = Run {
            channels: &channels,
            temp: &temp,
            rate_hz: 1.0,
        };
        let opts = FitOptions {
            order: Order::Fixed(order),
            t_ref_c: t_ref,
            ..FitOptions::default()
        };
        fit(&[run], &opts).unwrap()
    }

    #[test]
    fn each_sensor_set_carries_its_own_device_id() {
        // A ULog's sensor_gyro and sensor_accel ids of one ICM-20602 differ
        // in their device type byte.
        let mut m = model(3, None);
        m.device_id = Some(2_490_378);
        m.accel_device_id = Some(2_490_634);
        let text = export(&m, Firmware::Px4, Target::default()).unwrap().text;
        assert!(text.contains("TC_G0_ID\t2490378\t6"), "{text}");
        assert!(text.contains("TC_A0_ID\t2490634\t6"), "{text}");
        assert!(text.contains("TC_G_ENABLE\t1\t6") && text.contains("TC_A_ENABLE\t1\t6"));
        // One id (a text log's `# device_id:`) stands for both.
        m.accel_device_id = None;
        let text = export(&m, Firmware::Px4, Target::default()).unwrap().text;
        assert!(text.contains("TC_A0_ID\t2490378\t6"), "{text}");
    }

    #[test]
    fn written_files_load_back_to_the_models_correction() {
        let m = model(3, None);
        let (g, a) = (m.channel("gyro_x").unwrap(), m.channel("accel_x").unwrap());
        let target = Target {
            instance: None,
            device_id: Some(2_293_768),
        };
        for fw in [Firmware::Px4, Firmware::ArduPilot] {
            let out = export(&m, fw, target).unwrap();
            let cal = load(fw, &out.text, None).unwrap();
            for t in [10.0f64, 20.0, 33.0, 45.5, 70.0, 90.0] {
                let tc = t.clamp(m.t_min_c, m.t_max_c);
                let relative = |c: &crate::tcal::ChannelModel| c.bias(&m, tc) - c.bias(&m, m.t_ref_c);
                // PX4 takes the gyro's whole bias; ArduPilot, like the accelerometer, only its change.
                let gyro_expected = match fw {
                    Firmware::Px4 => -g.bias(&m, tc),
                    Firmware::ArduPilot => -relative(g),
                };
                let gyro = cal.correct(Sensor::Gyro, 0, 0.0, t, m.t_ref_c);
                let accel = cal.correct(Sensor::Accel, 0, 9.81, t, m.t_ref_c) - 9.81;
                assert!(
                    (gyro - gyro_expected).abs() < 2e-7,
                    "{fw:?} {t}: gyro {gyro} vs {gyro_expected}"
                );
                assert!(
                    (accel + relative(a)).abs() < 2e-5,
                    "{fw:?} {t}: accel {accel} vs {}",
                    -relative(a)
                );
            }
        }
    }

    #[test]
    fn what_the_firmware_cannot_apply_is_refused() {
        let m = model(4, None);
        for fw in [Firmware::Px4, Firmware::ArduPilot] {
            let e = export(&m, fw, Target::default()).unwrap_err();
            assert!(matches!(e, FirmwareError::OrderTooHigh { order: 4, .. }), "{e}");
            assert!(
                e.to_string()
                    .contains(&format!("the fit's firmware {}", fw.key())),
                "{e}"
            );
        }
        let mut m = model(2, None);
        m.channels[0].rate_coefficient = Some(0.1);
        m.dtdt_range_c_per_s = Some([-0.1, 0.1]);
        assert!(matches!(
            export(&m, Firmware::Px4, Target::default()),
            Err(FirmwareError::RateTerm { .. })
        ));
        let m = model(2, None);
        for (fw, n) in [
            (Firmware::Px4, 4),
            (Firmware::ArduPilot, 0),
            (Firmware::ArduPilot, 4),
        ] {
            let t = Target {
                instance: Some(n),
                device_id: None,
            };
            assert!(
                matches!(export(&m, fw, t), Err(FirmwareError::Instance { .. })),
                "{fw:?} {n}"
            );
        }
    }

    #[test]
    fn placeholder_id_and_range_beyond_the_documented_one_are_warned() {
        let mut m = model(3, None);
        let px4 = export(&m, Firmware::Px4, Target::default()).unwrap();
        assert!(px4.text.contains("1\t1\tTC_G0_ID\t0\t6"));
        assert!(px4.text.contains("listener sensor_gyro"));
        assert!(
            px4.warnings
                .iter()
                .any(|w| w.contains("TC_G0_ID is a placeholder"))
        );
        let inside = export(&m, Firmware::ArduPilot, Target::default()).unwrap();
        assert!(!inside.warnings.iter().any(|w| w.contains("documented")));
        // The model has only the x axes: the others are written as zero, and said so.
        assert!(
            inside
                .warnings
                .iter()
                .any(|w| w.contains("axis Y is not in the model"))
        );
        m.t_max_c = 100.0;
        m.centre_c = 60.0;
        m.scale_c = 40.0;
        let ap = export(&m, Firmware::ArduPilot, Target::default()).unwrap();
        assert!(ap.text.contains("INS_TCAL1_TMAX 100\n"), "{}", ap.text);
        assert!(ap.warnings.iter().any(|w| w.contains("documented")));
    }

    #[test]
    fn channel_names_map_to_sensor_and_axis() {
        assert_eq!(sensor_axis("gyro_x"), Some((Sensor::Gyro, 0)));
        assert_eq!(sensor_axis("accel_z"), Some((Sensor::Accel, 2)));
        assert_eq!(sensor_axis("temp"), None);
    }

    #[test]
    fn float32_text_reads_back_to_the_same_float32() {
        for v in [
            1.234_567_890_123e-9,
            -0.061_234_567_8,
            9.806_65,
            3.0e-12,
            123_456.789,
            0.0,
        ] {
            let text = float32_text("X", v).unwrap();
            assert!(!text.contains('e'), "{text}");
            // Parsed straight to f32, or through f64 as some loaders do.
            assert_eq!(text.parse::<f32>().unwrap(), v as f32, "{text}");
            assert_eq!(text.parse::<f64>().unwrap() as f32, v as f32, "{text}");
        }
        assert!(float32_text("X", 1e39).is_err());
    }
}
