//! Every IMU of a flight controller's log in one go: `tcal fit` on a PX4
//! ULog and an ArduPilot DataFlash log of two IMUs gives one model, `tcal
//! export` one parameter file covering both, and `tcal eval --params`
//! judges it per instance.
//!
//! The logs are written here byte by byte, and the exported files are
//! read and applied with this test's own transcription of each firmware,
//! not with imutherm's code:
//! - PX4 `src/modules/temperature_compensation/TemperatureCompensation.cpp`:
//!   `set_sensor_id` picks the set n whose `TC_G{n}_ID`/`TC_A{n}_ID` is
//!   the sensor's device id; `calc_thermal_offsets_3D` holds T within
//!   [TMIN, TMAX] and subtracts X0 + X1·dT + X2·dT² + X3·dT³, in float.
//! - ArduPilot `libraries/AP_InertialSensor/AP_InertialSensor_tempcal.cpp`:
//!   `correct_sensor` applies `INS_TCAL{n}` to IMU n − 1 when its ENABLE is
//!   1, T held within [TMIN, TMAX], v −= poly(T − 35) and
//!   v += poly(CALTEMP − 35), poly(d) = (C1 + (C2 + C3·d)·d)·d·1e-6.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use serde_json::Value;

mod support;
use support::{Refused, cli, imutherm, json_stdout, read_json, tcal_fit};

const RATE_HZ: f64 = 25.0;
const SAMPLES: usize = 20 * 60 * 25;
const G: f64 = 9.80665;
/// Gyro and accelerometer ids of the two IMUs (ICM-20602-like, as PX4 and
/// ArduPilot build them: bus type, bus, address, device type).
const IDS: [(u32, u32); 2] = [(2_490_378, 2_490_634), (3_407_882, 3_408_138)];

/// The true bias of `instance`'s gyro (k < 3) or accelerometer (k ≥ 3)
/// axis k % 3 at `t` °C: a cubic about 40 °C, different per instance.
fn bias(instance: usize, k: usize, t: f64) -> f64 {
    let d = t - 40.0;
    let s = if instance == 0 { 1.0 } else { -0.7 };
    let a = (k % 3) as f64 + 1.0;
    let scale = if k < 3 { 1.0 } else { 10.0 };
    scale * s * (3e-3 * a + 2e-4 * a * d - 4e-6 * d * d + 2e-7 * a * d * d * d)
}

/// A deterministic Gaussian stream (xorshift64 and Box–Muller).
struct Noise(u64);

