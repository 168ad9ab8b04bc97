//! `imutherm tcal export`, `tcal fit --for`, `tcal eval --export` and the
//! model's checks, end to end on simulated runs.
//!
//! The firmware files are read here with this test's own parsers and
//! applied with this test's own transcription of the firmware's formulas,
//! not with imutherm's code, so an error shared by imutherm's writer and
//! its evaluator cannot hide.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use assert_cmd::Command;
use predicates::prelude::*;
use serde_json::Value;

mod support;
use support::{
    Refused, Simulation, cli, imutherm, json_stdout, read_json, replaces_only_with_overwrite, succeed,
    tcal_fit,
};

/// The runs here: 2 Hz, long enough for a thermal profile.
fn simulate(dir: &Path, name: &str, profile: &str, duration: &str, seed: &str) -> PathBuf {
    Simulation::new()
        .profile(profile)
        .duration(duration)
        .rate("2")
        .seed(seed)
        .write(dir, name)
}

/// `imutherm tcal export ARGS MODEL`.
fn export(model: &Path, args: &[&str]) -> Command {
    let mut cmd = imutherm();
    cmd.args(["tcal", "export"]).args(args).arg(model);
    cmd
}

/// `imutherm tcal eval --json ARGS MODEL RUNS…`, which must succeed.
fn eval_json(model: &Path, args: &[&str], runs: &[&Path]) -> Value {
    json_stdout(
        imutherm()
            .args(["tcal", "eval", "--json"])
            .args(args)
            .arg(model)
            .args(runs),
    )
}

/// The thesis-format columns of a simulated run: accel 1–3, gyro 1–3, temp.
struct Columns {
    data: [Vec<f64>; 6],
    temp: Vec<f64>,
}

fn read_columns(path: &Path) -> Columns {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header = lines.next().unwrap();
    assert!(header.starts_with("mpu_accel_1"), "{header}");
    let mut data: [Vec<f64>; 6] = Default::default();
    let mut temp = Vec::new();
    for l in lines {
        let v: Vec<f64> = l.split(',').map(|f| f.trim().parse().unwrap()).collect();
        for (k, col) in data.iter_mut().enumerate() {
            col.push(v[k]);
        }
        temp.push(v[6]);
    }
    Columns { data, temp }
}

/// Means of `x` over 1 °C bins of `t`.
fn bin_means(x: &[f64], t: &[f64]) -> Vec<f64> {
    let mut bins: std::collections::BTreeMap<i64, (f64, usize)> = Default::default();
    for (&v, &tt) in x.iter().zip(t) {
        let e = bins.entry(tt.floor() as i64).or_default();
        e.0 += v;
        e.1 += 1;
    }
    bins.values()
        .filter(|b| b.1 >= 2)
        .map(|b| b.0 / b.1 as f64)
        .collect()
}

/// The bias variation over temperature: RMS of the bin means about their mean.
fn variation(x: &[f64], t: &[f64]) -> f64 {
    let m = bin_means(x, t);
    let mean = m.iter().sum::<f64>() / m.len() as f64;
    (m.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / m.len() as f64).sqrt()
}

/// QGroundControl's parameter file, read as `buildDiffFromFile` reads it
/// (QGroundControl, src/QmlControls/ParameterEditorController.cc): `#`
/// lines are comments, every other line is five tab-separated fields.
fn parse_qgc(text: &str) -> HashMap<String, (f32, u8)> {
    let mut out = HashMap::new();
    for line in text.lines().filter(|l| !l.starts_with('#')) {
        let f: Vec<&str> = line.split('\t').collect();
        assert_eq!(f.len(), 5, "not a QGroundControl parameter line: {line:?}");
        assert_eq!(f[0].parse::<u8>().unwrap(), 1, "{line}");
        assert_eq!(f[1].parse::<u8>().unwrap(), 1, "{line}");
        let kind: u8 = f[4].parse().unwrap();
        let value: f32 = match kind {
            6 => f[3].parse::<i32>().unwrap() as f32,
            9 => f[3].parse::<f32>().unwrap(),
            _ => panic!("type {kind} in {line:?}"),
        };
        assert!(value.is_finite(), "{line}");
        out.insert(f[2].to_string(), (value, kind));
    }
    out
}

