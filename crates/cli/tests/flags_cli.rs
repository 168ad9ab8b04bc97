//! Every flag value is checked when the command line is parsed: a bad one is
//! a usage error (exit status 2) naming the flag and what it takes, before
//! any file is read. The input named here does not exist: a value that
//! passed would end in exit status 1 for the missing file instead.

use predicates::prelude::*;

mod support;
use support::{Refused, Simulation, cli, imutherm, writing};

const MISSING: &str = "/nonexistent/imutherm-flags.txt";

/// (arguments, the flag the message must name, words of what it takes).
const BAD: &[(&[&str], &str, &str)] = &[
    (
        &["adev", MISSING, "--stat", "fastdev"],
        "--stat",
        "unknown statistic",
    ),
    (&["adev", MISSING, "--taus", "octaves"], "--taus", "comma list"),
    (&["adev", MISSING, "--taus", "1,0,10"], "--taus", "positive"),
    (&["adev", MISSING, "--taus", "1,inf"], "--taus", "positive"),
    (
        &["adev", MISSING, "--data-type", "voltage"],
        "--data-type",
        "freq",
    ),
    (
        &["adev", MISSING, "--confidence", "1"],
        "--confidence",
        "exclusive",
    ),
    (
        &["adev", MISSING, "--confidence", "0"],
        "--confidence",
        "exclusive",
    ),
    (
        &["adev", MISSING, "--confidence", "100"],
        "--confidence",
        "exclusive",
    ),
    (
        &["adev", MISSING, "--confidence", "nan"],
        "--confidence",
        "exclusive",
    ),
    (&["adev", MISSING, "--rate", "0"], "--rate", "positive"),
    (&["adev", MISSING, "--rate=-inf"], "--rate", "positive"),
    (&["adev", MISSING, "--unit", "gyro_x"], "--unit", "COLUMN=UNIT"),
    (
        &["adev", MISSING, "--unit", "gyro_x=furlong"],
        "--unit",
        "unknown unit",
    ),
    (
        &["adev", MISSING, "--time-unit", "fortnight"],
        "--time-unit",
        "s, ms, us or ns",
    ),
    (&["noise", MISSING, "--units", "imperial"], "--units", "datasheet"),
    (
        &["noise", MISSING, "--confidence", "1"],
        "--confidence",
        "exclusive",
    ),
    (
        &["report", MISSING, "--out", "/nonexistent/r", "--format", "pdf"],
        "--format",
        "png",
    ),
    (
        &["demo", "--out", "/nonexistent/d", "--format", "gif"],
        "--format",
        "svg",
    ),
    (&["thermal", MISSING, "--by", "pressure"], "--by", "temperature"),
    (
        &["thermal", MISSING, "--bin-width", "0"],
        "--bin-width",
        "positive",
    ),
    (
        &["thermal", MISSING, "--bin-width", "nan"],
        "--bin-width",
        "positive",
    ),
    (&["thermal", MISSING, "--window=-600"], "--window", "positive"),
    (&["thermal", MISSING, "--step", "0"], "--step", "positive"),
    (
        &["thermal", MISSING, "--confidence", "250"],
        "--confidence",
        "exclusive",
    ),
    (
        &[
            "tcal",
            "fit",
            MISSING,
            "-o",
            "/nonexistent/m.json",
            "--order",
            "10",
        ],
        "--order",
        "0 to 9",
    ),
    (
        &["tcal", "fit", MISSING, "-o", "/nonexistent/m.json", "--order=-1"],
        "--order",
        "0 to 9",
    ),
    (
        &[
            "tcal",
            "fit",
            MISSING,
            "-o",
            "/nonexistent/m.json",
            "--tref",
            "nan",
        ],
        "--tref",
        "finite",
    ),
    (
        &[
            "tcal",
            "fit",
            MISSING,
            "-o",
            "/nonexistent/m.json",
            "--bin-width",
            "0",
        ],
        "--bin-width",
        "positive",
    ),
    (
        &["tcal", "eval", MISSING, MISSING, "--export", "betaflight"],
        "--export",
        "ardupilot",
    ),
    (&["simulate", "-o", MISSING, "--rate", "0"], "--rate", "positive"),
    (
        &["simulate", "-o", MISSING, "--duration", "ten minutes"],
        "--duration",
        "not s, m, h or d",
    ),
    (
        &["simulate", "-o", MISSING, "--duration=-5s"],
        "--duration",
        "positive",
    ),
    (
        &["record", "-o", MISSING, "--device", "usb:0"],
        "--device",
        "expected sim[:PRESET]",
    ),
    (
        &["record", "-o", MISSING, "--device", "sim:nope"],
        "--device",
        "presets are",
    ),
    (
        &["record", "-o", MISSING, "--device", "sim", "--rate", "5000"],
        "--rate",
        "1000/(1 + n)",
    ),
    (
        &["record", "-o", MISSING, "--device", "sim", "--rate", "nan"],
        "--rate",
        "1000/(1 + n)",
    ),
    (
        &["record", "-o", MISSING, "--device", "sim", "--dlpf", "0"],
        "--dlpf",
        "184, 92",
    ),
    (
        &["record", "-o", MISSING, "--device", "sim", "--dlpf", "100"],
        "--dlpf",
        "184, 92",
    ),
    (
        &["record", "-o", MISSING, "--device", "sim", "--accel-range", "3"],
        "--accel-range",
        "2, 4, 8 or 16",
    ),
    (
        &[
            "record",
            "-o",
            MISSING,
            "--device",
            "sim",
            "--gyro-range",
            "250.5",
        ],
        "--gyro-range",
        "250, 500",
    ),
    (
        &["record", "-o", MISSING, "--device", "sim", "--duration", "soon"],
        "--duration",
        "duration 'soon'",
    ),
    (
        &[
            "record",
            "-o",
            MISSING,
            "--device",
            "sim",
            "--sim-bus-errors",
            "1",
        ],
        "--sim-bus-errors",
        "fraction",
    ),
    (
        &[
            "record",
            "-o",
            MISSING,
            "--device",
            "sim",
            "--sim-bus-errors=-0.1",
        ],
        "--sim-bus-errors",
        "fraction",
    ),
    (
        &[
            "record",
            "-o",
            MISSING,
            "--device",
            "sim",
            "--sim-stall-every",
            "0",
        ],
        "--sim-stall-every",
        "positive",
    ),
    (
        &[
            "record",
            "-o",
            MISSING,
            "--device",
            "sim",
            "--sim-clock-ppm",
            "-2000000",
        ],
        "--sim-clock-ppm",
        "backwards",
    ),
];