impl Noise {
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        ((self.0 >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    fn gauss(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

/// One run of both IMUs: per instance the temperature and the six
/// channels (gyro x–z, accel x–z) at [`RATE_HZ`].
struct Run {
    temp: [Vec<f64>; 2],
    data: [[Vec<f64>; 6]; 2],
}

fn run(heating: bool, seed: u64) -> Run {
    let mut noise = Noise(seed);
    let mut out = Run {
        temp: Default::default(),
        data: Default::default(),
    };
    for j in 0..SAMPLES {
        let frac = 1.0 - (-(j as f64) / (SAMPLES as f64 / 3.0)).exp();
        // The held-out cooling stays within the range the heating covers
        // (20 to 58 °C), where the firmware applies the fit unclamped.
        let t = if heating {
            20.0 + 40.0 * frac
        } else {
            57.0 - 35.0 * frac
        };
        for i in 0..2 {
            // The second IMU sits a little warmer on the board.
            let ti = t + 1.5 * i as f64;
            out.temp[i].push((ti / 0.01).round() * 0.01);
            for k in 0..6 {
                let (rest, sigma) = if k == 5 {
                    (-G, 2e-3)
                } else if k < 3 {
                    (0.0, 2e-4)
                } else {
                    (0.0, 2e-3)
                };
                out.data[i][k].push(rest + bias(i, k, ti) + sigma * noise.gauss());
            }
        }
    }
    out
}

/// An ArduPilot DataFlash log (`LogStructure.h`: FMT, PARM `QNf`, IMU
/// `QBffffffIIfBBHH`) of both IMUs, with their `INS_GYRn_ID`/`INS_ACCn_ID`
/// in PARM messages as ArduPilot logs its parameters at start.
fn dataflash(path: &Path, r: &Run) {
    let head = [0xA3u8, 0x95];
    let mut out = Vec::new();
    let fmt = |out: &mut Vec<u8>, ty: u8, len: u8, name: &str, format: &str, labels: &str| {
        out.extend(head);
        out.extend([128, ty, len]);
        for (s, n) in [(name, 4), (format, 16), (labels, 64)] {
            let mut b = s.as_bytes().to_vec();
            b.resize(n, 0);
            out.extend(b);
        }
    };
    fmt(
        &mut out,
        128,
        89,
        "FMT",
        "BBnNZ",
        "Type,Length,Name,Format,Columns",
    );
    fmt(&mut out, 64, 31, "PARM", "QNf", "TimeUS,Name,Value");
    fmt(
        &mut out,
        4,
        54,
        "IMU",
        "QBffffffIIfBBHH",
        "TimeUS,I,GyrX,GyrY,GyrZ,AccX,AccY,AccZ,EG,EA,T,GH,AH,GHz,AHz",
    );
    for (name, id) in [
        ("INS_GYR_ID", IDS[0].0),
        ("INS_ACC_ID", IDS[0].1),
        ("INS_GYR2_ID", IDS[1].0),
        ("INS_ACC2_ID", IDS[1].1),
        ("INS_GYR3_ID", 0),
    ] {
        out.extend(head);
        out.push(64);
        out.extend(1000u64.to_le_bytes());
        let mut b = name.as_bytes().to_vec();
        b.resize(16, 0);
        out.extend(b);
        out.extend((id as f32).to_le_bytes());
    }
    for j in 0..SAMPLES {
        let us = 1_000_000u64 + (j as f64 * 1e6 / RATE_HZ) as u64;
        for i in 0..2 {
            out.extend(head);
            out.push(4);
            out.extend(us.to_le_bytes());
            out.push(i as u8);
            for k in 0..6 {
                out.extend((r.data[i][k][j] as f32).to_le_bytes());
            }
            out.extend([0u8; 8]);
            out.extend((r.temp[i][j] as f32).to_le_bytes());
            out.extend([1, 1]);
            out.extend(1000u16.to_le_bytes());
            out.extend(1000u16.to_le_bytes());
        }
    }
    std::fs::write(path, out).unwrap();
}

/// A PX4 ULog (docs.px4.io, "ULog File Format": header, F formats, A
/// subscriptions, D data) with `sensor_gyro` and `sensor_accel` of both
/// IMUs, each carrying its `device_id` and temperature.
fn ulog(path: &Path, r: &Run) {
    let msg = |out: &mut Vec<u8>, kind: u8, body: &[u8]| {
        out.extend((body.len() as u16).to_le_bytes());
        out.push(kind);
        out.extend(body);
    };
    let mut out = b"ULog\x01\x12\x35\x01".to_vec();
    out.extend(0u64.to_le_bytes());
    msg(&mut out, b'B', &[0; 40]);
    let fields = "uint64_t timestamp;uint64_t timestamp_sample;uint32_t device_id;float x;float y;float z;float temperature;uint32_t error_count;";
    for topic in ["sensor_gyro", "sensor_accel"] {
        msg(&mut out, b'F', format!("{topic}:{fields}").as_bytes());
    }
    let mut ids = Vec::new();
    for (topic, sensor) in [("sensor_gyro", 0), ("sensor_accel", 1)] {
        for i in 0..2u8 {
            let id = ids.len() as u16;
            let mut body = vec![i];
            body.extend(id.to_le_bytes());
            body.extend(topic.as_bytes());
            msg(&mut out, b'A', &body);
            ids.push((id, sensor, i as usize));
        }
    }
    for j in 0..SAMPLES {
        let us = 1_000_000u64 + (j as f64 * 1e6 / RATE_HZ) as u64;
        for &(id, sensor, i) in &ids {
            let mut body = id.to_le_bytes().to_vec();
            body.extend(us.to_le_bytes());
            body.extend(us.to_le_bytes());
            body.extend(if sensor == 0 { IDS[i].0 } else { IDS[i].1 }.to_le_bytes());
            for k in 0..3 {
                body.extend((r.data[i][3 * sensor + k][j] as f32).to_le_bytes());
            }
            body.extend((r.temp[i][j] as f32).to_le_bytes());
            body.extend(0u32.to_le_bytes());
            msg(&mut out, b'D', &body);
        }
    }
    std::fs::write(path, out).unwrap();
}

/// A QGroundControl parameter file: name → value (ids as int).
fn parse_qgc(text: &str) -> HashMap<String, f64> {
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(|l| {
            let f: Vec<&str> = l.split('\t').collect();
            assert_eq!(f.len(), 5, "{l:?}");
            (f[2].to_string(), f[3].parse::<f64>().unwrap())
        })
        .collect()
}

/// A `NAME VALUE` file.
fn parse_name_value(text: &str) -> HashMap<String, f32> {
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            assert_eq!(f.len(), 2, "{l:?}");
            (f[0].to_string(), f[1].parse::<f32>().unwrap())
        })
        .collect()
}

/// PX4: the set `set_sensor_id` picks for `device_id`, applied to one
/// sample by `calc_thermal_offsets_3D`; `None` when no set names the id.
fn px4_correct(
    p: &HashMap<String, f64>,
    letter: char,
    device_id: u32,
    axis: usize,
    raw: f64,
    temp: f64,
) -> Option<f64> {
    if p.get(&format!("TC_{letter}_ENABLE")) != Some(&1.0) {
        return None;
    }
    let n = (0..4).find(|n| p.get(&format!("TC_{letter}{n}_ID")) == Some(&(device_id as f64)))?;
    let g = |f: &str| p[&format!("TC_{letter}{n}_{f}")] as f32;
    let t = temp as f32;
    let dt = if t > g("TMAX") {
        g("TMAX") - g("TREF")
    } else if t < g("TMIN") {
        g("TMIN") - g("TREF")
    } else {
        t - g("TREF")
    };
    let x = |k: usize| g(&format!("X{k}_{axis}"));
    Some((raw as f32 - (x(0) + x(1) * dt + x(2) * dt * dt + x(3) * dt * dt * dt)) as f64)
}

/// ArduPilot: `correct_sensor` of set `INS_TCAL{imu + 1}` on IMU `imu`.
fn ardupilot_correct(
    p: &HashMap<String, f32>,
    imu: usize,
    key: &str,
    axis: usize,
    raw: f64,
    temp: f64,
    cal: f64,
) -> Option<f64> {
    let s = format!("INS_TCAL{}", imu + 1);
    if p.get(&format!("{s}_ENABLE")) != Some(&1.0) {
        return None;
    }
    let c = |k: usize| p[&format!("{s}_{key}{k}_{}", ["X", "Y", "Z"][axis])];
    let (lo, hi) = (p[&format!("{s}_TMIN")], p[&format!("{s}_TMAX")]);
    let hold = |t: f32| {
        if t < lo {
            lo
        } else if t > hi {
            hi
        } else {
            t
        }
    };
    let poly = |d: f32| (c(1) + (c(2) + c(3) * d) * d) * d * 1e-6f32;
    Some((raw as f32 - poly(hold(temp as f32) - 35.0) + poly(hold(cal as f32) - 35.0)) as f64)
}

/// The spread (max − min) of the 1 °C bin means of `x`.
fn variation(x: &[f64], t: &[f64]) -> f64 {
    let mut bins: HashMap<i64, (f64, usize)> = HashMap::new();
    for (&v, &t) in x.iter().zip(t) {
        let e = bins.entry(t.floor() as i64).or_default();
        e.0 += v;
        e.1 += 1;
    }
    let means: Vec<f64> = bins
        .values()
        .filter(|b| b.1 >= 50)
        .map(|b| b.0 / b.1 as f64)
        .collect();
    means.iter().cloned().fold(f64::MIN, f64::max) - means.iter().cloned().fold(f64::MAX, f64::min)
}

fn logs(dir: &Path, write: fn(&Path, &Run), ext: &str) -> (PathBuf, PathBuf, Run) {
    let (heat, cool) = (dir.join(format!("heat.{ext}")), dir.join(format!("cool.{ext}")));
    write(&heat, &run(true, 0x9e37_79b9_7f4a_7c15));
    let held_out = run(false, 0x2545_f491_4f6c_dd1d);
    write(&cool, &held_out);
    (heat, cool, held_out)
}

/// `tcal eval --json --export FW --params FILE MODEL RUN`, whose verdicts
/// must name each instance, each applied.
fn eval_per_instance(model: &Path, firmware: &str, params: &Path, run: &Path) -> Value {
    let doc = json_stdout(
        imutherm()
            .args(["tcal", "eval", "--json", "--export", firmware, "--params"])
            .arg(params)
            .arg(model)
            .arg(run),
    );
    let verdicts = doc["firmware"]["verdicts"].as_array().unwrap();
    let instances: Vec<u64> = verdicts.iter().map(|v| v["instance"].as_u64().unwrap()).collect();
    assert_eq!(instances, [0, 1], "{verdicts:?}");
    assert!(verdicts.iter().all(|v| v["applies"] == true), "{verdicts:?}");
    let rows = doc["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 12);
    for r in rows {
        let (before, loaded) = (
            r["bias_rms_before"].as_f64().unwrap(),
            r["bias_rms_as_loaded"].as_f64().unwrap(),
        );
        assert!(
            loaded < 0.2 * before,
            "{} {}: {before:e} → {loaded:e}",
            r["instance"],
            r["channel"]
        );
    }
    doc
}

#[test]
fn a_ulog_of_two_imus_gives_one_px4_file_with_each_imus_ids() {
    let dir = tempfile::tempdir().unwrap();
    let (heat, cool, held_out) = logs(dir.path(), ulog, "ulg");
    let model = dir.path().join("model.json");
    // `--for px4` on a log of several IMUs takes them all.
    tcal_fit(&model, &["--for", "px4"], &[&heat]);
    let m = read_json(&model);
    let instances = m["instances"].as_array().unwrap();
    assert_eq!(instances.len(), 2);
    for (i, inst) in instances.iter().enumerate() {
        assert_eq!(inst["instance"], i as u64);
        assert_eq!(inst["device_id"], IDS[i].0);
        assert_eq!(inst["accel_device_id"], IDS[i].1);
    }
    // The top level is instance 0's whole model.
    assert_eq!(m["device_id"], IDS[0].0);
    assert_eq!(m["channels"], instances[0]["channels"]);

    let params = dir.path().join("all.params");
    cli!["tcal", "export", "--firmware", "px4", "-o", &params, &model]
        .assert()
        .success();
    let text = std::fs::read_to_string(&params).unwrap();
    assert_eq!(text.matches("\tTC_G_ENABLE\t").count(), 1, "{text}");
    assert!(!text.contains("placeholder"), "{text}");
    let p = parse_qgc(&text);
    for (i, (g, a)) in IDS.iter().enumerate() {
        assert_eq!(p[&format!("TC_G{i}_ID")], *g as f64);
        assert_eq!(p[&format!("TC_A{i}_ID")], *a as f64);
    }
    // Applied as PX4 applies it, each sensor by its id, to the held-out run.
    for (i, (gyro_id, accel_id)) in IDS.into_iter().enumerate() {
        for k in 0..6 {
            let (letter, id, axis) = if k < 3 {
                ('G', gyro_id, k)
            } else {
                ('A', accel_id, k - 3)
            };
            let raw = &held_out.data[i][k];
            let t = &held_out.temp[i];
            let out: Vec<f64> = raw
                .iter()
                .zip(t)
                .map(|(&x, &t)| px4_correct(&p, letter, id, axis, x, t).unwrap())
                .collect();
            let (before, after) = (variation(raw, t), variation(&out, t));
            assert!(
                after < 0.05 * before,
                "IMU {i} channel {k}: {before:e} → {after:e}"
            );
        }
    }
    eval_per_instance(&model, "px4", &params, &cool);

    // `tcal apply` compensates the instance asked for, with its own model.
    let out = dir.path().join("imu1.txt");
    cli!["tcal", "apply", "--instance", "1", "-o", &out, &model, &cool]
        .assert()
        .success();
    assert!(out.exists());
    cli!["tcal", "apply", "-o", dir.path().join("none.txt"), &model, &cool].refused(2, "give --instance N");
    assert!(!dir.path().join("none.txt").exists());

    // One slot or id for a model of several is a usage error.
    cli!["tcal", "export", "--firmware", "px4", "--slot", "1", &model].refused(2, "holds instances [0, 1]");
}

#[test]
fn a_dataflash_log_of_two_imus_gives_one_ardupilot_file_in_imu_order() {
    let dir = tempfile::tempdir().unwrap();
    let (heat, cool, held_out) = logs(dir.path(), dataflash, "bin");
    let model = dir.path().join("model.json");
    tcal_fit(&model, &["--instance", "all", "--for", "ardupilot"], &[&heat]);
    let m = read_json(&model);
    let instances = m["instances"].as_array().unwrap();
    // The ids come from the log's INS_GYRn_ID / INS_ACCn_ID.
    for (i, inst) in instances.iter().enumerate() {
        assert_eq!(inst["instance"], i as u64);
        assert_eq!(inst["device_id"], IDS[i].0);
        assert_eq!(inst["accel_device_id"], IDS[i].1);
    }
    let params = dir.path().join("all.parm");
    cli!["tcal", "export", "--firmware", "ardupilot", "-o", &params, &model]
        .assert()
        .success();
    let text = std::fs::read_to_string(&params).unwrap();
    assert!(
        text.contains("INS_GYR2_ID is 3407882 and INS_ACC2_ID is 3408138"),
        "{text}"
    );
    let p = parse_name_value(&text);
    assert_eq!(p.len(), 2 * 21, "{:?}", p.keys());
    let cal_temp = 25.0;
    for i in 0..2 {
        for k in 0..6 {
            let (key, axis) = if k < 3 { ("GYR", k) } else { ("ACC", k - 3) };
            let raw = &held_out.data[i][k];
            let t = &held_out.temp[i];
            let apply = |set: usize| -> f64 {
                let out: Vec<f64> = raw
                    .iter()
                    .zip(t)
                    .map(|(&x, &t)| ardupilot_correct(&p, set, key, axis, x, t, cal_temp).unwrap())
                    .collect();
                variation(&out, t)
            };
            let before = variation(raw, t);
            // Its own set removes the drift; the other IMU's would not.
            assert!(
                apply(i) < 0.05 * before,
                "IMU {i} channel {k}: {before:e} → {:e}",
                apply(i)
            );
            assert!(
                apply(1 - i) > 0.5 * before,
                "IMU {i} channel {k} with the other set"
            );
        }
    }
    eval_per_instance(&model, "ardupilot", &params, &cool);
}

#[test]
fn instance_all_is_refused_where_it_means_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let text = dir.path().join("run.txt");
    std::fs::write(&text, "time_s,gyro_x,temperature\n0,0.1,20\n1,0.1,21\n").unwrap();
    cli![
        "tcal",
        "fit",
        "--instance",
        "all",
        "-o",
        dir.path().join("m.json"),
        &text
    ]
    .refused(2, "has no IMU instances");
    cli!["adev", "--instance", "all", &text].refused(2, "only tcal fit and tcal eval");
    assert!(!dir.path().join("m.json").exists());
}
