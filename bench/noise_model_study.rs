//! The acceptance study of the noise model: each case of
//! `noise_model_cases.rs` over many seeds, and per term how often the
//! selected model holds it, how often it lies within the case's tolerance,
//! and how often its 95 % interval covers the truth.
//!
//! ```sh
//! cargo run --release -p imusim --example noise_model_study -- 200
//! ```
//!
//! With `--dump DIR` after the seed count, each seed's samples are written
//! to `DIR/<case>_<seed>.f64` (little-endian) and the terms of its selected
//! model to `DIR/imutherm.tsv`, for `noise_model_peer.py` to fit the same
//! records with a peer.

use rayon::prelude::*;

#[path = "noise_model_cases.rs"]
mod cases;
use cases::{CASES, NAMES, outcomes, truth};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let seeds: u64 = args.get(1).map_or(200, |s| s.parse().expect("a seed count"));
    let dump = match args.get(2).map(String::as_str) {
        Some("--dump") => Some(std::path::PathBuf::from(args.get(3).expect("--dump DIR"))),
        Some(other) => panic!("unknown argument {other}"),
        None => None,
    };
    if let Some(dir) = &dump {
        std::fs::create_dir_all(dir).expect("the dump directory");
        let header = format!("case\tseed\trate_hz\t{}\n", NAMES.join("\t"));
        std::fs::write(dir.join("imutherm.tsv"), header).expect("imutherm.tsv");
    }
    for (index, case) in CASES.iter().enumerate() {
        let start = std::time::Instant::now();
        let results: Vec<(String, [cases::Outcome; 6], bool, f64)> = (0..seeds)
            .into_par_iter()
            .map(|seed| {
                let m = cases::model_of(case, 10_000 + seed);
                let o = outcomes(case, &m);
                (m.label, o, m.fits, m.chi2_reduced.unwrap_or(f64::NAN))
            })
            .collect();
        if let Some(dir) = &dump {
            write_dump(dir, index, case, seeds);
        }
        let fitting = results.iter().filter(|r| r.2).count();
        let mut labels: Vec<(String, usize)> = Vec::new();
        for (l, ..) in &results {
            match labels.iter_mut().find(|(x, _)| x == l) {
                Some((_, c)) => *c += 1,
                None => labels.push((l.clone(), 1)),
            }
        }
        labels.sort_by_key(|x| std::cmp::Reverse(x.1));
        // Near 1 where the points' covariance is right and the model holds.
        let mut chi2: Vec<f64> = results.iter().map(|r| r.3).filter(|v| v.is_finite()).collect();
        chi2.sort_by(f64::total_cmp);
        let chi2_median = chi2.get(chi2.len() / 2).copied().unwrap_or(f64::NAN);
        println!(
            "## {} ({seeds} seeds, {:.0} s)\nthe selected model fits in {fitting}; median χ²/dof {chi2_median:.2}\nmodels: {}",
            case.name,
            start.elapsed().as_secs_f64(),
            labels
                .iter()
                .map(|(l, c)| format!("{l} {c}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
        println!(
            "| term | truth | in the model | within tolerance | median error | 95 % interval covers (of those in the model) | half-width / (1.96 × spread): sd / MAD |"
        );
        println!("| --- | --- | --- | --- | --- | --- | --- |");
        let t = truth(case);
        for k in 0..6 {
            let shown = results.iter().filter(|r| r.1[k].shown).count();
            if t[k] == 0.0 && shown == 0 {
                continue;
            }
            let within = results.iter().filter(|r| r.1[k].within).count();
            let covered = results.iter().filter(|r| r.1[k].covered).count();
            let mut errors: Vec<f64> = results.iter().filter_map(|r| r.1[k].error).collect();
            errors.sort_by(f64::total_cmp);
            let median = errors
                .get(errors.len() / 2)
                .map_or("—".to_string(), |e| format!("{:+.1} %", 100.0 * e));
            let calibration = calibration(results.iter().map(|r| &r.1[k]));
            println!(
                "| {} | {:.3e} | {shown} | {} | {median} | {} | {calibration} |",
                NAMES[k],
                t[k],
                if t[k] > 0.0 {
                    format!("{within} (±{:.0} %)", 100.0 * case.tolerance[k])
                } else {
                    "—".to_string()
                },
                if t[k] > 0.0 && shown > 0 {
                    format!("{covered} ({:.0} %)", 100.0 * covered as f64 / shown as f64)
                } else {
                    "—".to_string()
                }
            );
        }
        println!();
    }
}

/// The median half-width of the term's 95 % intervals in ln over 1.96 times
/// the spread of ln value across the seeds that hold it, that spread taken
/// two ways: the standard deviation, and 1.4826 times the median absolute
/// deviation (the same for a normal scatter, unmoved by the few seeds whose
/// model reads the term off another process). Near 1 for intervals as wide
/// as the estimates' own scatter asks, above 1 for intervals wider than
/// that; over 200 seeds each ratio is known to about ±5 % (±8 % the MAD's).
fn calibration<'a>(outcomes: impl Iterator<Item = &'a cases::Outcome>) -> String {
    let (mut logs, mut halves): (Vec<f64>, Vec<f64>) = outcomes
        .filter_map(|o| Some((o.log_value?, o.log_half?)))
        .filter(|(v, h)| v.is_finite() && h.is_finite())
        .unzip();
    if logs.len() < 3 {
        return "—".to_string();
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let n = logs.len() as f64;
    let mean = logs.iter().sum::<f64>() / n;
    let sd = (logs.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
    let centre = median(&mut logs);
    let mut deviations: Vec<f64> = logs.iter().map(|v| (v - centre).abs()).collect();
    let mad = 1.4826 * median(&mut deviations);
    let half = median(&mut halves);
    format!("{:.2} / {:.2}", half / (1.96 * sd), half / (1.96 * mad))
}

/// Each seed's samples of `case` and the values of its selected model
/// ("-" for a term it does not hold), in the order of [`NAMES`].
fn write_dump(dir: &std::path::Path, index: usize, case: &cases::Case, seeds: u64) {
    use std::io::Write;
    let mut table = std::fs::OpenOptions::new()
        .append(true)
        .open(dir.join("imutherm.tsv"))
        .expect("imutherm.tsv");
    for seed in 0..seeds {
        let seed = 10_000 + seed;
        let y = cases::simulate(case, seed);
        let bytes: Vec<u8> = y.iter().flat_map(|v| v.to_le_bytes()).collect();
        std::fs::write(dir.join(format!("{index}_{seed}.f64")), bytes).expect("samples");
        let m = cases::model_of(case, seed);
        let values = cases::values(&m)
            .iter()
            .map(|v| v.map_or("-".to_string(), |x| format!("{x:e}")))
            .collect::<Vec<_>>()
            .join("\t");
        writeln!(table, "{index}\t{seed}\t{}\t{values}", case.rate_hz).expect("a row");
    }
}
