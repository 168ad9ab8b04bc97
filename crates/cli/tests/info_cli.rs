//! `imutherm info` end to end.

use std::fmt::Write as _;

use predicates::prelude::*;

mod support;
use support::{Refused, cli, file, imutherm, json_stdout};

const HEADER: &str = "mpu_accel_1[m/^2], mpu_accel_2[m/^2], mpu_accel_3[m/^2], mpu_gyro_1[rad/s], \
                      mpu_gyro_2[rad/s], mpu_gyro_3[rad/s], temp[degC]\n";

#[test]
fn json_reports_channels_rate_temperature_and_problems_with_lines() {
    let mut body = format!("# format: imutherm-log/1\n# sample_rate_hz: 100\n# device: MPU-9250\n{HEADER}");
    for i in 0..100 {
        let t = 30.0 + i as f64 * 0.1;
        if i == 10 {
            body.push_str(&format!("0.1, 0.2, nan, 0.01, 0.02, 0.03, {t}\n"));
        } else {
            body.push_str(&format!("0.1, 0.2, 9.8, 0.01, 0.02, 0.03, {t}\n"));
        }
    }
    body.push_str("0.1, 0.2, 9.8, 0.0"); // power lost mid-write
    let (_d, p) = file("run.txt", body.as_bytes());
    let doc = json_stdout(imutherm().args(["info", "--json"]).arg(&p));
    assert_eq!(doc["schema"], "imutherm.info/1");
    let f = &doc["files"][0];
    assert_eq!(f["format"], "imutherm log");
    assert_eq!(f["device"], "MPU-9250");
    assert_eq!(f["samples"], 100);
    assert_eq!(f["rate_hz"], 100.0);
    assert_eq!(f["rate_source"], "file metadata");
    assert_eq!(f["duration_s"], 1.0);
    assert_eq!(f["temperature_c"]["min"], 30.0);
    assert!((f["temperature_c"]["max"].as_f64().unwrap() - 39.9).abs() < 1e-9);
    let ch = f["channels"].as_array().unwrap();
    assert_eq!(ch.len(), 7);
    assert_eq!(ch[2]["name"], "accel_z");
    assert_eq!(ch[2]["nan_samples"], 1);
    assert!((ch[2]["mean"].as_f64().unwrap() - 9.8).abs() < 1e-12);
    assert!(ch[2]["std"].as_f64().unwrap() < 1e-12);
    // Every row reads the same: each inertial channel is stuck, a problem
    // of the whole channel (no line); the problems of lines follow.
    let stuck: Vec<&str> = f["checks"]["findings"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|c| c["kind"] == "stuck")
        .map(|c| c["channel"].as_str().unwrap())
        .collect();
    assert_eq!(
        stuck,
        ["accel_x", "accel_y", "accel_z", "gyro_x", "gyro_y", "gyro_z"]
    );
    let problems = support::problem_lines(f);
    assert_eq!(
        problems,
        [("nan".to_string(), 15), ("truncated_last_line".to_string(), 105)]
    );
}

#[test]
fn text_output_has_units_and_problems() {
    let (_d, p) = file("g.csv", b"t[s],gyro_x[deg/s]\n0,1\n0.1,2\n0.2,3\n0.5,4\n0.6,5\n");
    imutherm().arg("info").arg(&p).assert().success().stdout(
        predicate::str::contains("10 Hz (derived from the time column")
            .and(predicate::str::contains("rad/s"))
            .and(predicate::str::contains(
                "line 5: 2 missing samples before this line",
            )),
    );
}

#[test]
fn unreadable_files_are_clear_errors() {
    for (name, content, expect) in [
        ("empty.txt", &b""[..], "no data rows"),
        ("header.txt", HEADER.as_bytes(), "no data rows"),
        (
            "binary.bin",
            &[0xff, 0xfe, 0x00, 0x80, b'\n', 1, 2][..],
            "not UTF-8 text",
        ),
    ] {
        let (_d, p) = file(name, content);
        cli!["info", &p]
            .assert()
            .code(1)
            .stderr(predicate::str::contains(name).and(predicate::str::contains(expect)));
    }
    let (_d, p) = file(
        "bad.txt",
        format!("{HEADER}1,2,3,4,5,6,7\n1,2,3,x,5,6,7\n").as_bytes(),
    );
    cli!["info", &p].refused(1, "bad.txt:3: column 4: cannot read 'x'");
    cli!["info", "--skip-bad-lines", &p]
        .assert()
        .success()
        .stdout(predicate::str::contains(
            "line 3: column 4: cannot read 'x' as a number (skipped as a gap)",
        ));
}

