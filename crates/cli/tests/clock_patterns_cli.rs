//! Stamps that follow a pattern rather than one clock, through `info`: a
//! publisher whose steps cluster on values no one clock makes (a PX4 log),
//! and a regular duty cycle (psim's thermal-vacuum gyro, bursts of 5 s
//! every 305 s), each said in the text and the JSON with its figures; and
//! the 16× grid guard still refusing a time column that is plainly wrong.

mod support;

use std::path::{Path, PathBuf};

use serde_json::Value;
use support::{imutherm, json_stdout, stderr_of};

fn px4(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../robotlogs/tests/fixtures/px4")
        .join(name)
}

/// psim, MATLAB/sensor_models/TVCtest3_7_20.csv (commit 2028d48, whose tree holds it beside its MIT LICENSE; the same bytes as at 91d70ad).
fn tvac() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/psim_tvac/TVCtest3_7_20.csv")
}

fn info_text(path: &Path) -> String {
    let out = imutherm().arg("info").arg(path).output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", stderr_of(&out));
    String::from_utf8(out.stdout).unwrap()
}

fn info_json(path: &Path) -> Value {
    let doc = json_stdout(imutherm().args(["info", "--json"]).arg(path));
    doc["files"][0].clone()
}

#[test]
fn a_publisher_on_steps_no_clock_makes_is_said_and_timed_by_its_span() {
    // sample_appended_multiple.ulg (an FMUv4-PRO): sensor_combined steps
    // 4 ms (2,228 of its 2,372 steps) and 4.8 ms (142), counted here with
    // pyulog 1.2 (steps rounded to 0.1 ms; the rest are 8 and 16 ms).
    let log = px4("sample_appended_multiple.ulg");
    let text = info_text(&log);
    assert!(
        text.contains("published irregularly: steps of 4 and 4.8 ms (2228 and 142 of the 2372 steps)"),
        "{text}"
    );
    // The span of its stamps, as pyulog reads them (expected.json).
    let expected: Value =
        serde_json::from_str(&std::fs::read_to_string(px4("expected.json")).unwrap()).unwrap();
    let e = &expected["sample_appended_multiple.ulg"]["sensor_combined"];
    let span = (e["last_timestamp_us"].as_f64().unwrap() - e["first_timestamp_us"].as_f64().unwrap()) * 1e-6;
    assert!(text.contains(&format!("duration     {span:.3} s")), "{text}");
    let f = info_json(&log);
    let p = &f["clock"]["pattern"];
    assert_eq!(p["kind"], "irregular", "{p}");
    assert_eq!(p["step_counts"], serde_json::json!([2228, 142]));
    let steps: Vec<f64> = p["steps_s"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert!(
        (steps[0] - 4.0e-3).abs() < 2e-5 && (steps[1] - 4.8e-3).abs() < 2e-5,
        "{steps:?}"
    );
    assert!((p["span_s"].as_f64().unwrap() - span).abs() < 1e-9);
    assert!((f["duration_s"].as_f64().unwrap() - span).abs() < 1e-9);
    // Missing samples only past 1.5 times the longest step of the pattern.
    let above = p["gap_above_s"].as_f64().unwrap();
    assert!((above / 1.5 - 4.882e-3).abs() < 1e-6, "{above}");
}

#[test]
fn steps_that_are_whole_multiples_of_one_are_a_clock_with_losses() {
    // sample_logging_tagged_and_default_params.ulg (PX4 SITL): 1,362
    // steps of 4 ms and 665 of 8 ms (pyulog): a 250 Hz clock missing a
    // sample at each 8 ms step, not an irregular publisher.
    let log = px4("sample_logging_tagged_and_default_params.ulg");
    let f = info_json(&log);
    assert!(f["clock"].get("pattern").is_none(), "{}", f["clock"]);
    let missing: u64 = f["problems"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|p| p["kind"] == "time_gap")
        .map(|p| p["count"].as_u64().unwrap())
        .sum();
    assert_eq!(missing, 665);
    assert!(!info_text(&log).contains("irregularly"));
}

#[test]
fn a_duty_cycle_is_read_with_its_gaps_and_named() {
    // 25 bursts of 250 samples at 50 Hz, one every 305 s (counted from the
    // file's time column with numpy: burst periods 304.97–305.01 s, bursts
    // 4.97–5.00 s from first to last stamp).
    let text = info_text(&tvac());
    assert!(text.contains("bursts of 5.0 s every 305 s, 25 bursts"), "{text}");
    let f = info_json(&tvac());
    let p = &f["clock"]["pattern"];
    assert_eq!(p["kind"], "bursts", "{p}");
    assert_eq!(p["burst_count"], 25);
    assert!((p["period_s"].as_f64().unwrap() - 304.98).abs() < 0.03, "{p}");
    assert!((p["burst_s"].as_f64().unwrap() - 4.98).abs() < 0.02, "{p}");
    // Every sample kept (the last line is cut and reported), the pauses
    // filled as gaps: 24 of them.
    assert_eq!(
        f["samples"].as_u64().unwrap() - f["channels"][0]["nan_samples"].as_u64().unwrap(),
        6249
    );
    let gaps = f["problems"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|p| p["kind"] == "time_gap")
        .count();
    assert_eq!(gaps, 24);
    // A limit given is the limit: the pattern does not lift it.
    let out = imutherm()
        .args(["info", "--max-grid-factor", "16"])
        .arg(tvac())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(
        stderr_of(&out).contains("more than 16 times its"),
        "{}",
        stderr_of(&out)
    );
}

#[test]
fn the_grid_guard_still_refuses_a_time_column_that_is_plainly_wrong() {
    // 100 Hz for 2,000 rows, with one stamp in the middle written in
    // microseconds instead of seconds: one pause no pattern repeats.
    let dir = tempfile::tempdir().unwrap();
    let mut text = String::from("time[s],gyro_x[rad/s]\n");
    let mut t = 0.0;
    for k in 0..2000 {
        t += if k == 1000 { 5.0e4 } else { 0.01 };
        text.push_str(&format!("{t:.2},0.001\n"));
    }
    let path = dir.path().join("wrong.csv");
    std::fs::write(&path, text).unwrap();
    let out = imutherm().arg("info").arg(&path).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = stderr_of(&out);
    assert!(err.contains("more than 16 times its 2000 samples"), "{err}");
    // Nor do pauses of every length, however many.
    let mut text = String::from("time[s],gyro_x[rad/s]\n");
    let mut t = 0.0;
    for k in 0..2000 {
        t += if k % 200 == 199 {
            30.0 * (1 + k / 200) as f64
        } else {
            0.01
        };
        text.push_str(&format!("{t:.2},0.001\n"));
    }
    std::fs::write(&path, text).unwrap();
    let out = imutherm().arg("info").arg(&path).output().unwrap();
    assert_eq!(out.status.code(), Some(1), "{}", stderr_of(&out));
    assert!(
        stderr_of(&out).contains("more than 16 times"),
        "{}",
        stderr_of(&out)
    );
}
