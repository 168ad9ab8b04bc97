//! What the firmware will do with a parameter file on a given recording,
//! in words: which set it applies to which sensor, or why it applies
//! nothing. Any file is judged, imutherm's or another tool's.
//!
//! The rules, from the firmware's source:
//! - PX4, `src/modules/temperature_compensation/TemperatureCompensation.cpp`:
//!   `parameters_update` reads the `TC_G*`/`TC_A*` sets only when
//!   `TC_G_ENABLE`/`TC_A_ENABLE` is 1; `set_sensor_id` picks the set whose
//!   `TC_x{n}_ID` equals the sensor's device id, among n = 0–3, and without
//!   one applies nothing; `calc_thermal_offsets_3D` holds T within
//!   [TMIN, TMAX].
//! - ArduPilot, `libraries/AP_InertialSensor/AP_InertialSensor_tempcal.cpp`,
//!   `correct_sensor`: set `INS_TCALn` corrects the n-th IMU, only when its
//!   `ENABLE` is 1 (2 learns instead), with T held within [TMIN, TMAX]. The
//!   sets carry no device id: the IMU order (`INS_GYRn_ID`) decides.

use super::params::{ParamFile, ParamValue};
use super::{Firmware, FirmwareError, px4};

/// What a recording tells about the vehicle the file is for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunFacts {
    /// The gyro's device id, where the recording gives it.
    pub gyro_id: Option<u32>,
    /// The accelerometer's.
    pub accel_id: Option<u32>,
    /// Whether the recording has gyro channels.
    pub has_gyro: bool,
    /// Whether it has accelerometer channels.
    pub has_accel: bool,
    /// Lowest and highest temperature of the run, °C.
    pub t_range_c: [f64; 2],
}

/// The firmware's behaviour on the run, sentence by sentence.
#[derive(Debug, Clone, PartialEq)]
pub struct Verdict {
    /// One sentence per sensor type, and notes.
    pub says: Vec<String>,
    /// Whether any sensor of the recording gets a correction (where the
    /// recording gives no device id: once the set's id is the sensor's,
    /// which the sentence says).
    pub applies: bool,
}

/// Judges `text` as `firmware` loads it, for the IMU in slot `instance`
/// (ArduPilot's numbering, 1–3; PX4 matches by id and ignores it).
pub fn judge(
    firmware: Firmware,
    text: &str,
    instance: Option<u8>,
    run: &RunFacts,
) -> Result<Verdict, FirmwareError> {
    match firmware {
        Firmware::Px4 => Ok(judge_px4(&ParamFile::parse_qgc(text)?, run)),
        Firmware::ArduPilot => Ok(judge_ardupilot(
            &ParamFile::parse_name_value(text)?,
            instance.unwrap_or(1),
            run,
        )),
    }
}

/// The PX4 set (0–3) whose `TC_G{n}_ID` is the gyro's `device_id`: the
/// one `set_sensor_id` picks.
pub fn px4_gyro_slot(text: &str, device_id: u32) -> Result<Option<u8>, FirmwareError> {
    let file = ParamFile::parse_qgc(text)?;
    Ok(px4::INSTANCES
        .clone()
        .find(|n| file.get(&format!("TC_G{n}_ID")) == Some(ParamValue::Int(device_id as i32))))
}