/// A `NAME VALUE` parameter file.
fn parse_name_value(text: &str) -> HashMap<String, f32> {
    let mut out = HashMap::new();
    for line in text.lines().filter(|l| !l.starts_with('#')) {
        let f: Vec<&str> = line.split_whitespace().collect();
        assert_eq!(f.len(), 2, "not a NAME VALUE line: {line:?}");
        let v: f32 = f[1].parse().unwrap();
        assert!(v.is_finite(), "{line}");
        out.insert(f[0].to_string(), v);
    }
    out
}

/// PX4, `TemperatureCompensation.cpp`, `calc_thermal_offsets_3D`, in
/// float; the offset is subtracted (`Gyroscope.hpp`/`Accelerometer.hpp`,
/// `Correct`).
fn px4_correct(p: &HashMap<String, (f32, u8)>, prefix: &str, axis: usize, raw: f64, temp: f64) -> f64 {
    let g = |n: &str| p[&format!("{prefix}_{n}")].0;
    let (t, tmin, tmax, tref) = (temp as f32, g("TMIN"), g("TMAX"), g("TREF"));
    let dt = if t > tmax {
        tmax - tref
    } else if t < tmin {
        tmin - tref
    } else {
        t - tref
    };
    let x = |k: usize| g(&format!("X{k}_{axis}"));
    let offset = x(0) + x(1) * dt + x(2) * dt * dt + x(3) * dt * dt * dt;
    (raw as f32 - offset) as f64
}

/// ArduPilot, `AP_InertialSensor_tempcal.cpp`, `correct_sensor` and
/// `polynomial_eval`: coefficients × 1e6 about 35 °C, T and the
/// calibration temperature held within [TMIN, TMAX].
fn ardupilot_correct(p: &HashMap<String, f32>, key: &str, axis: usize, raw: f64, temp: f64, cal: f64) -> f64 {
    let xyz = ["X", "Y", "Z"][axis];
    let c = |k: usize| p[&format!("INS_TCAL1_{key}{k}_{xyz}")];
    let (tmin, tmax) = (p["INS_TCAL1_TMIN"], p["INS_TCAL1_TMAX"]);
    let hold = |t: f32| t.max(tmin).min(tmax);
    let poly = |d: f32| (c(1) + (c(2) + c(3) * d) * d) * d * 1e-6f32;
    let t = hold(temp as f32);
    let cal = hold(cal as f32);
    (raw as f32 - poly(t - 35.0) + poly(cal - 35.0)) as f64
}

#[test]
fn exported_files_correct_a_held_out_run_as_each_firmware_applies_them() {
    let dir = tempfile::tempdir().unwrap();
    let cooling = simulate(dir.path(), "cool.txt", "cooling:100:20:1500", "100m", "11");
    let heating = simulate(dir.path(), "heat.txt", "ramp:20:100:6000", "100m", "12");
    let model = dir.path().join("model.json");
    tcal_fit(&model, &["--order", "3", "--for", "px4"], &[&cooling]);

    let px4 = dir.path().join("imu.params");
    export(&model, &["--firmware", "px4", "--device-id", "2293768"])
        .arg("-o")
        .arg(&px4)
        .assert()
        .success();
    let px4 = parse_qgc(&std::fs::read_to_string(&px4).unwrap());
    for (name, value, kind) in [
        ("TC_G_ENABLE", 1.0, 6),
        ("TC_A_ENABLE", 1.0, 6),
        ("TC_G0_ID", 2293768.0, 6),
        ("TC_A0_ID", 2293768.0, 6),
        ("TC_A0_X0_0", 0.0, 9),
        ("TC_A0_X0_1", 0.0, 9),
        ("TC_A0_X0_2", 0.0, 9),
    ] {
        assert_eq!(px4[name], (value, kind), "{name}");
    }
    assert_eq!(px4.len(), 2 * (2 + 3 + 12), "{:?}", px4.keys());

    // The cooling run reaches 100 °C, past ArduPilot's documented TMAX range.
    let ap = dir.path().join("imu.parm");
    export(&model, &["--firmware", "ardupilot"])
        .arg("-o")
        .arg(&ap)
        .assert()
        .success()
        .stderr(predicate::str::contains(
            "beyond the documented range of INS_TCAL1_TMIN/TMAX",
        ));
    let ap = parse_name_value(&std::fs::read_to_string(&ap).unwrap());
    assert_eq!(ap["INS_TCAL1_ENABLE"], 1.0);
    assert_eq!(ap.len(), 3 + 18, "{:?}", ap.keys());

    // The accelerometer and gyro calibrations ran at room temperature.
    let cal_temp = 25.0;
    let run = read_columns(&heating);
    for (k, raw) in run.data.iter().enumerate() {
        let (axis, accel) = (k % 3, k < 3);
        let before = variation(raw, &run.temp);
        let px4_out: Vec<f64> = raw
            .iter()
            .zip(&run.temp)
            .map(|(&x, &t)| px4_correct(&px4, if accel { "TC_A0" } else { "TC_G0" }, axis, x, t))
            .collect();
        let ap_out: Vec<f64> = raw
            .iter()
            .zip(&run.temp)
            .map(|(&x, &t)| ardupilot_correct(&ap, if accel { "ACC" } else { "GYR" }, axis, x, t, cal_temp))
            .collect();
        for (firmware, out) in [("PX4", &px4_out), ("ArduPilot", &ap_out)] {
            let after = variation(out, &run.temp);
            assert!(
                after <= 0.2 * before,
                "{firmware} column {k}: bias variation {before:.3e} → {after:.3e}"
            );
            if accel {
                // Gravity stays: the mean moves by less than the raw
                // reading's own spread over temperature.
                let m = bin_means(raw, &run.temp);
                let spread =
                    m.iter().cloned().fold(f64::MIN, f64::max) - m.iter().cloned().fold(f64::MAX, f64::min);
                let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
                let shift = (mean(out) - mean(raw)).abs();
                assert!(
                    shift <= spread,
                    "{firmware} accel {axis}: mean moved {shift:.3e}, spread {spread:.3e}"
                );
            }
        }
    }
}