#[test]
fn a_dynamic_adev_window_that_is_not_a_duration_or_longer_than_the_run_is_a_usage_error() {
    let dir = tempfile::tempdir().unwrap();
    for (flag, value) in [
        ("--dyn-window", "30 weeks"),
        ("--dyn-step", "90 parsecs"),
        ("--dyn-window", "0"),
    ] {
        cli!["report", MISSING, "--out", dir.path().join("rep"), flag, value]
            .refused(2, format!("for '{flag} "));
    }
    // Longer than the quick demo's 1 h cooling run: refused before any
    // simulation.
    let demo = dir.path().join("demo");
    cli!["demo", "--quick", "--dyn-window", "2h", "--out", &demo].refused(
        2,
        "--dyn-window 7200 s is longer than the demo's cooling run (3600 s)",
    );
    assert!(!demo.join("cooling_100_to_20C.txt").exists());
    // Longer than a report's run whose temperature changes, named.
    let cooling = Simulation::new()
        .profile("cooling:90:25:600")
        .duration("600")
        .rate("5")
        .write(dir.path(), "cooling.txt");
    cli![
        "report",
        &cooling,
        "--dyn-window",
        "15min",
        "--out",
        dir.path().join("rep")
    ]
    .assert()
    .code(2)
    .stderr(
        predicate::str::contains("--dyn-window 900 s is longer than")
            .and(predicate::str::contains("cooling.txt (600.0 s)")),
    );
}

#[test]
fn every_bad_flag_value_exits_2_naming_the_flag() {
    for (args, flag, says) in BAD {
        let out = imutherm().args(*args).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.contains(&format!("for '{flag} ")),
            "{args:?} does not name {flag}: {err}"
        );
        assert!(err.contains(says), "{args:?} does not say '{says}': {err}");
    }
}

#[test]
fn the_spellings_in_use_keep_working() {
    for args in [
        &["adev", MISSING, "--confidence", "0.683"][..],
        &["adev", MISSING, "--confidence", "68.3"],
        &["adev", MISSING, "--confidence", "95"],
        &[
            "adev",
            MISSING,
            "--stat",
            "OADEV",
            "--taus",
            "1,10,100",
            "--data-type",
            "frequency",
        ],
        &[
            "adev",
            MISSING,
            "-s",
            "theo1",
            "-t",
            "many",
            "--data-type",
            "phase",
        ],
        &[
            "adev",
            MISSING,
            "--unit",
            "gyro_x=deg/s",
            "--time-unit",
            "ns",
            "--rate",
            "200",
        ],
        &["noise", MISSING, "--units", "datasheet", "--confidence", "0.95"],
        &["thermal", MISSING, "--by", "temp", "--bin-width", "2"],
        &[
            "thermal", MISSING, "--by", "time", "--window", "300", "--step", "150",
        ],
        &[
            "tcal",
            "fit",
            MISSING,
            "-o",
            "/nonexistent/m.json",
            "--order",
            "auto",
            "--tref",
            "35",
        ],
        &[
            "tcal",
            "fit",
            MISSING,
            "-o",
            "/nonexistent/m.json",
            "--order",
            "3",
            "--bin-width",
            "0.5",
        ],
        &["tcal", "eval", MISSING, MISSING, "--export", "PX4"],
        &["report", MISSING, "--out", "/nonexistent/r", "--format", "png"],
    ] {
        imutherm().args(args).assert().code(1);
    }
    // Durations and rates of simulate, read back from the configuration it prints.
    for (duration, seconds) in [
        ("3600", 3600.0),
        ("90m", 5400.0),
        ("2h", 7200.0),
        ("1.5h", 5400.0),
    ] {
        let out = cli![
            "simulate",
            "--print-config",
            "--rate",
            "50",
            "--duration",
            duration
        ]
        .output()
        .unwrap();
        assert!(out.status.success(), "{duration}");
        let cfg: toml::Table = String::from_utf8(out.stdout).unwrap().parse().unwrap();
        assert_eq!(cfg["duration_s"].as_float(), Some(seconds), "{duration}");
        assert_eq!(cfg["rate_hz"].as_float(), Some(50.0));
    }
}

