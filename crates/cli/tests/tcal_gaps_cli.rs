//! Thermal recordings as they are logged, and what a flight stack does with
//! the parameter file fitted on them. Duty-cycled bursts with their
//! gaps in time, or gaps written out as NaN rows. Each fits with the order
//! chosen automatically, and the model it writes loads in `tcal eval` with
//! finite residuals.

use std::path::{Path, PathBuf};

use predicates::prelude::*;

mod support;
use support::{cli, imutherm, json_stdout, read_json, succeed};

/// A cooling run, 24 → 16.7 °C over 2 h at 20 Hz, logged 5 s every 305 s
/// (the shape of a thermal-vacuum test's log); the gaps left out of the
/// file, or written as NaN rows. gyro_x has a quadratic bias in T.
fn write_bursts(dir: &Path, nan_rows: bool) -> PathBuf {
    let mut text = String::from("time_s,gyro_x,gyro_y,gyro_z,temperature\n");
    let mut state = 5u64;
    let mut noise = move || {
        // Sum of 12 uniforms: a Gaussian of unit variance, deterministic.
        (0..12)
            .map(|_| {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (state >> 11) as f64 / (1u64 << 53) as f64
            })
            .sum::<f64>()
            - 6.0
    };
    for i in 0..7200 * 20 {
        let s = i as f64 / 20.0;
        let t = 16.0 + 8.0 * (-s / 3000.0).exp();
        if s % 305.0 < 5.0 {
            let g = 1e-3 + 4e-5 * (t - 20.0) + 3e-6 * (t - 20.0).powi(2) + 1e-3 * noise();
            text += &format!(
                "{s:.3},{g:.6e},{:.6e},{:.6e},{:.4}\n",
                1e-3 * noise(),
                1e-3 * noise(),
                t
            );
        } else if nan_rows {
            text += &format!("{s:.3},nan,nan,nan,nan\n");
        }
    }
    let path = dir.join(if nan_rows { "nan_rows.csv" } else { "bursts.csv" });
    std::fs::write(&path, text).unwrap();
    path
}

fn fits_and_loads(dir: &Path, run: &Path, read: &[&str]) {
    let model = dir.join(format!("{}.json", run.file_stem().unwrap().to_str().unwrap()));
    succeed(
        imutherm()
            .args(["tcal", "fit", "--order", "auto", "--for", "px4"])
            .args(read)
            .arg(run)
            .arg("-o")
            .arg(&model),
    );
    let m = read_json(&model);
    for c in m["channels"].as_array().unwrap() {
        assert!(c["residual_rms"].as_f64().unwrap().is_finite(), "{c}");
        assert!(c["order"].as_u64().unwrap() <= 3);
    }
    let doc = json_stdout(
        imutherm()
            .args(["tcal", "eval", "--json"])
            .args(read)
            .arg(&model)
            .arg(run),
    );
    for row in doc["rows"].as_array().unwrap() {
        assert!(row["bias_rms_after"].as_f64().unwrap().is_finite(), "{row}");
        // The fitted range is the data's: the fitted run lies inside it.
        assert_eq!(row["samples_out_of_range"], 0, "{row}");
    }
}

#[test]
fn a_duty_cycled_log_is_read_with_its_gaps_when_the_grid_limit_is_raised() {
    let dir = tempfile::tempdir().unwrap();
    let run = write_bursts(dir.path(), false);
    cli!["info", &run]
        .assert()
        .failure()
        .stderr(predicate::str::contains("--max-grid-factor 6"));
    fits_and_loads(dir.path(), &run, &["--max-grid-factor", "64"]);
}

#[test]
fn nan_rows_fit_with_the_order_chosen_and_load_in_eval() {
    let dir = tempfile::tempdir().unwrap();
    let run = write_bursts(dir.path(), true);
    fits_and_loads(dir.path(), &run, &[]);
}

/// `tcal eval --export px4 --params FILE` judges the file as PX4 would, and
/// fails where PX4 would correct nothing.
#[test]
fn eval_says_what_px4_does_with_a_parameter_file() {
    let dir = tempfile::tempdir().unwrap();
    let run = write_bursts(dir.path(), true);
    let model = dir.path().join("m.json");
    succeed(
        imutherm()
            .args(["tcal", "fit", "--for", "px4"])
            .arg(&run)
            .arg("-o")
            .arg(&model),
    );
    let params = dir.path().join("m.params");
    succeed(
        imutherm()
            .args(["tcal", "export", "--firmware", "px4", "-o"])
            .arg(&params)
            .arg(&model),
    );
    let text = std::fs::read_to_string(&params).unwrap();
    let eval = |text: &str| {
        let p = dir.path().join("judged.params");
        std::fs::write(&p, text).unwrap();
        let mut cmd = imutherm();
        cmd.args(["tcal", "eval", "--export", "px4", "--params"])
            .arg(&p)
            .arg(&model)
            .arg(&run);
        cmd.assert()
    };
    // The run gives no device id and the file holds the placeholder: the
    // verdict says PX4 applies nothing as written, and what it applies once
    // the id is set (which the figures show), never plainly "applies".
    eval(&text).success().stdout(
        predicate::str::contains("PX4 applies nothing to the gyro as the file stands: TC_G0_ID is 0")
            .and(predicate::str::contains(
                "once it holds the gyro's device id PX4 applies TC_G0",
            ))
            .and(predicate::str::contains("PX4 applies TC_G0 to the gyro").not()),
    );
    // With the gyro's id in the file and none in the run, the condition.
    eval(&text.replace("TC_G0_ID\t0\t", "TC_G0_ID\t2490378\t"))
        .success()
        .stdout(predicate::str::contains(
            "PX4 applies TC_G0 to the gyro only if 2490378 is that id",
        ));
    // As PX4's own script writes it: no ENABLE.
    let no_enable: String = text
        .lines()
        .filter(|l| !l.contains("_ENABLE"))
        .map(|l| format!("{l}\n"))
        .collect();
    eval(&no_enable)
        .code(1)
        .stdout(predicate::str::contains(
            "PX4 applies nothing to the gyro: TC_G_ENABLE is absent",
        ))
        .stderr(predicate::str::contains("would apply no temperature correction"));
    // A range the run never reaches.
    let far: String = text
        .lines()
        .map(|l| {
            let f: Vec<&str> = l.split('\t').collect();
            match f.get(2) {
                Some(&"TC_G0_TMIN") => "1\t1\tTC_G0_TMIN\t80\t9\n".to_string(),
                Some(&"TC_G0_TMAX") => "1\t1\tTC_G0_TMAX\t90\t9\n".to_string(),
                _ => format!("{l}\n"),
            }
        })
        .collect();
    eval(&far)
        .code(1)
        .stdout(predicate::str::contains("misses TC_G0_TMIN…TMAX 80.0…90.0 °C"));
}