#[test]
fn eval_export_output_loads_and_shows_the_firmware_result() {
    let dir = tempfile::tempdir().unwrap();
    let cooling = simulate(dir.path(), "cool.txt", "cooling:70:20:900", "40m", "21");
    let heating = simulate(dir.path(), "heat.txt", "ramp:22:68:2400", "40m", "22");
    let model = dir.path().join("model.json");
    tcal_fit(&model, &["--for", "ardupilot"], &[&cooling]);
    let out = succeed(
        imutherm()
            .args(["tcal", "eval", "--export", "px4"])
            .arg(&model)
            .arg(&heating),
    );
    let text = String::from_utf8(out.stdout).unwrap();
    // The table is there, as comments.
    assert!(
        text.lines()
            .any(|l| l.starts_with("# ") && l.contains("heat.txt") && l.contains("held out")),
        "{text}"
    );
    assert!(
        text.lines()
            .any(|l| l.starts_with("# ") && l.contains("as loaded RMS")),
        "{text}"
    );
    // Every line is a comment or a parameter: the whole output loads.
    let params = parse_qgc(&text);
    assert!(params.contains_key("TC_G0_X3_2"));
    let doc = eval_json(&model, &["--export", "ardupilot"], &[&heating]);
    parse_name_value(doc["firmware"]["parameters"].as_str().unwrap());
    for r in doc["rows"].as_array().unwrap() {
        let (b, l) = (
            r["bias_rms_before"].as_f64().unwrap(),
            r["bias_rms_as_loaded"].as_f64().unwrap(),
        );
        assert!(l < 0.2 * b, "{}: {b} → {l}", r["channel"]);
        // The level (gravity, for the accelerometers) moves by less than
        // the bias varied over temperature.
        let (lb, ll) = (
            r["level_before"].as_f64().unwrap(),
            r["level_as_loaded"].as_f64().unwrap(),
        );
        let spread = r["bias_max_before"].as_f64().unwrap() * 2.0;
        if r["channel"].as_str().unwrap().starts_with("accel") {
            assert!((lb - ll).abs() < spread, "{}: level {lb} → {ll}", r["channel"]);
        }
    }

    // A file loaded into the vehicle, evaluated as it is: the export, then
    // the same with the coefficients left unscaled (ArduPilot divides them
    // by 1e6), which corrects nothing.
    let parm = dir.path().join("imu.parm");
    export(&model, &["--firmware", "ardupilot"])
        .arg("-o")
        .arg(&parm)
        .assert()
        .success();
    let text = std::fs::read_to_string(&parm).unwrap();
    let unscaled: String = text
        .lines()
        .map(|l| match l.split_once(' ') {
            Some((name, v)) if name.contains("_ACC") || name.contains("_GYR") => {
                format!("{name} {}\n", v.parse::<f64>().unwrap() / 1e6)
            }
            _ => format!("{l}\n"),
        })
        .collect();
    let unscaled_path = dir.path().join("unscaled.parm");
    std::fs::write(&unscaled_path, unscaled).unwrap();
    let as_loaded = |params: &Path| -> Vec<(f64, f64)> {
        let params = params.to_str().unwrap();
        let doc = eval_json(
            &model,
            &["--export", "ardupilot", "--params", params],
            &[&heating],
        );
        doc["rows"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| {
                (
                    r["bias_rms_before"].as_f64().unwrap(),
                    r["bias_rms_as_loaded"].as_f64().unwrap(),
                )
            })
            .collect()
    };
    for (b, l) in as_loaded(&parm) {
        assert!(l < 0.2 * b, "{b} → {l}");
    }
    for (b, l) in as_loaded(&unscaled_path) {
        assert!(l > 0.99 * b, "an unscaled file corrects nothing: {b} → {l}");
    }
}

