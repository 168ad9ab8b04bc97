//! The full model (lag, hysteresis) on `imusim::history` truths, whose bias
//! is no polynomial of the logged temperature, and its C header.

#[path = "../../../bench/tcal_dynamics_score.rs"]
#[allow(dead_code)]
mod score;

use imusim::history::{self, AXES, Truth};
use thermal::tcal::FitOptions;

/// One fit shared by the tests (the fit is the cost in the debug
/// profile): seed 1's calibration runs at a quarter hertz, fast against
/// the shortest lag and direction memory the generator draws (60 s).
const RATE_HZ: f64 = 0.25;
const SEED: u64 = 1;

fn fitted() -> &'static score::Score {
    static FIT: std::sync::OnceLock<score::Score> = std::sync::OnceLock::new();
    FIT.get_or_init(|| score::score(&Truth::draw(SEED), RATE_HZ, SEED, &FitOptions::default()))
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

#[test]
fn lag_and_hysteresis_beat_a_cubic_of_the_logged_temperature() {
    // Fitted on a 1.1 °C/min heating and a Newton cooling, judged on a run
    // heating at 2.2 °C/min with a plateau. One seed here, the first;
    // bench/tcal_dynamics.rs runs twelve at 2 Hz (bench/README.md).
    let s = fitted();
    let ratios: Vec<f64> = (0..6).map(|k| s.full[k] / s.cubic[k]).collect();
    assert!(median(ratios.clone()) < 1.0, "{ratios:?} of the cubic, per axis");
    assert!(
        s.model
            .channels
            .iter()
            .any(|c| c.hysteresis_term.is_some() || c.lag_s.is_some()),
        "neither lag nor hysteresis found on a truth that has both"
    );
}

#[test]
fn the_c_header_compensates_as_apply_does() {
    let (runs, _) = score::recordings(&Truth::draw(SEED), RATE_HZ, SEED);
    let model = &fitted().model;
    assert!(
        model.channels.iter().any(|c| c.lag_s.is_some())
            && model
                .channels
                .iter()
                .any(|c| c.hysteresis_term.as_ref().is_some_and(|h| h.relax_s.is_some())),
        "the header is checked on a model with its filters (a lag, a relaxed direction)"
    );
    let header = thermal::c_header::render(model).unwrap();
    let Ok(cc) = which_cc() else {
        panic!("no C compiler (cc) to check the header with");
    };
    let dir = tempfile_dir();
    std::fs::write(dir.join("imutherm_tcal.h"), &header).unwrap();
    std::fs::write(
        dir.join("main.c"),
        r#"#include <stdio.h>
#include "imutherm_tcal.h"
int main(void) {
    imutherm_tcal_state s = {0};
    double dt, t, x[IMUTHERM_TCAL_CHANNELS];
    while (scanf("%lf %lf", &dt, &t) == 2) {
        for (int k = 0; k < IMUTHERM_TCAL_CHANNELS; ++k)
            if (scanf("%lf", &x[k]) != 1) return 1;
        imutherm_tcal_apply(&s, t, dt, x);
        for (int k = 0; k < IMUTHERM_TCAL_CHANNELS; ++k)
            printf("%.17g%c", x[k], k + 1 < IMUTHERM_TCAL_CHANNELS ? ' ' : '\n');
    }
    return 0;
}
"#,
    )
    .unwrap();
    let exe = dir.join("tcal");
    let out = std::process::Command::new(&cc)
        .args(["-std=c99", "-Wall", "-Werror", "-O1", "-o"])
        .arg(&exe)
        .arg(dir.join("main.c"))
        .arg("-lm")
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // The cooling run, with a gap of NaN temperatures.
    let r = &runs[1];
    let mut temp = r.temp.clone();
    for t in temp.iter_mut().skip(1000).take(120) {
        *t = f64::NAN;
    }
    let mut input = String::new();
    for (i, t) in temp.iter().enumerate() {
        input += &format!("{} {}", 1.0 / r.rate_hz, t);
        for k in 0..6 {
            input += &format!(" {:e}", r.channels[k][i]);
        }
        input.push('\n');
    }
    // Through a file: a pipe written whole before it is read would fill.
    let data = dir.join("input.txt");
    std::fs::write(&data, input).unwrap();
    let out = std::process::Command::new(&exe)
        .stdin(std::fs::File::open(&data).unwrap())
        .output()
        .unwrap();
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    let rows: Vec<Vec<f64>> = text
        .lines()
        .map(|l| {
            l.split(' ')
                .map(|v| v.parse::<f64>().unwrap_or(f64::NAN))
                .collect()
        })
        .collect();
    assert_eq!(rows.len(), temp.len());
    for (k, name) in AXES.iter().enumerate() {
        let mut want = r.channels[k].clone();
        model.apply(name, &mut want, &temp, r.rate_hz).unwrap();
        let scale = want
            .iter()
            .filter(|v| v.is_finite())
            .fold(0.0f64, |m, v| m.max(v.abs()));
        for (i, w) in want.iter().enumerate() {
            let got = rows[i][k];
            if w.is_nan() {
                assert!(got.is_nan(), "{name}[{i}]: {got} where apply gives NaN");
            } else {
                assert!((got - w).abs() <= 1e-6 * scale, "{name}[{i}]: {got} vs {w}");
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

fn which_cc() -> Result<String, ()> {
    std::process::Command::new("cc")
        .arg("--version")
        .output()
        .map(|_| "cc".to_string())
        .map_err(|_| ())
}

fn tempfile_dir() -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("imutherm-cheader-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn the_generator_has_its_lag_and_quantized_readout() {
    let truth = Truth::draw(5);
    assert!((60.0..200.0).contains(&truth.lag_s) && (2.5..15.0).contains(&truth.hysteresis_c));
    let (start, legs) = history::held_out_run();
    let r = history::record(&truth, start, &legs, 1.0, 1);
    let k = r.temp[100] / history::MPU9250_TEMP_STEP_C;
    assert!((k - k.round()).abs() < 1e-6);
}
