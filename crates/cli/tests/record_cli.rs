//! `imutherm record` against the simulated chip, in real time: the end-to-end
//! runs (a signal, faults read back by `info`, the file's bytes) and the
//! flags. What the recorder does under each fault is tested in simulated
//! time in `crates/logger/tests/`.

use std::process::Command as Process;
use std::time::Duration;

use assert_cmd::cargo::CommandCargoExt;

mod support;
use support::{Refused, cli, imutherm, json_stdout, replaces_only_with_overwrite, writing};

fn rows(path: &std::path::Path) -> Vec<Vec<f64>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("mpu_"))
        .map(|l| l.split(", ").map(|v| v.parse::<f64>().unwrap()).collect())
        .collect()
}

/// Runs `imutherm record ARGS -o FILE` to success in a fresh directory;
/// returns the directory (kept alive) and the file.
fn record(args: &[&str]) -> (tempfile::TempDir, std::path::PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("rec.txt");
    writing("record", args, &out).assert().success();
    (dir, out)
}

/// `imutherm info --json FILE`.
fn info_json(file: &std::path::Path) -> serde_json::Value {
    json_stdout(imutherm().args(["info", "--json"]).arg(file))
}

/// A number from the file's `# trailer:` line.
fn trailer_field(text: &str, key: &str) -> f64 {
    let trailer = text.lines().find(|l| l.starts_with("# trailer:")).unwrap();
    trailer
        .split_whitespace()
        .find_map(|f| f.strip_prefix(&format!("{key}=")))
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no number {key} in {trailer}"))
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
    let doc = info_json(&out);
    assert_eq!(doc["files"][0]["samples"], n);
    assert!(doc["files"][0]["problems"].as_array().unwrap().is_empty());
}

#[test]
fn bus_errors_and_overflows_are_counted_and_marked_as_gaps() {
    let (_dir, out) = record(&[
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
    ]);
    let text = std::fs::read_to_string(&out).unwrap();
    let trailer = text.lines().find(|l| l.starts_with("# trailer:")).unwrap();
    let field = |k: &str| trailer_field(&text, k) as u64;
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
    // Each gap is announced with its size.
    let announced: u64 = text
        .lines()
        .filter_map(|l| l.strip_prefix("# gap: "))
        .map(|l| l.split(' ').next().unwrap().parse::<u64>().unwrap())
        .sum();
    assert_eq!(announced, field("gap_samples"));
    // `info` shows what the logger counted, and lists each gap once.
    let doc = info_json(&out);
    let f = &doc["files"][0];
    assert_eq!(f["logger"]["gap_samples"], field("gap_samples"));
    assert_eq!(f["logger"]["bus_errors"], field("bus_errors"));
    let runs: Vec<&serde_json::Value> = f["problems"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|p| p["kind"] == "nan")
        .collect();
    assert!(!runs.is_empty() && runs.len() as u64 <= field("gaps"), "{runs:?}");
    assert!(runs.iter().all(|p| p["channel"].is_null()), "{runs:?}");
}

#[test]
fn an_existing_recording_is_never_overwritten_unasked() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("precious.txt");
    std::fs::write(&out, "ten hours of data\n").unwrap();
    replaces_only_with_overwrite(
        &["record", "--device", "sim", "--duration", "0.1s", "-o"],
        &out,
        &["already exists (18 bytes)"],
    );
    assert!(
        std::fs::read_to_string(&out)
            .unwrap()
            .contains("# trailer: samples=20 ")
    );
}

#[test]
fn a_rate_the_chip_cannot_make_is_named_and_the_real_one_recorded() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r.txt");
    let args = ["--device", "sim", "--rate", "300", "--duration", "0.3s"];
    writing("record", &args, &out)
        .assert()
        .success()
        .stderr(predicates::str::contains(
            "recording at 333.333 Hz (SMPLRT_DIV 2)",
        ));
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("# sample_rate_hz: 333.3333333333333\n"), "{text}");
    assert_eq!(rows(&out).len(), 100);
}

#[test]
fn a_missing_bus_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    // A bus that is not there is found when opened (exit 1); a device the
    // flag cannot name is a usage error (exit 2).
    for (device, status, says) in [
        (
            "i2c:/dev/i2c-imutherm-none@0x68",
            1,
            "opening /dev/i2c-imutherm-none",
        ),
        (
            "spi:/dev/spidev-imutherm-none",
            1,
            "opening /dev/spidev-imutherm-none",
        ),
        ("usb:0", 2, "expected sim[:PRESET], i2c:"),
        (
            "i2c:/dev/i2c-1@0x70",
            2,
            "answers at 0x68 (AD0 low) or 0x69 (AD0 high), not 0x70",
        ),
        ("i2c:/dev/i2c-1@68h", 2, "'68h' is not an address like 0x68"),
    ] {
        cli![
            "record",
            "--device",
            device,
            "--duration",
            "1",
            "-o",
            dir.path().join("x.txt")
        ]
        .refused(status, says);
    }
}

/// Masks what depends on the moment of the run: the start time and the
/// elapsed host time.
fn without_times(text: &str) -> String {
    text.lines()
        .map(|l| {
            if l.starts_with("# start_time: ") {
                "# start_time: …".to_string()
            } else if l.starts_with("# trailer: ") {
                l.split(' ')
                    .map(|f| {
                        if f.starts_with("elapsed_s=") {
                            "elapsed_s=…"
                        } else {
                            f
                        }
                    })
                    .collect::<Vec<_>>()
                    .join(" ")
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn the_file_is_byte_for_byte_what_the_recorder_wrote_before_it_became_a_library() {
    // tests/data/record_sim_counter_200hz.txt: written by `imutherm record
    // --device sim:counter --rate 200 --duration 0.5s` at commit a7dab85,
    // when the loop was part of the binary.
    let want = include_str!("data/record_sim_counter_200hz.txt");
    let (_dir, out) = record(&["--device", "sim:counter", "--rate", "200", "--duration", "0.5s"]);
    let got = std::fs::read_to_string(&out).unwrap();
    assert_eq!(without_times(&got), without_times(want));
    assert!(got.ends_with('\n') && want.ends_with('\n'));
}