/// Writes a model JSON with `edit` applied to a sound one.
fn edited_model(dir: &Path, sound: &Path, name: &str, edit: impl Fn(&mut serde_json::Value)) -> PathBuf {
    let mut v = read_json(sound);
    edit(&mut v);
    let p = dir.join(name);
    std::fs::write(&p, serde_json::to_string_pretty(&v).unwrap()).unwrap();
    p
}

#[test]
fn what_a_firmware_cannot_load_is_refused_with_what_to_refit() {
    let dir = tempfile::tempdir().unwrap();
    let cooling = simulate(dir.path(), "cool.txt", "cooling:70:20:900", "40m", "31");
    let quartic = dir.path().join("quartic.json");
    tcal_fit(&quartic, &["--order", "4"], &[&cooling]);
    for fw in ["px4", "ardupilot"] {
        export(&quartic, &["--firmware", fw])
            .assert()
            .code(1)
            .stdout(predicate::str::is_empty())
            .stderr(predicate::str::contains("order 4").and(predicate::str::contains(format!("--for {fw}"))));
    }
    let lagged = dir.path().join("lagged.json");
    tcal_fit(&lagged, &["--order", "2", "--rate-term"], &[&cooling]);
    export(&lagged, &["--firmware", "px4"])
        .assert()
        .code(1)
        .stderr(predicate::str::contains("dT/dt term"));
    // The same refusals at fit time are usage errors.
    for args in [
        vec!["--for", "px4", "--rate-term"],
        vec!["--for", "ardupilot", "--order", "4"],
        vec!["--for", "betaflight"],
    ] {
        imutherm()
            .args(["tcal", "fit"])
            .args(&args)
            .arg(&cooling)
            .arg("-o")
            .arg(dir.path().join("never.json"))
            .assert()
            .code(2);
        assert!(!dir.path().join("never.json").exists());
    }
    // --order auto stops at the cubic.
    let auto = dir.path().join("auto.json");
    tcal_fit(&auto, &["--for", "px4"], &[&cooling]);
    let m = read_json(&auto);
    for c in m["channels"].as_array().unwrap() {
        assert!(c["order"].as_u64().unwrap() <= 3);
        assert!(c["cross_validation"].as_array().unwrap().len() <= 4);
    }
    // Flags the firmware has no room for.
    for args in [
        vec!["--firmware", "ardupilot", "--slot", "0"],
        vec!["--firmware", "px4", "--slot", "4"],
        vec!["--firmware", "px4", "--device-id", "gyro"],
        vec!["--firmware", "inav"],
    ] {
        export(&auto, &args).assert().code(2);
    }
    // PX4 without a device id: a placeholder, commented, and a warning.
    let slot2 = export(&auto, &["--firmware", "px4", "--slot", "2"])
        .assert()
        .success()
        .stdout(
            predicate::str::contains("1\t1\tTC_G2_ID\t0\t6")
                .and(predicate::str::contains("listener sensor_gyro")),
        )
        .stderr(predicate::str::contains("TC_G2_ID is a placeholder"))
        .get_output()
        .stdout
        .clone();
    // `--instance`, the slot's former name here, is the same flag.
    let old = export(&auto, &["--firmware", "px4", "--instance", "2"])
        .assert()
        .success();
    assert_eq!(old.get_output().stdout, slot2);
    // A slot the firmware lacks is named by the flag's current name.
    export(&auto, &["--firmware", "ardupilot", "--slot", "0"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains(
            "--slot 0: ArduPilot has calibration instances 1 to 3",
        ));
}

#[test]
fn export_output_is_written_whole_and_never_replaces_a_file_unasked() {
    let dir = tempfile::tempdir().unwrap();
    let cooling = simulate(dir.path(), "cool.txt", "cooling:70:20:900", "30m", "41");
    let model = dir.path().join("model.json");
    tcal_fit(&model, &["--for", "px4"], &[&cooling]);
    let out = dir.path().join("imu.params");
    std::fs::write(&out, "keep me\n").unwrap();
    replaces_only_with_overwrite(
        &[
            "tcal",
            "export",
            "--firmware",
            "px4",
            model.to_str().unwrap(),
            "-o",
        ],
        &out,
        &["--overwrite"],
    );
    parse_qgc(&std::fs::read_to_string(&out).unwrap());
    // Onto the model itself, even with --overwrite: refused, model intact.
    let before = std::fs::read(&model).unwrap();
    export(&model, &["--firmware", "px4", "--overwrite"])
        .arg("-o")
        .arg(dir.path().join(".").join("model.json"))
        .assert()
        .code(2);
    assert_eq!(std::fs::read(&model).unwrap(), before);
}

#[test]
fn broken_models_are_refused_naming_the_field_and_never_panic() {
    let dir = tempfile::tempdir().unwrap();
    let run = simulate(dir.path(), "run.txt", "ramp:25:60:1800", "30m", "51");
    let sound = dir.path().join("model.json");
    tcal_fit(&sound, &["--order", "2"], &[&run]);
    type Edit = fn(&mut serde_json::Value);
    let cases: Vec<(&str, Edit, &str)> = vec![
        (
            "reversed.json",
            |v| {
                let (a, b) = (v["t_min_c"].clone(), v["t_max_c"].clone());
                v["t_min_c"] = b;
                v["t_max_c"] = a;
            },
            "t_min_c (",
        ),
        (
            "scale.json",
            |v| v["scale_c"] = 0.into(),
            "scale_c (0) is not positive",
        ),
        (
            "huge.json",
            |v| v["channels"][2]["coefficients"][1] = 1e308.into(),
            "channels[2].coefficients overflow",
        ),
        (
            "empty.json",
            |v| v["channels"][1]["coefficients"] = serde_json::json!([]),
            "channels[1].coefficients has 0 coefficients",
        ),
        (
            "temp.json",
            |v| v["channels"][0]["name"] = "temp".into(),
            "channels[0].name 'temp' is the temperature channel",
        ),
        (
            "twice.json",
            |v| {
                let first = v["channels"][0].clone();
                v["channels"].as_array_mut().unwrap().push(first);
            },
            "channels[6].name 'accel_x' repeats channels[0]",
        ),
        (
            "lag.json",
            |v| v["channels"][0]["rate_coefficient"] = 0.5.into(),
            "channels[0].rate_coefficient is set but dtdt_range_c_per_s is missing",
        ),
    ];
    for (name, edit, expected) in cases {
        let m = edited_model(dir.path(), &sound, name, edit);
        for cmd in [
            vec!["tcal".to_string(), "eval".into()],
            vec!["tcal".into(), "apply".into()],
            vec!["tcal".into(), "export".into(), "--firmware".into(), "px4".into()],
        ] {
            let mut c = imutherm();
            c.args(&cmd).arg(&m);
            if cmd[1] != "export" {
                c.arg(&run);
            }
            if cmd[1] == "apply" {
                c.arg("-o").arg(dir.path().join("never.txt"));
            }
            c.assert()
                .code(1)
                .stderr(predicate::str::contains(format!("{}: {expected}", m.display())));
        }
        assert!(!dir.path().join("never.txt").exists());
    }
}

#[test]
fn tref_outside_the_fitted_range_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let run = simulate(dir.path(), "run.txt", "ramp:25:60:1800", "30m", "61");
    for tref in ["500", "10"] {
        cli![
            "tcal",
            "fit",
            "--tref",
            tref,
            "-o",
            dir.path().join("m.json"),
            &run
        ]
        .refused(1, "outside the fitted range");
        assert!(!dir.path().join("m.json").exists());
    }
    // Not a temperature at all: refused when the flags are parsed.
    for tref in ["nan", "inf"] {
        cli![
            "tcal",
            "fit",
            "--tref",
            tref,
            "-o",
            dir.path().join("m.json"),
            &run
        ]
        .assert()
        .code(2)
        .stderr(predicate::str::contains("'--tref <C>'").and(predicate::str::contains("finite number")));
        assert!(!dir.path().join("m.json").exists());
    }
}