fn judge_px4(file: &ParamFile, run: &RunFacts) -> Verdict {
    let mut says = Vec::new();
    let mut applies = false;
    for (present, id, what, letter) in [
        (run.has_gyro, run.gyro_id, "gyro", 'G'),
        (run.has_accel, run.accel_id, "accelerometer", 'A'),
    ] {
        if !present {
            continue;
        }
        let enable = format!("TC_{letter}_ENABLE");
        match file.get(&enable) {
            None => {
                says.push(format!("PX4 applies nothing to the {what}: {enable} is absent"));
                continue;
            }
            Some(v) if v != ParamValue::Int(1) => {
                says.push(format!(
                    "PX4 applies nothing to the {what}: {enable} is {}, not 1",
                    v.as_f32()
                ));
                continue;
            }
            Some(_) => {}
        }
        let slots: Vec<(u8, i32)> = px4::INSTANCES
            .filter_map(|n| match file.get(&format!("TC_{letter}{n}_ID")) {
                Some(ParamValue::Int(i)) => Some((n, i)),
                _ => None,
            })
            .collect();
        // Without the recording's id, the set PX4 would take if its id
        // were the sensor's, and that id: the sentence then says the
        // condition instead of a plain "applies".
        let mut unconfirmed = None;
        let chosen = match id {
            Some(id) => match slots.iter().find(|(_, i)| *i as u32 == id) {
                Some(&(n, _)) => n,
                None => {
                    let listed: Vec<String> = slots
                        .iter()
                        .map(|(n, i)| format!("TC_{letter}{n}_ID {i}"))
                        .collect();
                    says.push(format!(
                        "PX4 applies nothing to the {what}: its device id {id} matches no set ({})",
                        if listed.is_empty() {
                            "none has an id".to_string()
                        } else {
                            listed.join(", ")
                        }
                    ));
                    continue;
                }
            },
            None => match slots.first() {
                Some(&(n, i)) => {
                    unconfirmed = Some(i);
                    n
                }
                None => {
                    says.push(format!(
                        "PX4 applies nothing to the {what}: no TC_{letter}0..3_ID in the file"
                    ));
                    continue;
                }
            },
        };
        let p = format!("TC_{letter}{chosen}");
        let range = (file.get(&format!("{p}_TMIN")), file.get(&format!("{p}_TMAX")));
        let (Some(lo), Some(hi)) = range else {
            says.push(format!(
                "PX4 cannot apply {p} to the {what}: {p}_TMIN or {p}_TMAX is absent"
            ));
            continue;
        };
        match range_sentence(&p, lo.as_f32(), hi.as_f32(), run.t_range_c) {
            Err(miss) => says.push(format!(
                "PX4 corrects the {what} with {p} by a constant only: {miss}"
            )),
            Ok(note) => {
                applies = true;
                says.push(match unconfirmed {
                    None => format!("PX4 applies {p} to the {what}{note}"),
                    // PX4's device ids are never 0: the exported
                    // placeholder matches no sensor.
                    Some(0) => format!(
                        "PX4 applies nothing to the {what} as the file stands: {p}_ID is 0, a placeholder no sensor matches; \
                         once it holds the {what}'s device id PX4 applies {p}, as evaluated here{note}"
                    ),
                    Some(i) => format!(
                        "the recording gives no {what} device id: PX4 applies {p} to the {what} only if {i} is that id{note}"
                    ),
                });
            }
        }
    }
    Verdict { says, applies }
}

fn judge_ardupilot(file: &ParamFile, n: u8, run: &RunFacts) -> Verdict {
    let p = format!("INS_TCAL{n}");
    let mut says = Vec::new();
    let applies = match file.get(&format!("{p}_ENABLE")).map(ParamValue::as_f32) {
        None => {
            says.push(format!(
                "ArduPilot applies nothing to IMU {n}: {p}_ENABLE is absent"
            ));
            false
        }
        Some(2.0) => {
            says.push(format!(
                "ArduPilot applies nothing to IMU {n}: {p}_ENABLE is 2, which learns a calibration instead"
            ));
            false
        }
        Some(v) if v != 1.0 => {
            says.push(format!(
                "ArduPilot applies nothing to IMU {n}: {p}_ENABLE is {v}, not 1"
            ));
            false
        }
        Some(_) => match (file.get(&format!("{p}_TMIN")), file.get(&format!("{p}_TMAX"))) {
            (Some(lo), Some(hi)) => match range_sentence(&p, lo.as_f32(), hi.as_f32(), run.t_range_c) {
                Err(miss) => {
                    says.push(format!(
                        "ArduPilot corrects IMU {n} with {p} by a constant only: {miss}"
                    ));
                    false
                }
                Ok(note) => {
                    says.push(format!(
                        "ArduPilot applies {p} to IMU {n} (the set carries no device id: it goes to IMU {n} in the firmware's order, the one INS_GYR{n}_ID names){note}"
                    ));
                    true
                }
            },
            _ => {
                says.push(format!(
                    "ArduPilot applies nothing to IMU {n}: {p}_TMIN or {p}_TMAX is absent"
                ));
                false
            }
        },
    };
    Verdict { says, applies }
}

