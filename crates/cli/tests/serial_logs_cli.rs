//! Text captured from a serial port, as people capture it: two BMI270 logs
//! (MIT, tests/data/bmi270/LICENSE) written through PuTTY by an STM32H7's
//! firmware, `printf("%2f,%.3f,%.3f,%.3f,%.2f,%.2f,%.2f\r\n", temperature,
//! accel x, y, z, gyro x, y, z)`: °C, the accelerometer printed at 16384
//! LSB/g while the sensor ran at ±8 g (4096 LSB/g, so its values read ×4
//! too small, as the source's own analysis multiplies them), the gyro in
//! °/s. Each file opens with PuTTY's banner line; the hot one's first row
//! was cut where the capture began; both hold a line garbled on the wire.

use std::path::PathBuf;

mod support;
use support::{Refused, imutherm, json_stdout, problem_lines};

fn log(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/bmi270")
        .join(name)
}

#[test]
fn a_garbled_line_is_refused_with_the_flag_that_reads_past_it() {
    imutherm()
        .arg("info")
        .arg(log("cold.csv"))
        .refused(1, "cold.csv:9: column 6: cannot read '-0.3-0.31' as a number")
        .stderr(predicates::str::contains("--skip-bad-lines"));
}

#[test]
fn the_cold_log_reads_with_one_flag_its_banner_skipped_and_reported() {
    let doc = json_stdout(
        imutherm()
            .args(["info", "--json", "--skip-bad-lines"])
            .arg(log("cold.csv")),
    );
    let f = &doc["files"][0];
    // 3,258 lines: the banner, 3,256 rows, one of them garbled (a gap),
    // and the capture's last line, cut where it stopped.
    assert_eq!(f["samples"], 3256);
    assert_eq!(f["channels"].as_array().unwrap().len(), 7);
    assert_eq!(
        problem_lines(f),
        [
            ("preamble".to_string(), 1),
            ("bad_line".to_string(), 9),
            ("truncated_last_line".to_string(), 3258)
        ]
    );
    let banner = &f["problems"][0]["message"];
    assert!(
        banner.as_str().unwrap().contains("PuTTY log 2026.05.08 15:02:51"),
        "{banner}"
    );
}

#[test]
fn the_hot_log_reads_past_its_banner_and_its_cut_first_row() {
    let doc = json_stdout(
        imutherm()
            .args(["info", "--json", "--skip-bad-lines"])
            .arg(log("hot.csv")),
    );
    let f = &doc["files"][0];
    // 6,537 lines: the banner, a first row of 6 fields where the rows
    // have 7, 6,533 rows, one of 8 fields (two rows run together) and a
    // last line cut where the capture stopped.
    assert_eq!(f["samples"], 6534);
    assert_eq!(f["channels"].as_array().unwrap().len(), 7);
    assert_eq!(
        problem_lines(f),
        [
            ("preamble".to_string(), 1),
            ("cut_first_row".to_string(), 2),
            ("bad_line".to_string(), 13),
            ("truncated_last_line".to_string(), 6537)
        ]
    );
}

#[test]
fn scale_corrects_the_accelerometers_sensitivity_and_says_so() {
    // The hot run lay with x up: ×4 makes its x axis 1 g.
    let doc = json_stdout(
        imutherm()
            .args([
                "info",
                "--json",
                "--skip-bad-lines",
                "--unit",
                "col2=g",
                "--scale",
                "col2=4",
            ])
            .arg(log("hot.csv")),
    );
    let f = &doc["files"][0];
    // An accelerometer now (`col2` reads as axis 2 of its quantity).
    let x = &f["channels"][1];
    assert_eq!(x["name"], "accel_y");
    let g = x["mean"].as_f64().unwrap() / 9.80665;
    assert!((g - 1.0).abs() < 0.02, "{g} g");
    let notes = f["notes"].to_string();
    assert!(notes.contains("multiplied by 4 (--scale col2=4)"), "{notes}");
    imutherm()
        .args(["info", "--scale", "col9=4"])
        .arg(log("hot.csv"))
        .refused(1, "no column 'col9 (named by --scale)'");
    imutherm()
        .args(["info", "--scale", "col2=0"])
        .arg(log("hot.csv"))
        .refused(2, "not a finite number other than 0");
}
