//! `imutherm simulate` end to end.

use predicates::prelude::*;

mod support;
use support::{Refused, Simulation, cli, imutherm, json_stdout, scratch_files, succeed, writing};

#[test]
fn writes_a_log_with_its_truth_that_reads_back() {
    let dir = tempfile::tempdir().unwrap();
    let a = dir.path().join("a.txt");
    let b = dir.path().join("b.txt");
    for p in [&a, &b] {
        Simulation::new()
            .duration("20s")
            .rate("50")
            .seed("7")
            .profile("cooling:100:20:600")
            .command(p)
            .assert()
            .success()
            .stderr(predicate::str::contains("1000 samples"));
    }
    // Same seed, same bytes.
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    assert_eq!(
        scratch_files(dir.path()),
        Vec::<String>::new(),
        "scratch files left beside a.txt"
    );
    let doc = json_stdout(imutherm().args(["info", "--json"]).arg(&a));
    let f = &doc["files"][0];
    assert_eq!(f["format"], "imutherm log");
    assert_eq!(f["samples"], 1000);
    assert_eq!(f["rate_hz"], 50.0);
    assert_eq!(f["device"], "imusim:mpu9250-thesis");
    // Cooling from 100 °C: the sensor starts there.
    assert!(f["temperature_c"]["max"].as_f64().unwrap() > 99.0);
    let text = std::fs::read_to_string(&a).unwrap();
    assert!(text.contains("# true.gyro_x.n: "), "the truth is in the metadata");
    assert!(text.contains("# true.profile: cooling 100 °C → 20 °C"));
}

#[test]
fn print_config_round_trips_through_config() {
    let dir = tempfile::tempdir().unwrap();
    let out = succeed(imutherm().args(["simulate", "--preset", "white", "--print-config"]));
    let cfg = dir.path().join("white.toml");
    std::fs::write(&cfg, &out.stdout).unwrap();
    let log = dir.path().join("w.txt");
    cli!["simulate", "--duration", "5", "--config", &cfg, "-o", &log]
        .assert()
        .success();
    assert!(
        std::fs::read_to_string(&log)
            .unwrap()
            .contains("# true.gyro_x.n: 0.00015")
    );
}

#[test]
fn bad_configurations_exit_1_with_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.txt");
    cli!["simulate", "--preset", "mpu6050-dream", "-o", &out].refused(1, "unknown preset 'mpu6050-dream'");
    cli!["simulate", "--rate", "0", "-o", &out].refused(2, "'--rate <HZ>': expected a positive number");
    cli!["simulate", "--duration", "ten minutes", "-o", &out].refused(2, "duration 'ten minutes'");
    let printed = cli!["simulate", "--preset", "white", "--print-config"]
        .output()
        .unwrap();
    let text = String::from_utf8(printed.stdout)
        .unwrap()
        .replacen("n = 0.00015", "n = -0.00015", 1);
    let cfg = dir.path().join("bad.toml");
    std::fs::write(&cfg, text).unwrap();
    cli!["simulate", "--config", &cfg, "-o", &out]
        .assert()
        .code(1)
        .stderr(predicate::str::contains("gyro.terms[0].n = -0.00015").and(predicate::str::contains("≥ 0")));
    assert!(!out.exists());
}

#[test]
fn a_profile_file_beside_the_configuration() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("chamber.csv"), "time_s, temp_C\n0, 60\n10, 40\n").unwrap();
    let printed = cli!["simulate", "--preset", "white", "--print-config"]
        .output()
        .unwrap();
    let text = String::from_utf8(printed.stdout).unwrap();
    // Replace the preset's [profile] table with a file profile.
    let start = text.find("[profile]").unwrap();
    let end = start + text[start..].find("\n\n").unwrap_or(text.len() - start);
    let text = format!(
        "{}[profile]\nkind = \"file\"\npath = \"chamber.csv\"{}",
        &text[..start],
        &text[end..]
    );
    let cfg = dir.path().join("run.toml");
    std::fs::write(&cfg, text).unwrap();
    let log = dir.path().join("run.txt");
    // Run from elsewhere: the profile is found beside the configuration.
    imutherm()
        .current_dir(std::env::temp_dir())
        .args(["simulate", "--duration", "10", "--rate", "10", "--config"])
        .arg(&cfg)
        .arg("-o")
        .arg(&log)
        .assert()
        .success();
    let doc = json_stdout(imutherm().args(["info", "--json"]).arg(&log));
    let t = &doc["files"][0]["temperature_c"];
    assert!((t["max"].as_f64().unwrap() - 60.0).abs() < 0.01, "{t}");
    assert!(t["min"].as_f64().unwrap() < 42.5, "{t}");
    // And a missing one is an error that names it.
    cli![
        "simulate",
        "--profile",
        "file:no-such-chamber.csv",
        "-o",
        dir.path().join("x.txt")
    ]
    .refused(1, "no-such-chamber.csv");
}