#[test]
fn the_adis16405_csv_and_a_phone_export_as_new_users_feed_them() {
    let dir = tempfile::tempdir().unwrap();
    // The static ADIS16405 run of SMAC-Group/imudata as a user converts it.
    let adis = dir.path().join("adis.csv");
    let mut text = String::from("t_s,gyro_x_dps,gyro_y_dps,gyro_z_dps,acc_x_g,acc_y_g,acc_z_g\n");
    for k in 0..3000 {
        let _ = writeln!(text, "{:.2},0.05,-0.4,0.3,0.0,0.0,-1.0", k as f64 / 100.0);
    }
    std::fs::write(&adis, text).unwrap();
    let doc = json_stdout(imutherm().args(["info", "--json"]).arg(&adis));
    let f = &doc["files"][0];
    assert_eq!(f["rate_hz"], 100.0);
    assert_eq!(f["channels"].as_array().unwrap().len(), 6, "t_s is the time axis");
    for c in f["channels"].as_array().unwrap() {
        assert_eq!(c["unit_source"], "header", "{c}");
    }
    let gx = &f["channels"][0];
    assert!((gx["mean"].as_f64().unwrap() - 0.05f64.to_radians()).abs() < 1e-12);

    // A phone app's export: no units, accelerometer in g.
    let phone = dir.path().join("phone.csv");
    let mut text = String::from("timestamp,ax,ay,az,gx,gy,gz\n");
    for k in 0..2000u64 {
        let _ = writeln!(text, "{},0.01,0.02,0.99,0.001,0.002,0.003", k * 5);
    }
    std::fs::write(&phone, text).unwrap();
    let out = imutherm().arg("info").arg(&phone).output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("m/s^2 (assumed)") && text.contains("rad/s (assumed)"),
        "{text}"
    );
    assert!(text.contains("looks like g"), "{text}");
    assert!(text.contains("unit ms, guessed from the median step"), "{text}");
    assert!(text.contains("rate         200 Hz"), "{text}");
    // adev repeats what the reader guessed.
    let out = cli!["adev", "--channels", "gyro_x", &phone].output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("guessed from the median step") && err.contains("0 gaps filled"),
        "{err}"
    );
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(table.contains("[rad/s (assumed)]"), "{table}");
}

#[test]
fn a_logger_whose_chip_runs_0_3_percent_fast_stamped_in_integer_ms() {
    let rate = 200.0 * 1.003;
    let mut text = String::from("timestamp[ms],gyro_x[rad/s]\n");
    for k in 0..36_108u32 {
        let _ = writeln!(text, "{},{k}", (f64::from(k) / rate * 1e3).floor());
    }
    let (_dir, p) = file("fast.csv", text.as_bytes());
    let out = imutherm().arg("info").arg(&p).output().unwrap();
    let shown = String::from_utf8_lossy(&out.stdout);
    assert!(shown.contains("rate         200.6 Hz"), "{shown}");
    assert!(
        shown.contains("the median step (0.005000 s) would say 200 Hz"),
        "{shown}"
    );
    let doc = json_stdout(imutherm().args(["info", "--json"]).arg(&p));
    let f = &doc["files"][0];
    // Every real sample kept, none invented.
    assert_eq!(f["samples"], 36_108);
    assert_eq!(f["channels"][0]["nan_samples"], 0);
    assert_eq!(f["dropped_samples"], 0);
    let fitted = f["clock"]["rate_hz"].as_f64().unwrap();
    assert!((fitted / rate - 1.0).abs() < 5e-4, "{fitted}");
}
