//! `imutherm record` against the simulated chip, in real time.

use std::process::Command as Process;
use std::time::Duration;

use assert_cmd::Command;
use assert_cmd::cargo::CommandCargoExt;

fn rows(path: &std::path::Path) -> Vec<Vec<f64>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("mpu_"))
        .map(|l| l.split(", ").map(|v| v.parse::<f64>().unwrap()).collect())
        .collect()
}

#[test]
fn ten_seconds_at_200_hz_are_2000_samples_with_the_configured_noise() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("rec.txt");
    Command::cargo_bin("imutherm")
        .unwrap()
        .args([
            "record",
            "--device",
            "sim:white",
            "--rate",
            "200",
            "--duration",
            "10s",
            "-o",
        ])
        .arg(&out)
        .assert()
        .success();
    let r = rows(&out);
    assert!((1999..=2001).contains(&r.len()), "{} samples", r.len());
    // Gyro x: white noise of N = 1.5e-4 rad/√s (the preset), so the ADEV
    // at τ0 = 5 ms is N/√τ0 = 2.12e-3 rad/s, plus the ±250 °/s quantization.
    let gx: Vec<f64> = r.iter().map(|row| row[3]).collect();
    let curve = allan::analyze(
        &gx,
        &allan::Options {
            rate_hz: 200.0,
            ..allan::Options::default()
        },
    )
    .unwrap();
    let lsb = std::f64::consts::PI / 180.0 / 131.0;
    let want = ((1.5e-4f64).powi(2) * 200.0 + lsb * lsb / 6.0).sqrt();
    let p = &curve.points[0];
    assert!(
        p.dev_lo * 0.97 < want && want < p.dev_hi * 1.03,
        "{} vs {want}",
        p.dev
    );
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("# trailer: samples=") && text.contains("stopped_by=duration"));
}

#[test]
fn full_scale_sets_the_quantization_step() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("fs.txt");
    Command::cargo_bin("imutherm")
        .unwrap()
        .args([
            "record",
            "--device",
            "sim:white",
            "--rate",
            "100",
            "--duration",
            "1s",
            "--gyro-range",
            "2000",
            "--accel-range",
            "16",
            "-o",
        ])
        .arg(&out)
        .assert()
        .success();
    let (g, a) = (std::f64::consts::PI / 180.0 / 16.4, 9.80665 / 2048.0);
    for row in rows(&out) {
        let (kg, ka) = (row[3] / g, row[0] / a);
        assert!(
            (kg - kg.round()).abs() < 1e-6 && (ka - ka.round()).abs() < 1e-6,
            "{row:?}"
        );
    }
}

#[test]
fn sigint_leaves_a_complete_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("int.txt");
    let mut child = Process::cargo_bin("imutherm")
        .unwrap()
        .args(["record", "--device", "sim", "--rate", "500", "-o"])
        .arg(&out)
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(2500));
    let killed = Process::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let status = child.wait().unwrap();
    assert!(status.success(), "{status:?}");
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.ends_with('\n'));
    assert!(text.contains("stopped_by=signal"));
    let n = rows(&out).len();
    assert!(n > 100, "{n} samples");
    // The readers find nothing wrong with it.
    let info = Command::cargo_bin("imutherm")
        .unwrap()
        .args(["info", "--json"])
        .arg(&out)
        .output()
        .unwrap();
    let doc: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
    assert_eq!(doc["files"][0]["samples"], n);
    assert!(doc["files"][0]["problems"].as_array().unwrap().is_empty());
}

#[test]
fn bus_errors_and_overflows_are_counted_and_marked_as_gaps() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("faults.txt");
    Command::cargo_bin("imutherm")
        .unwrap()
        .args([
            "record",
            "--device",
            "sim:white",
            "--rate",
            "200",
            "--duration",
            "4s",
            "--sim-bus-errors",
            "0.01",
            "--sim-stall-every",
            "1.5",
            "-o",
        ])
        .arg(&out)
        .assert()
        .success();
    let text = std::fs::read_to_string(&out).unwrap();
    let trailer = text.lines().find(|l| l.starts_with("# trailer:")).unwrap();
    let field = |k: &str| -> u64 {
        trailer
            .split_whitespace()
            .find_map(|f| f.strip_prefix(&format!("{k}=")))
            .and_then(|v| v.parse().ok())
            .unwrap()
    };
    // Every row accounted for: samples read plus samples marked lost.
    let r = rows(&out);
    assert!((799..=801).contains(&r.len()), "{} rows", r.len());
    assert_eq!(field("samples") + field("gap_samples"), r.len() as u64);
    assert!(field("overflows") >= 1 && field("gap_samples") > 0, "{trailer}");
    assert!(field("bus_errors") >= 1, "{trailer}");
    let gaps = r.iter().filter(|row| row.iter().all(|v| v.is_nan())).count() as u64;
    assert_eq!(gaps, field("gap_samples"));
    // No half-read frame: a row is all numbers or all gap.
    assert!(
        r.iter()
            .all(|row| row.iter().all(|v| v.is_nan()) || row.iter().all(|v| v.is_finite()))
    );
}

#[test]
fn a_missing_bus_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    for (device, says) in [
        (
            "i2c:/dev/i2c-imutherm-none@0x68",
            "opening /dev/i2c-imutherm-none",
        ),
        (
            "spi:/dev/spidev-imutherm-none",
            "opening /dev/spidev-imutherm-none",
        ),
        ("usb:0", "expected sim[:PRESET], i2c:"),
    ] {
        Command::cargo_bin("imutherm")
            .unwrap()
            .args(["record", "--device", device, "--duration", "1", "-o"])
            .arg(dir.path().join("x.txt"))
            .assert()
            .code(1)
            .stderr(predicates::str::contains(says));
    }
}