#[test]
fn help_documents_profiles_and_durations() {
    imutherm().args(["simulate", "--help"]).assert().success().stdout(
        predicate::str::contains("cooling:START:AMBIENT:TAU_S")
            .and(predicate::str::contains("steps:T1,T2"))
            .and(predicate::str::contains("file:PATH"))
            .and(predicate::str::contains("90m")),
    );
    // A usage error is clap's: exit 2.
    cli!["simulate", "--rate", "fast", "-o", "x.txt"].assert().code(2);
}

#[test]
fn a_log_of_no_samples_is_a_usage_error_and_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("empty.txt");
    // 1 ms at the thesis preset's 20 Hz rounds to 0 samples.
    cli!["simulate", "--duration", "0.001", "-o", &out].refused(2, "less than one sample");
    assert!(!out.exists());
}

/// The `# true.gyro_x.n` line of a log.
fn true_n(text: &str, channel: &str) -> f64 {
    let key = format!("# true.{channel}.n: ");
    let line = text.lines().find(|l| l.starts_with(&key)).unwrap();
    line[key.len()..].trim().parse().unwrap()
}

#[test]
fn a_unit_of_a_population_is_the_same_board_on_every_run() {
    let dir = tempfile::tempdir().unwrap();
    let run_as = |flag: &str, name: &str, extra: &[&str]| {
        let p = dir.path().join(name);
        imutherm()
            .args(["simulate", "--preset", "white", "--duration", "10", flag])
            .args(extra)
            .arg("-o")
            .arg(&p)
            .assert()
            .success();
        std::fs::read_to_string(p).unwrap()
    };
    let run = |name: &str, extra: &[&str]| run_as("--unit-id", name, extra);
    let a1 = run("a1.txt", &["SN-1"]);
    // `--unit`, the flag's former name, is the same flag.
    assert_eq!(run_as("--unit", "a1_old.txt", &["SN-1"]), a1);
    let a2 = run("a2.txt", &["SN-1", "--seed", "5"]);
    let b = run("b.txt", &["SN-2"]);
    let bad = run("bad.txt", &["SN-1", "--defect", "noise-3x"]);
    // The white preset's gyro N is 1.5e-4 rad/√s: a unit scatters around it.
    assert_eq!(true_n(&a1, "gyro_x"), true_n(&a2, "gyro_x"));
    assert_ne!(true_n(&a1, "gyro_x"), true_n(&b, "gyro_x"));
    assert_ne!(true_n(&a1, "gyro_x"), 1.5e-4);
    assert!((true_n(&bad, "gyro_x") / true_n(&a1, "gyro_x") - 3.0).abs() < 1e-12);
    assert!(a1.contains("# population.unit: SN-1\n") && a1.contains("# population.defect: none\n"));
    assert!(bad.contains("# population.defect: noise-3x\n"));
    // Another seed, another realisation of the same board.
    let rows = |t: &str| {
        t.lines()
            .filter(|l| !l.starts_with('#'))
            .nth(5)
            .map(str::to_owned)
    };
    assert_ne!(rows(&a1), rows(&a2));
}

#[test]
fn population_flags_are_checked_as_flags() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.txt");
    for (args, says) in [
        (vec!["--defect", "noise-3x"], "--unit-id"),
        (vec!["--unit-id", "U", "--defect", "dead-axis:mag_x"], "gyro_z"),
        (vec!["--unit-id", "U", "--scatter", "0.1"], "NOISE,BIAS"),
        (vec!["--unit-id", "", "--preset", "white"], "empty"),
        (vec!["--unit", "", "--preset", "white"], "--unit-id"),
    ] {
        writing("simulate", &args, &out).refused(2, says);
    }
    assert!(!out.exists());
}