/// `Ok` with a note when the run lies (partly) within [TMIN, TMAX]; `Err`
/// when it misses the range entirely, so that the firmware holds T at one
/// end throughout and the correction is a constant.
fn range_sentence(p: &str, lo: f32, hi: f32, [a, b]: [f64; 2]) -> Result<String, String> {
    let (lo, hi) = (f64::from(lo), f64::from(hi));
    // TMIN and TMAX are the run's own ends rounded to float32: a run
    // beyond them by that rounding alone is within them.
    let slack = f64::from(f32::EPSILON) * lo.abs().max(hi.abs()).max(1.0);
    if lo > hi || lo.is_nan() || hi.is_nan() {
        return Err(format!("{p}_TMIN {lo} is above {p}_TMAX {hi}"));
    }
    if b < lo || a > hi {
        return Err(format!(
            "the run's {a:.1}…{b:.1} °C misses {p}_TMIN…TMAX {lo:.1}…{hi:.1} °C"
        ));
    }
    if a < lo - slack || b > hi + slack {
        return Ok(format!(
            "; the run's {a:.1}…{b:.1} °C goes beyond {lo:.1}…{hi:.1} °C, where T is held at the edge"
        ));
    }
    Ok(String::new())
}

#[cfg(test)]
mod tests {
    use super::*;

    const RUN: RunFacts = RunFacts {
        gyro_id: Some(2_490_378),
        accel_id: Some(2_490_634),
        has_gyro: true,
        has_accel: true,
        t_range_c: [25.0, 60.0],
    };

    fn px4_file(enable: bool, gyro_id: i32, tmin: f32, tmax: f32) -> String {
        let mut s = String::new();
        if enable {
            s += "1\t1\tTC_G_ENABLE\t1\t6\n1\t1\tTC_A_ENABLE\t1\t6\n";
        }
        for (l, id) in [('G', gyro_id), ('A', 2_490_634)] {
            s += &format!(
                "1\t1\tTC_{l}0_ID\t{id}\t6\n1\t1\tTC_{l}0_TMIN\t{tmin}\t9\n1\t1\tTC_{l}0_TMAX\t{tmax}\t9\n"
            );
        }
        s
    }

    #[test]
    fn a_px4_file_without_enable_applies_nothing_and_says_so() {
        // The shape of process_sensor_caldata.py's own output: no ENABLE.
        let v = judge(Firmware::Px4, &px4_file(false, 2_490_378, 20.0, 70.0), None, &RUN).unwrap();
        assert!(!v.applies);
        assert_eq!(
            v.says[0],
            "PX4 applies nothing to the gyro: TC_G_ENABLE is absent"
        );
    }

    #[test]
    fn a_px4_set_is_matched_by_device_id() {
        let v = judge(Firmware::Px4, &px4_file(true, 2_490_378, 20.0, 70.0), None, &RUN).unwrap();
        assert!(v.applies, "{v:?}");
        assert_eq!(
            v.says,
            [
                "PX4 applies TC_G0 to the gyro",
                "PX4 applies TC_A0 to the accelerometer"
            ]
        );
        let v = judge(Firmware::Px4, &px4_file(true, 0, 20.0, 70.0), None, &RUN).unwrap();
        assert!(
            v.says[0].contains("its device id 2490378 matches no set (TC_G0_ID 0)"),
            "{v:?}"
        );
        assert!(v.applies, "the accelerometer's set still matches");
        let gyro_only = RunFacts {
            has_accel: false,
            ..RUN
        };
        assert!(
            !judge(Firmware::Px4, &px4_file(true, 0, 20.0, 70.0), None, &gyro_only)
                .unwrap()
                .applies
        );
    }