#[test]
fn the_rate_term_does_not_amplify_a_temperature_spike() {
    let dir = tempfile::tempdir().unwrap();
    let cooling = simulate(dir.path(), "cool.txt", "cooling:80:20:900", "40m", "71");
    let heating = simulate(dir.path(), "heat.txt", "ramp:22:78:2400", "40m", "72");
    let model = dir.path().join("model.json");
    tcal_fit(&model, &["--order", "2", "--rate-term"], &[&cooling, &heating]);
    let m = read_json(&model);
    let range = m["dtdt_range_c_per_s"].as_array().unwrap();
    let max_rate = range
        .iter()
        .map(|v| v.as_f64().unwrap().abs())
        .fold(0.0, f64::max);
    // One sample of the heating run reads 500 °C.
    let text = std::fs::read_to_string(&heating).unwrap();
    let mut rows = 0;
    let spiked: Vec<String> = text
        .lines()
        .map(|l| {
            if l.starts_with('#') || l.starts_with("mpu") {
                return l.to_string();
            }
            rows += 1;
            if rows != 2000 {
                return l.to_string();
            }
            let mut f: Vec<&str> = l.split(", ").collect();
            f[6] = "500";
            f.join(", ")
        })
        .collect();
    let spiked_path = dir.path().join("spiked.txt");
    std::fs::write(&spiked_path, spiked.join("\n") + "\n").unwrap();
    let out = dir.path().join("comp.txt");
    cli!["tcal", "apply", &model, &spiked_path, "-o", &out]
        .assert()
        .success();
    let raw = read_columns(&spiked_path);
    let comp = read_columns(&out);
    for (k, ch) in m["channels"].as_array().unwrap().iter().enumerate() {
        let lag = ch["rate_coefficient"].as_f64().unwrap().abs() * max_rate;
        // What p(T) − p(T_ref) can reach within the fitted range (|u| ≤ 1,
        // the constant cancels), plus the largest lag correction the fit saw.
        let poly: f64 = ch["coefficients"]
            .as_array()
            .unwrap()
            .iter()
            .skip(1)
            .map(|c| 2.0 * c.as_f64().unwrap().abs())
            .sum();
        let col = match ch["name"].as_str().unwrap() {
            "accel_x" => 0,
            "accel_y" => 1,
            "accel_z" => 2,
            "gyro_x" => 3,
            "gyro_y" => 4,
            _ => 5,
        };
        let worst = raw.data[col]
            .iter()
            .zip(&comp.data[col])
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(
            worst <= poly + lag,
            "channel {k}: moved {worst:.3e} > {:.3e}",
            poly + lag
        );
    }
}

