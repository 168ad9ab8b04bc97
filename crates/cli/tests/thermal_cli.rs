//! `imutherm thermal` and `imutherm tcal` end to end, on simulated runs.

use predicates::prelude::*;

mod support;
use support::{Refused, Simulation, cli, imutherm, json_stdout, read_json, tcal_fit};

/// The runs here: 40 minutes at 5 Hz.
fn simulate(dir: &std::path::Path, name: &str, profile: &str, seed: &str) -> std::path::PathBuf {
    Simulation::new()
        .profile(profile)
        .duration("40m")
        .rate("5")
        .seed(seed)
        .write(dir, name)
}

#[test]
fn fit_apply_eval_and_the_surface() {
    let dir = tempfile::tempdir().unwrap();
    let cooling = simulate(dir.path(), "cool.txt", "cooling:90:25:700", "1");
    let heating = simulate(dir.path(), "heat.txt", "ramp:30:85:2000", "2");
    let model = dir.path().join("model.json");
    tcal_fit(&model, &["--order", "3", "--tref", "35"], &[&cooling])
        .stderr(predicate::str::contains("gyro_x   order 3"));
    let m = read_json(&model);
    assert_eq!(m["schema"], "imutherm.tcal/1");
    assert_eq!(m["t_ref_c"], 35.0);
    assert_eq!(m["channels"].as_array().unwrap().len(), 6);

    // Evaluated on the heating run the fit never saw: the bias over
    // temperature shrinks by more than 90 %.
    let doc = json_stdout(
        imutherm()
            .args(["tcal", "eval", "--json"])
            .arg(&model)
            .arg(&heating),
    );
    for r in doc["rows"].as_array().unwrap() {
        let (b, a) = (
            r["bias_rms_before"].as_f64().unwrap(),
            r["bias_rms_after"].as_f64().unwrap(),
        );
        assert!(a < 0.1 * b, "{}: {b} → {a}", r["channel"]);
    }
    cli!["tcal", "eval", "--export", "ardupilot", &model, &heating]
        .assert()
        .success()
        .stdout(
            predicate::str::contains("INS_TCAL1_GYR1_X").and(predicate::str::contains("INS_TCAL1_ACC3_Z")),
        );
    cli!["tcal", "eval", "--export", "px4", &model, &heating]
        .assert()
        .success()
        .stdout(
            predicate::str::contains("\tTC_G0_X3_2\t")
                .and(predicate::str::contains("1\t1\tTC_A0_TREF\t35\t9")),
        );

    let comp = dir.path().join("heat_comp.txt");
    cli!["tcal", "apply", &model, &heating, "-o", &comp]
        .assert()
        .success();
    let text = std::fs::read_to_string(&comp).unwrap();
    assert!(text.contains("# temperature_compensated_with:"));

    let doc = json_stdout(
        imutherm()
            .args(["thermal", "--channels", "gyro_x", "--bin-width", "10", "--json"])
            .arg(&cooling),
    );
    assert_eq!(doc["schema"], "imutherm.thermal/1");
    let rows = doc["channels"][0]["rows"].as_array().unwrap();
    assert!(rows.len() >= 5, "{} bins", rows.len());
    assert!(rows.iter().all(|r| !r["points"].as_array().unwrap().is_empty()));
    cli![
        "thermal",
        "--by",
        "time",
        "--window",
        "300",
        "--channels",
        "gyro",
        &cooling
    ]
    .assert()
    .success()
    .stdout(predicate::str::contains("window [s]"));
}

#[test]
fn degenerate_inputs_exit_1() {
    let dir = tempfile::tempdir().unwrap();
    let flat = simulate(dir.path(), "flat.txt", "constant:34", "3");
    let model = dir.path().join("m.json");
    cli!["tcal", "fit", &flat, "-o", &model].refused(1, "nothing to fit a temperature model to");
    let narrow = simulate(dir.path(), "narrow.txt", "ramp:30:33.5:2400", "4");
    cli!["tcal", "fit", "--order", "6", &narrow, "-o", &model]
        .refused(1, "cannot determine a polynomial of order 6");
    // A model applied to a file without its channels.
    let warm = simulate(dir.path(), "warm.txt", "ramp:30:60:2400", "5");
    tcal_fit(&model, &["--order", "1"], &[&warm]);
    let other = dir.path().join("other.csv");
    std::fs::write(&other, "temp,pressure[hPa]\n30,1013\n31,1012\n").unwrap();
    cli!["tcal", "apply", &model, &other, "-o", dir.path().join("o.txt")]
        .refused(1, "the model has channel 'accel_x', the file does not");
}

/// A 10 Hz log of one gyro over a linear cooling: its samples lost over
/// 1000..1990 (the second 100 s window keeps 10), its temperature lost over
/// 2100..2150.
fn gappy_log() -> (String, Vec<f64>) {
    let temps: Vec<f64> = (0..3000).map(|i| 80.0 - 0.01 * i as f64).collect();
    let mut body =
        String::from("# format: imutherm-log/1\n# sample_rate_hz: 10\ngyro_x[rad/s], temp[degC]\n");
    for (i, t) in temps.iter().enumerate() {
        let gyro = if (1000..1990).contains(&i) {
            "nan".to_string()
        } else {
            format!("{}", ((i * 7919) % 101) as f64 * 1e-4)
        };
        let temp = if (2100..2150).contains(&i) {
            "nan".to_string()
        } else {
            format!("{t}")
        };
        body.push_str(&format!("{gyro}, {temp}\n"));
    }
    (body, temps)
}

#[test]
fn time_windows_list_what_they_leave_out_and_label_what_they_keep() {
    let (body, temps) = gappy_log();
    let (_dir, log) = support::file("gappy.txt", &body);
    let by_time = ["thermal", "--by", "time", "--window", "100", "--step", "100"];
    let doc = json_stdout(imutherm().args(by_time).arg("--json").arg(&log));
    let ch = &doc["channels"][0];
    let rows = ch["rows"].as_array().unwrap();
    let starts: Vec<f64> = rows.iter().map(|r| r["start"].as_f64().unwrap()).collect();
    assert_eq!(starts, [0.0, 200.0]);
    let skipped = ch["skipped"].as_array().unwrap();
    assert_eq!(skipped.len(), 1);
    assert_eq!(
        (skipped[0]["start"].as_f64(), skipped[0]["end"].as_f64()),
        (Some(100.0), Some(200.0))
    );
    let reason = skipped[0]["reason"].as_str().unwrap();
    assert!(reason.contains("10 valid samples"), "{reason}");
    // The last window is labelled by the 950 samples that have a
    // temperature, not made NaN by the 50 that lack one.
    let last = &rows[1];
    assert_eq!(last["samples"], 950);
    let labelled: Vec<f64> = (2000..3000)
        .filter(|i| !(2100..2150).contains(i))
        .map(|i| temps[i])
        .collect();
    let mean = labelled.iter().sum::<f64>() / labelled.len() as f64;
    let got = last["t_mean_c"].as_f64().unwrap();
    assert!((got - mean).abs() < 1e-9, "{got} {mean}");

    imutherm()
        .args(by_time)
        .arg(&log)
        .assert()
        .success()
        .stdout(predicate::str::contains(
            "no curve for 100.0–200.0 s: 10 valid samples",
        ));
}
