//! `imutherm ins` end to end on simulated recordings: the truth is read
//! from the recordings' `true.*` metadata and the closed forms are written
//! out here, not taken from imutherm's code.

use std::path::Path;

use predicates::prelude::*;
use serde_json::Value;

mod support;
use support::{Refused, Simulation, cli, imutherm, json_stdout, tcal_fit};

/// A `true.*` value of a simulated recording.
fn truth(path: &Path, key: &str) -> f64 {
    let text = std::fs::read_to_string(path).unwrap();
    let prefix = format!("# {key}: ");
    text.lines()
        .find_map(|l| l.strip_prefix(&prefix))
        .unwrap_or_else(|| panic!("{key} not in {}", path.display()))
        .trim()
        .parse()
        .unwrap()
}

/// `imutherm ins FILES… ARGS --json`, which must succeed.
fn json_of(args: &[&str], files: &[&Path]) -> Value {
    json_stdout(imutherm().arg("ins").args(files).args(args).arg("--json"))
}

#[test]
fn white_noise_prediction_is_the_closed_form_and_the_measurement_follows_it() {
    let dir = tempfile::tempdir().unwrap();
    let f = Simulation::new()
        .args(&["--preset", "white"])
        .duration("30m")
        .write(dir.path(), "white.txt");
    let ng = truth(&f, "true.gyro_x.n");
    let na = truth(&f, "true.accel_x.n");
    let g: f64 = 9.80665; // standard gravity: no --latitude
    let ta: f64 = 10.0;
    let doc = json_of(&["--horizon", "60", "--every", "5"], &[&f]);
    assert_eq!(doc["schema"], "imutherm.ins/1");
    let file = &doc["files"][0];
    assert_eq!(file["align_s"], 10.0);
    assert!(file["windows"].as_u64().unwrap() > 300);
    let curve = file["curve"].as_array().unwrap();
    let ts: Vec<f64> = curve.iter().map(|p| p["t_s"].as_f64().unwrap()).collect();
    assert_eq!(ts, vec![1.0, 10.0, 30.0, 60.0]);
    for p in curve {
        let t = p["t_s"].as_f64().unwrap();
        // Per axis: gyro g·N·t^{5/2}/√20, accelerometer N·t^{3/2}/√3,
        // levelling ½·N·t²/√T_a, and the gyro bias the alignment window's
        // mean leaves, g·N·t³/(6·√T_a); two axes.
        let axis = (g * ng * t.powf(2.5) / 20f64.sqrt()).powi(2)
            + (na * t.powf(1.5) / 3f64.sqrt()).powi(2)
            + (0.5 * na * t * t / ta.sqrt()).powi(2)
            + (g * ng * t.powi(3) / (6.0 * ta.sqrt())).powi(2);
        let closed = (2.0 * axis).sqrt();
        let predicted = p["predicted_horizontal_position_1sigma_m"].as_f64().unwrap();
        assert!(
            (predicted / closed - 1.0).abs() < 0.02,
            "t = {t}: predicted {predicted}, closed form {closed}"
        );
        if t >= 10.0 {
            let rms = p["horizontal_position_m"]["rms"].as_f64().unwrap();
            assert!(
                (rms / closed - 1.0).abs() < 0.15,
                "t = {t}: measured {rms}, closed form {closed}"
            );
        }
        for key in [
            "horizontal_position_m",
            "horizontal_velocity_m_s",
            "tilt_deg",
            "heading_deg",
        ] {
            let s = &p[key];
            let (rms, p50, p95) = (
                s["rms"].as_f64().unwrap(),
                s["p50"].as_f64().unwrap(),
                s["p95"].as_f64().unwrap(),
            );
            assert!(p50 > 0.0 && p50 <= p95 && rms > 0.0, "{key} at {t}: {s}");
        }
    }
    assert!(file.get("compensated").is_none());
}

