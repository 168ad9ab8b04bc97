//! `imutherm record` against the simulated chip, in real time.

use std::process::Command as Process;
use std::time::Duration;

use assert_cmd::cargo::CommandCargoExt;

mod support;
use support::{imutherm, json_stdout, replaces_only_with_overwrite};

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
    imutherm()
        .arg("record")
        .args(args)
        .arg("-o")
        .arg(&out)
        .assert()
        .success();
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
fn ten_seconds_at_200_hz_are_2000_samples_with_the_configured_noise() {
    let (_dir, out) = record(&["--device", "sim:white", "--rate", "200", "--duration", "10s"]);
    let r = rows(&out);
    assert!((1999..=2001).contains(&r.len()), "{} samples", r.len());
    // Gyro x: white noise of N = 1.5e-4 rad/√s (the preset), so the ADEV
    // at τ0 = 5 ms is N/√τ0 = 2.12e-3 rad/s, plus the ±250 °/s LSB's
    // rounding, whose variance LSB²/12 adds to the Allan variance at τ0.
    let gx: Vec<f64> = r.iter().map(|row| row[3]).collect();
    // One test over all octave τ at a 95 % family level (Bonferroni: each
    // point at 1 − 0.05/points).
    let curve = |confidence| {
        allan::analyze(
            &gx,
            &allan::Options {
                rate_hz: 200.0,
                confidence,
                ..allan::Options::default()
            },
        )
        .unwrap()
    };
    let curve = curve(1.0 - 0.05 / curve(0.95).points.len() as f64);
    let lsb = std::f64::consts::PI / 180.0 / 131.0;
    let want = ((1.5e-4f64).powi(2) * 200.0 + lsb * lsb / 12.0).sqrt();
    // At every octave τ the white-noise line N/√τ lies in the 95 % interval.
    for p in &curve.points {
        let want = if p.tau == 0.005 {
            want
        } else {
            1.5e-4 / p.tau.sqrt()
        };
        assert!(
            p.dev_lo < want && want < p.dev_hi,
            "τ {} s: {} [{}, {}] vs {want}",
            p.tau,
            p.dev,
            p.dev_lo,
            p.dev_hi
        );
    }
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("# trailer: samples=") && text.contains("stopped_by=duration"));
}