#[test]
fn the_accepted_values_are_listed_in_help() {
    imutherm().args(["adev", "--help"]).assert().success().stdout(
        predicate::str::contains("[possible values: adev, oadev, mdev")
            .and(predicate::str::contains("[possible values: freq, phase]")),
    );
    cli!["record", "--help"]
        .assert()
        .success()
        .stdout(predicate::str::contains(
            "[possible values: 184, 92, 41, 20, 10, 5]",
        ));
    cli!["thermal", "--help"]
        .assert()
        .success()
        .stdout(predicate::str::contains("[possible values: temperature, time]"));
}

#[test]
fn a_simulation_too_large_is_refused_at_once_unless_allowed() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("huge.txt");
    let started = std::time::Instant::now();
    cli!["simulate", "--rate", "1e9", "-o", &out]
        .assert()
        .code(2)
        .stderr(predicate::str::contains("2.520e13 values").and(predicate::str::contains("--allow-large")));
    assert!(started.elapsed().as_secs_f64() < 5.0);
    assert!(!out.exists() && std::fs::read_dir(dir.path()).unwrap().count() == 0);
    // Just past the limit (1e8 values = 14 285 715 samples × 7 columns):
    // refused; just below, or with --allow-large, the size check lets it
    // through (and the missing folder then stops it: exit 1).
    cli!["simulate", "--duration", "142858", "--rate", "100", "-o", &out]
        .assert()
        .code(2);
    cli![
        "simulate",
        "--duration",
        "142857",
        "--rate",
        "100",
        "-o",
        "/nonexistent/dir/x.txt"
    ]
    .assert()
    .code(1);
    cli![
        "simulate",
        "--rate",
        "1e9",
        "--allow-large",
        "-o",
        "/nonexistent/dir/x.txt"
    ]
    .refused(1, "/nonexistent/dir");
}

#[test]
fn absurd_slicings_of_a_recording_are_refused_before_the_analysis() {
    let dir = tempfile::tempdir().unwrap();
    let run = Simulation::new()
        .args(&["--preset", "white"])
        .profile("ramp:20:80:600")
        .duration("600")
        .rate("20")
        .seed("3")
        .write(dir.path(), "ramp.txt");
    for (args, says) in [
        (&["--bin-width", "1e-6"][..], "at most 1000 are analysed"),
        (
            &["--by", "time", "--window", "60", "--step", "1e-6"],
            "shorter than one sample",
        ),
        (
            &["--by", "time", "--window", "10", "--step", "0.05"],
            "at most 10000 are analysed",
        ),
    ] {
        let started = std::time::Instant::now();
        imutherm()
            .arg("thermal")
            .arg(&run)
            .args(args)
            .assert()
            .code(1)
            .stderr(predicate::str::contains(says));
        // Refused, not attempted: the whole run, reading included, is quick.
        assert!(started.elapsed().as_secs_f64() < 5.0, "{args:?}");
    }
    let model = dir.path().join("m.json");
    let started = std::time::Instant::now();
    cli!["tcal", "fit", "--bin-width", "1e-4", &run, "-o", &model].refused(1, "at most 1000 are fitted");
    assert!(started.elapsed().as_secs_f64() < 5.0);
    assert!(!model.exists());
}

#[test]
fn flags_that_cannot_go_together_are_usage_errors() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.txt");
    for (args, says) in [
        (
            &[
                "--device",
                "i2c:/dev/i2c-imutherm-none",
                "--sim-bus-errors",
                "0.01",
            ][..],
            "for --device sim only",
        ),
        (
            &["--device", "sim", "--rate", "10", "--duration", "0.01"],
            "less than one sample",
        ),
    ] {
        writing("record", args, &out).refused(2, says);
    }
    assert!(!out.exists());
}