#[test]
fn the_rotating_earth_leaves_no_drift_with_the_latitude() {
    let dir = tempfile::tempdir().unwrap();
    let config = String::from_utf8(
        imutherm()
            .args(["simulate", "--preset", "white", "--print-config"])
            .output()
            .unwrap()
            .stdout,
    )
    .unwrap();
    // Noise-free, tilted, facing north at 48° N.
    let config: String = config
        .lines()
        .map(|l| match l {
            l if l.starts_with("n = ") => "n = 0.0".to_string(),
            l if l.starts_with("duration_s") => "duration_s = 140.0".to_string(),
            "roll_deg = 0.0" => "roll_deg = 1.23".to_string(),
            "pitch_deg = 0.0" => "pitch_deg = -5.14\nheading_deg = 0.0\nlatitude_deg = 48.0".to_string(),
            l => l.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n");
    let toml = dir.path().join("earth.toml");
    std::fs::write(&toml, config).unwrap();
    let f = Simulation::new()
        .args(&["--config", toml.to_str().unwrap()])
        .write(dir.path(), "earth.txt");
    assert_eq!(truth(&f, "true.latitude_deg"), 48.0);
    // The gyros read the Earth's rate: |ω| = 7.292115e-5 rad/s (WGS-84).
    let w: f64 = ["x", "y", "z"]
        .iter()
        .map(|a| truth(&f, &format!("true.gyro_{a}.input")).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!((w - 7.292_115e-5).abs() < 1e-12, "{w}");
    let doc = json_of(&["--latitude", "48", "--every", "5"], &[&f]);
    let curve = doc["files"][0]["curve"].as_array().unwrap();
    assert_eq!(curve.last().unwrap()["t_s"], 120.0);
    for p in curve {
        let e = p["horizontal_position_m"]["p95"].as_f64().unwrap();
        assert!(e < 0.1, "{e} m at {}", p["t_s"]);
    }
}

#[test]
fn a_model_navigates_the_compensated_run_beside_the_raw_one() {
    let dir = tempfile::tempdir().unwrap();
    let f = Simulation::new()
        .profile("cooling:100:20:600")
        .duration("15m")
        .rate("50")
        .write(dir.path(), "cooling.txt");
    let model = dir.path().join("model.json");
    tcal_fit(&model, &[], &[&f]);
    cli!["ins", &f, "--model", &model, "--horizon", "60", "--every", "20"]
        .assert()
        .success()
        .stdout(
            predicate::str::is_match(r"60 s without GNSS: raw [0-9.]+ m, compensated [0-9.]+ m").unwrap(),
        );
    let doc = json_of(
        &[
            "--model",
            model.to_str().unwrap(),
            "--horizon",
            "60",
            "--every",
            "20",
        ],
        &[&f],
    );
    let file = &doc["files"][0];
    let c = &file["compensated"];
    assert_eq!(c["align_s"], 10.0);
    assert_eq!(c["windows"], file["windows"]);
    let at60 = |v: &Value| v["curve"][3]["horizontal_position_m"]["rms"].as_f64().unwrap();
    assert_eq!(file["curve"][3]["t_s"], 60.0);
    // The cooling run's bias follows its temperature: compensated, it drifts less.
    assert!(
        at60(c) < at60(file),
        "compensated {} m, raw {} m",
        at60(c),
        at60(file)
    );
    // Both predictions rest on the compensated run's terms: the raw run's
    // measured error above its prediction is the temperature's share.
    assert_eq!(file["noise_from"], "compensated_run");
    assert_eq!(file["noise_si"], c["noise_si"]);
    for (r, k) in file["curve"]
        .as_array()
        .unwrap()
        .iter()
        .zip(c["curve"].as_array().unwrap())
    {
        assert_eq!(
            r["predicted_horizontal_position_drms_m"],
            k["predicted_horizontal_position_drms_m"]
        );
        // The old name keeps the same figure.
        assert_eq!(
            r["predicted_horizontal_position_1sigma_m"],
            r["predicted_horizontal_position_drms_m"]
        );
    }
}

/// `ins --horizon 3600` on white noise with a latitude: at every printed
/// time the prediction is within 10 % of the Monte Carlo, or the output
/// says from when it is not.
#[test]
fn an_hour_with_a_latitude_is_predicted_or_says_where_it_stops() {
    let dir = tempfile::tempdir().unwrap();
    let f = Simulation::new()
        .args(&["--preset", "white"])
        .duration("3620")
        .rate("10")
        .write(dir.path(), "hour.txt");
    let plot = dir.path().join("hour.svg");
    let args = [
        "--horizon",
        "3600",
        "--every",
        "3610",
        "--latitude",
        "48",
        "--runs",
        "200",
        "--seed",
        "7",
    ];
    let mut with_plot = args.to_vec();
    with_plot.extend(["--plot", plot.to_str().unwrap()]);
    let doc = json_of(&with_plot, &[&f]);
    let file = &doc["files"][0];
    assert_eq!(file["schuler_loop"], true);
    assert_eq!(
        (
            file["monte_carlo_runs"].as_u64(),
            file["monte_carlo_seed"].as_u64()
        ),
        (Some(200), Some(7))
    );
    let stops = file["prediction_stops_at_s"].as_f64();
    let curve = file["curve"].as_array().unwrap();
    assert_eq!(curve.len(), 10, "1 s to an hour");
    for p in curve {
        let t = p["t_s"].as_f64().unwrap();
        let predicted = p["predicted_horizontal_position_drms_m"].as_f64().unwrap();
        let mc = p["monte_carlo_horizontal_position_m"]["rms"].as_f64().unwrap();
        assert!(
            (predicted / mc - 1.0).abs() < 0.1 || stops.is_some_and(|s| s <= t),
            "{t} s: predicted {predicted} m, Monte Carlo {mc} m, stops at {stops:?}"
        );
    }
    let svg = std::fs::read_to_string(&plot).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("predicted DRMS"));
    imutherm()
        .arg("ins")
        .arg(&f)
        .args(args)
        .assert()
        .success()
        .stdout(predicate::str::contains(
            "latitude 48°: normal gravity, Earth rate, Coriolis, the Schuler loop",
        ))
        .stdout(predicate::str::contains("Monte Carlo: 200 runs from seed 7"));
}

#[test]
fn bad_values_are_usage_errors_and_short_files_runtime_errors() {
    let dir = tempfile::tempdir().unwrap();
    let f = Simulation::new()
        .args(&["--preset", "white"])
        .duration("60")
        .write(dir.path(), "short.txt");
    for bad in [
        &["--align", "0"][..],
        &["--horizon", "-5"],
        &["--every", "abc"],
        &["--latitude", "91"],
        &["--latitude", "north"],
        &["--runs", "1"],
    ] {
        imutherm().arg("ins").arg(&f).args(bad).assert().code(2);
    }
    // A plot neither SVG nor PNG is refused before anything is written.
    let pdf = dir.path().join("drift.pdf");
    cli!["ins", &f, "--plot", &pdf].assert().code(2);
    assert!(!pdf.exists());
    // Past 1/ω_s a flat Earth no longer stands for the real one.
    cli!["ins", &f, "--horizon", "900"].refused(2, "give the latitude");
    // Sixty seconds cannot hold 10 s of alignment and 120 s of navigation.
    cli!["ins", &f].refused(1, "130.0 s are needed");
    cli!["ins", "--help"]
        .assert()
        .success()
        .stdout(predicate::str::contains(
            "imutherm ins cooling.txt --model model.json",
        ));
}
