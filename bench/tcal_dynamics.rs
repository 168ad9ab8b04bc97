//! `tcal fit`'s default model on thermal histories that are no polynomial
//! of the logged temperature (`imusim::history`: element lag 60–200 s,
//! hysteresis worth 2.5–15 °C, MPU-9250 noise and temperature steps),
//! fitted on a 1.1 °C/min heating and a Newton cooling, judged on a run
//! heating at 2.2 °C/min with a plateau, against a least-squares cubic and
//! the truth's own floor; then the same on a pure cubic.
//!
//!     cargo run --release -p thermal --example tcal_dynamics -- [SEEDS…]

#[path = "tcal_dynamics_score.rs"]
mod score;

use imusim::history::{AXES, Truth};
use thermal::tcal::FitOptions;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

fn main() {
    let seeds = score::seeds(10);
    let rate = 2.0;
    for pure in [false, true] {
        let mut full_floor = vec![Vec::new(); 6];
        let mut full_cubic = vec![Vec::new(); 6];
        let mut cubic_floor = vec![Vec::new(); 6];
        let mut firmware_cubic = vec![Vec::new(); 6];
        for &seed in &seeds {
            let mut truth = Truth::draw(seed);
            truth.pure_cubic = pure;
            let s = score::score(&truth, rate, seed, &FitOptions::default());
            let found: Vec<String> = s
                .model
                .channels
                .iter()
                .map(|c| {
                    format!(
                        "{}:o{}{}{}",
                        &c.name,
                        c.order,
                        c.lag_s.map_or(String::new(), |l| format!(" lag {l:.0} s")),
                        c.hysteresis_term
                            .as_ref()
                            .map_or(String::new(), |h| format!(" h {:.2e}", h.heating_minus_cooling))
                    )
                })
                .collect();
            println!(
                "seed {seed}{}: truth lag {:.0} s, hysteresis {:.1} °C; {}",
                if pure { " (pure cubic)" } else { "" },
                truth.lag_s,
                truth.hysteresis_c,
                found.join(", ")
            );
            // `--for px4`: a cubic at most, projected on the logged temperature.
            let fw = score::score(
                &truth,
                rate,
                seed,
                &FitOptions {
                    max_auto_order: 3,
                    firmware_projection: true,
                    ..FitOptions::default()
                },
            );
            for k in 0..6 {
                firmware_cubic[k].push(fw.full[k] / s.cubic[k]);
                full_floor[k].push(s.full[k] / s.floor[k]);
                full_cubic[k].push(s.full[k] / s.cubic[k]);
                cubic_floor[k].push(s.cubic[k] / s.floor[k]);
            }
        }
        println!(
            "\n{} truths, {} seeds, medians:\n| axis | imutherm / floor | imutherm / cubic | cubic / floor | `--for` projection / cubic |\n|---|---|---|---|---|",
            if pure { "pure-cubic" } else { "lag + hysteresis" },
            seeds.len()
        );
        for k in 0..6 {
            println!(
                "| {} | {:.2} | {:.3} | {:.2} | {:.3} |",
                AXES[k],
                median(full_floor[k].clone()),
                median(full_cubic[k].clone()),
                median(cubic_floor[k].clone()),
                median(firmware_cubic[k].clone())
            );
        }
        println!();
    }
}