#[test]
fn full_scale_sets_the_quantization_step() {
    let (_dir, out) = record(&[
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
    ]);
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

/// The `counter` signal: sample k reads k LSB on all seven fields. Decodes
/// a row back to k, or `None` for a gap row; panics on a row whose fields
/// disagree (a frame decoded from misaligned bytes).
fn counter_index(row: &[f64]) -> Option<i64> {
    if row[..7].iter().all(|v| v.is_nan()) {
        return None;
    }
    let (a, g) = (9.80665 / 16384.0, std::f64::consts::PI / 180.0 / 131.0);
    let k: Vec<f64> = (0..3)
        .map(|i| row[i] / a)
        .chain((3..6).map(|i| row[i] / g))
        .chain(std::iter::once((row[6] - 21.0) * 333.87))
        .collect();
    let k0 = k[0].round();
    assert!(k.iter().all(|v| (v - k0).abs() < 1e-3), "misaligned frame: {k:?}");
    Some(k0 as i64)
}

#[test]
fn a_recognisable_stream_stays_aligned_and_every_gap_is_sized_to_one_sample() {
    // A chip 1 % fast, a host that stalls for 0.5 s every 6 s (FIFO
    // overflows) and a bus failing 1 % of transfers (part reads resync).
    let (_dir, out) = record(&[
        "--device",
        "sim:counter",
        "--rate",
        "200",
        "--duration",
        "14s",
        "--sim-bus-errors",
        "0.01",
        "--sim-stall-every",
        "6",
        "--sim-clock-ppm",
        "10000",
        "--host-time",
    ]);
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("temp[degC], host_time[s]\n"));
    let r = rows(&out);
    assert_eq!(r.len(), 2800);
    let mut previous: Option<(i64, i64)> = None;
    let (mut gaps, mut worst) = (0, 0i64);
    for (pos, row) in r.iter().enumerate() {
        let Some(k) = counter_index(row) else {
            assert!(row[7].is_nan(), "a gap row has no host time");
            continue;
        };
        // Rows between two samples must number the samples between them
        // (before the first: sample −1 at row −1).
        let (p, pk) = previous.unwrap_or((-1, -1));
        let rows_between = pos as i64 - p - 1;
        let missing = k - pk - 1;
        if missing != 0 || rows_between != 0 {
            gaps += 1;
            worst = worst.max((missing - rows_between).abs());
            assert!(
                (missing - rows_between).abs() <= 1,
                "row {pos}: {missing} samples missing, {rows_between} gap rows"
            );
        }
        assert!(missing >= 0, "row {pos}: sample {k} after {pk}");
        previous = Some((pos as i64, k));
    }
    let trailer = text.lines().find(|l| l.starts_with("# trailer:")).unwrap();
    let field = |key: &str| trailer_field(&text, key);
    assert!(field("overflows") >= 2.0, "{trailer}");
    assert!(
        gaps as f64 >= field("gaps") - 1.0 && gaps >= 2,
        "{gaps} gaps seen; {trailer}"
    );
    // The chip's clock is 1 % fast and the logger says so.
    let measured = field("rate_measured_hz");
    assert!((measured / 202.0 - 1.0).abs() < 2e-3, "{trailer}");
    // Host times: increasing over the file, at the measured rate.
    let host: Vec<f64> = r.iter().map(|row| row[7]).filter(|t| t.is_finite()).collect();
    let span = host.last().unwrap() - host[0];
    assert!((span * 202.0 / 2800.0 - 1.0).abs() < 0.01, "{span} s");
    assert!(
        host.windows(2).all(|w| w[1] > w[0] - 0.003),
        "host time runs backwards"
    );
    eprintln!("{gaps} gaps, worst size error {worst} sample(s); {trailer}");
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
fn a_brown_out_is_reconfigured_and_its_silence_is_a_gap() {
    // The chip loses its registers 2 s in: nothing comes until the logger
    // notices (1 s without a frame) and configures it again.
    let (_dir, out) = record(&[
        "--device",
        "sim:counter",
        "--rate",
        "200",
        "--duration",
        "5s",
        "--sim-brownout-at",
        "2",
    ]);
    let text = std::fs::read_to_string(&out).unwrap();
    assert_eq!(trailer_field(&text, "reconfigurations"), 1.0, "{text}");
    assert_eq!(trailer_field(&text, "gaps"), 1.0);
    assert!(text.contains("the sensor stopped delivering: reconfigured"));
    let r = rows(&out);
    assert_eq!(r.len(), 1000);
    let gap = r.iter().filter(|row| row[0].is_nan()).count();
    // About a second of silence and the poll that notices it.
    assert!((195..=240).contains(&gap), "{gap} gap rows");
    // The chip made no sample while it was down: the stream jumps once, by
    // the few frames its FIFO held when it lost them (one poll's worth).
    let ks: Vec<i64> = r.iter().filter_map(|row| counter_index(row)).collect();
    let jumps: Vec<i64> = ks.windows(2).map(|w| w[1] - w[0]).filter(|&d| d != 1).collect();
    assert!(
        jumps.len() <= 1 && jumps.iter().all(|&d| (2..=12).contains(&d)),
        "{jumps:?}"
    );
}

#[test]
fn a_silent_chip_ends_the_run_at_the_duration_in_host_time() {
    // A chip whose clock has stopped never delivers: the run still ends,
    // at 1.05 × the duration + 2 s, the silence written as a gap.
    let (_dir, out) = record(&[
        "--device",
        "sim:counter",
        "--rate",
        "100",
        "--duration",
        "1s",
        "--sim-clock-ppm=-1000000",
    ]);
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("stopped_by=time_limit"), "{text}");
    assert_eq!(trailer_field(&text, "samples"), 0.0);
    assert_eq!(rows(&out).len(), 100, "the whole second is a gap");
}

#[test]
fn a_rate_the_chip_cannot_make_is_named_and_the_real_one_recorded() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r.txt");
    imutherm()
        .args([
            "record",
            "--device",
            "sim",
            "--rate",
            "300",
            "--duration",
            "0.3s",
            "-o",
        ])
        .arg(&out)
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
        imutherm()
            .args(["record", "--device", device, "--duration", "1", "-o"])
            .arg(dir.path().join("x.txt"))
            .assert()
            .code(status)
            .stderr(predicates::str::contains(says));
    }
}