#[test]
fn held_out_is_judged_by_the_file_and_a_run_is_fitted_once() {
    let dir = tempfile::tempdir().unwrap();
    let cooling = simulate(dir.path(), "cool.txt", "cooling:70:20:900", "30m", "81");
    let heating = simulate(dir.path(), "heat.txt", "ramp:22:68:1800", "30m", "82");
    let copy = dir.path().join("copy-of-cool.txt");
    std::fs::copy(&cooling, &copy).unwrap();
    let model = dir.path().join("model.json");
    for twice in [dir.path().join(".").join("cool.txt"), copy.clone()] {
        cli!["tcal", "fit", "-o", &model, &cooling, &twice].refused(2, "are the same recording");
    }
    tcal_fit(&model, &["--order", "2"], &[&cooling]);
    let doc = eval_json(
        &model,
        &[],
        &[&dir.path().join(".").join("cool.txt"), &copy, &heating],
    );
    let held: HashMap<String, bool> = doc["rows"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| {
            let f = r["file"].as_str().unwrap();
            (
                Path::new(f).file_name().unwrap().to_string_lossy().into_owned(),
                r["held_out"].as_bool().unwrap(),
            )
        })
        .collect();
    assert!(!held["cool.txt"]);
    assert!(!held["copy-of-cool.txt"]);
    assert!(held["heat.txt"]);
}

#[test]
fn eval_without_a_run_is_a_usage_error() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("model.json");
    std::fs::write(&model, "{}").unwrap();
    cli!["tcal", "eval", &model]
        .assert()
        .code(2)
        .stdout("")
        .stderr(predicate::str::contains("<FILE>"));
}
