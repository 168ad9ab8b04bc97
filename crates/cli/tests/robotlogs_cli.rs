//! Robot logs through the command line: `info` on PX4's sample logs, the
//! stream choice, and `noise` on simulated bags against the truth they
//! were written with and against the same samples as a text log.

mod support;

use std::path::{Path, PathBuf};

use serde_json::Value;
use support::{imutherm, json_stdout, stderr_of};

fn fixture(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../robotlogs/tests/fixtures")
        .join(p)
}

#[test]
fn info_on_px4_sample_logs_lists_streams_rates_samples_and_gaps() {
    // pyulog's reading of the same logs (make_fixtures.py px4).
    let expected: Value =
        serde_json::from_str(&std::fs::read_to_string(fixture("px4/expected.json")).unwrap()).unwrap();
    for (file, topics) in expected.as_object().unwrap() {
        let doc = json_stdout(
            imutherm()
                .args(["info", "--json"])
                .arg(fixture(&format!("px4/{file}"))),
        );
        let f = &doc["files"][0];
        assert_eq!(f["format"], "PX4 ULog");
        let streams = f["streams"].as_array().unwrap();
        let combined = streams.iter().find(|s| s["name"] == "sensor_combined").unwrap();
        let e = &topics["sensor_combined"];
        assert_eq!(combined["messages"], e["messages"], "{file}");
        assert_eq!(combined["selected"], true, "{file}");
        // The log's mean rate: messages over the span of their timestamps.
        let span_s =
            (e["last_timestamp_us"].as_f64().unwrap() - e["first_timestamp_us"].as_f64().unwrap()) * 1e-6;
        let mean = (e["messages"].as_f64().unwrap() - 1.0) / span_s;
        assert!(
            (combined["rate_hz"].as_f64().unwrap() / mean - 1.0).abs() < 1e-9,
            "{file}"
        );
        // Every message is a sample: the slots not filled are the gaps.
        let nan = f["channels"][3]["nan_samples"].as_u64().unwrap();
        assert_eq!(
            f["samples"].as_u64().unwrap() - nan,
            e["messages"].as_u64().unwrap(),
            "{file}"
        );
        let gap_samples: u64 = f["problems"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|p| p["kind"] == "time_gap")
            .map(|p| {
                assert!(p["message"].as_str().unwrap().contains("t = "), "{p}");
                p["count"].as_u64().unwrap()
            })
            .sum();
        assert_eq!(f["problems_unlisted"], 0, "{file}");
        assert_eq!(gap_samples, nan, "{file}");
        for (topic, t) in topics.as_object().unwrap() {
            if topic.starts_with("sensor_gyro") {
                let s = streams.iter().find(|s| s["name"] == topic.as_str()).unwrap();
                assert_eq!(s["messages"], t["messages"]);
                assert_eq!(s["instance"], topic[12..].parse::<u64>().unwrap());
            }
        }
    }
}

#[test]
fn several_imu_topics_fail_with_their_list_and_a_topic_chooses() {
    let out = imutherm()
        .args(["noise"])
        .arg(fixture("ros/two_imus.mcap"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = stderr_of(&out);
    assert!(
        err.contains("--topic") && err.contains("/imu0/data") && err.contains("200 Hz"),
        "{err}"
    );
    assert!(err.contains("/imu1/data") && err.contains("100 Hz"), "{err}");
    let doc = json_stdout(
        imutherm()
            .args(["adev", "--json", "--topic", "/imu1/data"])
            .arg(fixture("ros/two_imus.mcap")),
    );
    assert!((doc["rate_hz"].as_f64().unwrap() - 100.0).abs() < 1e-3, "{doc}");
}

#[test]
fn stream_flags_on_a_text_log_are_an_error() {
    let (_d, p) = support::file("g.csv", "gyro_x\n0.1\n0.2\n0.3\n");
    let out = imutherm()
        .args(["info", "--instance", "1"])
        .arg(&p)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr_of(&out).contains("--instance"), "{}", stderr_of(&out));
}

/// N of every axis, by name, from `imutherm noise --json`.
fn noise_n(file: &Path) -> Vec<(String, f64)> {
    let doc = json_stdout(imutherm().args(["noise", "--json"]).arg(file));
    doc["files"][0]["channels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            let n = c["chosen"]
                .as_array()
                .unwrap()
                .iter()
                .find(|t| t["term"] == "N")
                .unwrap();
            (
                c["name"].as_str().unwrap().to_string(),
                n["si"]["value"].as_f64().unwrap(),
            )
        })
        .collect()
}

#[test]
fn every_storage_of_the_same_samples_gives_the_same_noise() {
    let reference = noise_n(&fixture("ros/imu_zstd.mcap"));
    assert_eq!(reference.len(), 6);
    for f in [
        "ros/bag_sqlite3",
        "ros/bag_mcap",
        "ros/imu_bz2.bag",
        "ros/imu_lz4_big_endian.mcap",
    ] {
        assert_eq!(noise_n(&fixture(f)), reference, "{f}");
    }
}

/// The large fixtures, generated by `make_fixtures.py large` (in `.ci/run`).
fn large_fixtures() -> Option<PathBuf> {
    let dir = std::env::var_os("IMUTHERM_ROBOTLOG_FIXTURES").map_or_else(
        || Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target/robotlog-fixtures"),
        PathBuf::from,
    );
    if dir.join("truth.json").is_file() {
        return Some(dir);
    }
    if std::env::var("IMUTHERM_REQUIRE_FIXTURES").as_deref() == Ok("1") {
        panic!(
            "IMUTHERM_REQUIRE_FIXTURES=1 but {} holds no large fixtures",
            dir.display()
        );
    }
    eprintln!(
        "skipped: the large robot-log fixtures are not in {} \
         (make_fixtures.py large DIR; IMUTHERM_ROBOTLOG_FIXTURES=DIR)",
        dir.display()
    );
    None
}

/// N of the 10-minute text log, computed once for the tests of the bags.
fn text_noise(dir: &Path) -> &'static [(String, f64)] {
    static TEXT: std::sync::OnceLock<Vec<(String, f64)>> = std::sync::OnceLock::new();
    TEXT.get_or_init(|| noise_n(&dir.join("static_10min.csv")))
}

/// `noise` on a 10-minute bag: N within 5 % of the truth on every axis, and
/// the same numbers as the same samples written as text.
fn ten_minute_bag(name: &str) {
    let Some(dir) = large_fixtures() else { return };
    let truth: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("truth.json")).unwrap()).unwrap();
    let bag = noise_n(&dir.join(name));
    assert_eq!(bag, text_noise(&dir), "{name}");
    for (channel, n) in &bag {
        let k = ["x", "y", "z"].iter().position(|a| channel.ends_with(a)).unwrap();
        let key = if channel.starts_with("gyro") {
            "gyro_n"
        } else {
            "accel_n"
        };
        let t = truth[key][k].as_f64().unwrap();
        assert!((n / t - 1.0).abs() < 0.05, "{name} {channel}: N {n} against {t}");
    }
}

#[test]
fn noise_on_a_ten_minute_mcap_bag_is_the_truth_and_the_text_log() {
    ten_minute_bag("static_10min.mcap");
}

#[test]
fn noise_on_a_ten_minute_sqlite3_bag_is_the_truth_and_the_text_log() {
    ten_minute_bag("static_10min_sqlite3");
}

#[test]
fn noise_on_a_ten_minute_ros1_bag_is_the_truth_and_the_text_log() {
    ten_minute_bag("static_10min.bag");
}