    /// A recording without device ids and a file with the exported
    /// placeholder: one sentence per sensor, which never says PX4 applies
    /// a set that, as written, matches no sensor.
    #[test]
    fn a_placeholder_id_is_never_said_to_be_applied() {
        let no_ids = RunFacts {
            gyro_id: None,
            accel_id: None,
            ..RUN
        };
        let v = judge(Firmware::Px4, &px4_file(true, 0, 20.0, 70.0), None, &no_ids).unwrap();
        assert_eq!(v.says.len(), 2, "{v:?}");
        assert!(
            v.says[0].starts_with(
                "PX4 applies nothing to the gyro as the file stands: TC_G0_ID is 0, a placeholder"
            ),
            "{v:?}"
        );
        assert!(!v.says[0].contains("PX4 applies TC_G0 to"), "{v:?}");
        // The accelerometer's set names a real id: applied only if it is
        // the sensor's.
        assert_eq!(
            v.says[1],
            "the recording gives no accelerometer device id: PX4 applies TC_A0 to the accelerometer only if 2490634 is that id"
        );
    }

    /// TMIN/TMAX are the fitted run's ends in float32: the same run is
    /// within them, not "beyond 27.8…70.0 °C" by the rounding.
    #[test]
    fn a_run_at_its_own_float32_rounded_range_is_within_it() {
        let (lo, hi) = (27.812_345_678_9_f64, 70.012_345_678_9_f64);
        let (lo32, hi32) = (lo as f32, hi as f32);
        assert!(
            f64::from(lo32) > lo || f64::from(hi32) < hi,
            "the case needs a rounding inward"
        );
        let run = RunFacts {
            t_range_c: [lo, hi],
            ..RUN
        };
        let text = px4_file(true, 2_490_378, lo32, hi32);
        let v = judge(Firmware::Px4, &text, None, &run).unwrap();
        assert_eq!(v.says[0], "PX4 applies TC_G0 to the gyro", "{v:?}");
    }

    #[test]
    fn the_px4_gyro_set_is_the_one_with_the_gyros_id() {
        let text = px4_file(true, 7, 20.0, 70.0) + "1\t1\tTC_G2_ID\t2490378\t6\n";
        assert_eq!(px4_gyro_slot(&text, 2_490_378).unwrap(), Some(2));
        assert_eq!(px4_gyro_slot(&text, 7).unwrap(), Some(0));
        assert_eq!(px4_gyro_slot(&text, 9).unwrap(), None);
    }

    #[test]
    fn a_range_that_misses_the_run_is_a_constant_only() {
        let v = judge(Firmware::Px4, &px4_file(true, 2_490_378, 70.0, 80.0), None, &RUN).unwrap();
        assert!(!v.applies);
        assert!(v.says[0].contains("misses TC_G0_TMIN…TMAX 70.0…80.0 °C"), "{v:?}");
        let v = judge(Firmware::Px4, &px4_file(true, 2_490_378, 30.0, 50.0), None, &RUN).unwrap();
        assert!(v.applies && v.says[0].contains("held at the edge"), "{v:?}");
    }

    #[test]
    fn an_ardupilot_set_needs_its_enable_for_its_imu() {
        let text = "INS_TCAL1_ENABLE 1\nINS_TCAL1_TMIN 20\nINS_TCAL1_TMAX 70\n";
        assert!(judge(Firmware::ArduPilot, text, Some(1), &RUN).unwrap().applies);
        let v = judge(Firmware::ArduPilot, text, Some(2), &RUN).unwrap();
        assert!(!v.applies);
        assert_eq!(
            v.says[0],
            "ArduPilot applies nothing to IMU 2: INS_TCAL2_ENABLE is absent"
        );
        let learning = text.replace("ENABLE 1", "ENABLE 2");
        assert!(
            !judge(Firmware::ArduPilot, &learning, Some(1), &RUN)
                .unwrap()
                .applies
        );
    }
}
