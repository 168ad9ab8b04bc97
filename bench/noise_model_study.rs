//! The acceptance study of the noise model: each case of
//! `noise_model_cases.rs` over many seeds, and per term how often the
//! selected model holds it, how often it lies within the case's tolerance,
//! and how often its 95 % interval covers the truth.
//!
//! ```sh
//! cargo run --release -p imusim --example noise_model_study -- 200
//! ```

use rayon::prelude::*;

#[path = "noise_model_cases.rs"]
mod cases;
use cases::{CASES, NAMES, outcomes, truth};

fn main() {
    let seeds: u64 = std::env::args()
        .nth(1)
        .map_or(200, |s| s.parse().expect("a seed count"));
    for case in &CASES {
        let start = std::time::Instant::now();
        let results: Vec<(String, [cases::Outcome; 6])> = (0..seeds)
            .into_par_iter()
            .map(|seed| {
                let m = cases::model_of(case, 10_000 + seed);
                let o = outcomes(case, &m);
                (m.label, o)
            })
            .collect();
        let mut labels: Vec<(String, usize)> = Vec::new();
        for (l, _) in &results {
            match labels.iter_mut().find(|(x, _)| x == l) {
                Some((_, c)) => *c += 1,
                None => labels.push((l.clone(), 1)),
            }
        }
        labels.sort_by_key(|x| std::cmp::Reverse(x.1));
        println!(
            "## {} ({seeds} seeds, {:.0} s)\nmodels: {}",
            case.name,
            start.elapsed().as_secs_f64(),
            labels
                .iter()
                .map(|(l, c)| format!("{l} {c}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
        println!(
            "| term | truth | in the model | within tolerance | 95 % interval covers (of those in the model) |"
        );
        println!("| --- | --- | --- | --- | --- |");
        let t = truth(case);
        for k in 0..6 {
            let shown = results.iter().filter(|r| r.1[k].shown).count();
            if t[k] == 0.0 && shown == 0 {
                continue;
            }
            let within = results.iter().filter(|r| r.1[k].within).count();
            let covered = results.iter().filter(|r| r.1[k].covered).count();
            println!(
                "| {} | {:.3e} | {shown} | {} | {} |",
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
