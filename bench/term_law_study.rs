//! The acceptance study of the terms' law over temperature
//! (`analysis::term_law`): sets of four constant-temperature runs at the
//! thesis's 34, 43, 62 and 82 °C, simulated with the `mpu9250-thesis`
//! preset (one hour at 20 Hz each, its gyro y), once with every noise
//! term rising 13 % from 34 to 82 °C (exactly log-linear at the four
//! temperatures) and once with the terms constant; per seed, each run's
//! noise terms as `imutherm noise` reads them, then the law of N, B and K
//! over the four runs. Per case and term: how often the slope's 95 %
//! interval covers the truth, what the law says, and how wide it is.
//!
//! ```sh
//! nice -n 10 cargo run --release -p analysis --example term_law_study -- 200
//! ```
//!
//! The output stage's LSB rounding is off: it adds a white noise of its
//! own, the same at every temperature, which would bend the truth off a
//! log-linear law by about 1 % of the slope.

use rayon::prelude::*;

use allan::noise_terms::analyze_terms_vec;
use analysis::term_law::{At, LAW_TERMS, Law, Reading, Verdict};
use imusim::thermal::Profile;
use imusim::{Simulator, presets};

/// The thesis's constant temperatures, °C.
const TEMPERATURES: [f64; 4] = [34.0, 43.0, 62.0, 82.0];

/// Length of each run, s, and its rate, Hz (the thesis's).
const DURATION_S: f64 = 3600.0;

struct Case {
    name: &'static str,
    /// Growth of every term from 34 to 82 °C: 1.13 is +13 %.
    growth: f64,
}

const CASES: [Case; 2] = [
    Case {
        name: "terms rising 13 % from 34 to 82 °C",
        growth: 1.13,
    },
    Case {
        name: "terms constant",
        growth: 1.0,
    },
];

/// The true slope of ln(term) per °C.
fn true_slope(case: &Case) -> f64 {
    case.growth.ln() / (TEMPERATURES[3] - TEMPERATURES[0])
}

/// The gyro y samples of one run.
fn run(case: &Case, t_c: f64, seed: u64) -> Vec<f64> {
    let mut cfg = presets::preset("mpu9250-thesis").expect("the thesis preset exists");
    cfg.duration_s = DURATION_S;
    cfg.seed = seed;
    cfg.profile = Profile::constant(t_c, 0.05);
    cfg.sensor.quantize = false;
    let s = true_slope(case);
    cfg.gyro.noise_scale = TEMPERATURES
        .iter()
        .map(|&t| [t, (s * (t - TEMPERATURES[0])).exp()])
        .collect();
    let sim = Simulator::new(cfg).expect("a valid configuration");
    let mut y = Vec::new();
    sim.run(|c| {
        y.extend_from_slice(&c.columns[4]);
        Ok(())
    })
    .expect("simulation runs");
    y
}

/// One seed's laws of N, B and K, and each run's readings of them.
fn laws(case: &Case, seed: u64) -> Vec<(Law, Vec<Reading>)> {
    let rate = presets::THESIS_RATE_HZ;
    let terms: Vec<_> = TEMPERATURES
        .iter()
        .enumerate()
        .map(|(i, &t)| {
            let y = run(case, t, 1_000 * seed + i as u64);
            analyze_terms_vec(y, rate, 0.95).expect("the curve").1
        })
        .collect();
    LAW_TERMS
        .iter()
        .map(|&term| {
            let at: Vec<At> = TEMPERATURES
                .iter()
                .zip(&terms)
                .map(|(&t_c, n)| At {
                    t_c,
                    reading: Reading::of(n, term),
                })
                .collect();
            let readings = at.iter().map(|a| a.reading).collect();
            (Law::fit(term, &at, 0.95), readings)
        })
        .collect()
}

fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let seeds: u64 = args.get(1).map_or(200, |s| s.parse().expect("a seed count"));
    for case in &CASES {
        let start = std::time::Instant::now();
        let results: Vec<Vec<(Law, Vec<Reading>)>> =
            (0..seeds).into_par_iter().map(|seed| laws(case, seed)).collect();
        let truth = true_slope(case);
        println!(
            "## {} ({seeds} seeds, {:.0} s; true slope {:.3e} /°C, change {:+.1} %)",
            case.name,
            start.elapsed().as_secs_f64(),
            truth,
            100.0 * (case.growth - 1.0)
        );
        println!(
            "| term | law fitted | 95 % interval covers the truth | rises / falls / not log-linear / no dependence / too few | \
             median change [median interval] | slope sd: median stated / across seeds | bounds left out | widened | \
             seeds with a pair called different |"
        );
        println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- |");
        for (k, term) in LAW_TERMS.iter().enumerate() {
            let laws: Vec<&Law> = results.iter().map(|r| &r[k].0).collect();
            let fits: Vec<_> = laws.iter().filter_map(|l| l.fit).collect();
            let covered = fits
                .iter()
                .filter(|f| f.slope_per_c.lo <= truth && truth <= f.slope_per_c.hi)
                .count();
            let count = |v: Verdict| laws.iter().filter(|l| l.verdict() == v).count();
            let mut change: Vec<f64> = fits.iter().map(|f| 100.0 * f.change.value).collect();
            let mut lo: Vec<f64> = fits.iter().map(|f| 100.0 * f.change.lo).collect();
            let mut hi: Vec<f64> = fits.iter().map(|f| 100.0 * f.change.hi).collect();
            let mut stated: Vec<f64> = fits.iter().map(|f| f.slope_sd).collect();
            let slopes: Vec<f64> = fits.iter().map(|f| f.slope_per_c.value).collect();
            let n = slopes.len() as f64;
            let mean = slopes.iter().sum::<f64>() / n;
            let across = (slopes.iter().map(|s| (s - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
            let bounds: usize = results
                .iter()
                .map(|r| r[k].1.iter().filter(|x| matches!(x, Reading::Bound(_))).count())
                .sum();
            let widened = fits.iter().filter(|f| f.widened).count();
            let pairs = laws
                .iter()
                .filter(|l| l.differences.iter().any(|d| d.significant()))
                .count();
            println!(
                "| {} | {} | {covered} ({:.1} %) | {} / {} / {} / {} / {} | {:+.1} % [{:+.1}, {:+.1}] | {:.2e} / {:.2e} | {bounds} | {widened} | {pairs} |",
                term.symbol(),
                fits.len(),
                100.0 * covered as f64 / fits.len().max(1) as f64,
                count(Verdict::Rises),
                count(Verdict::Falls),
                count(Verdict::NotLogLinear),
                count(Verdict::NoDependence),
                count(Verdict::TooFew),
                median(&mut change),
                median(&mut lo),
                median(&mut hi),
                median(&mut stated),
                across,
            );
        }
        println!();
    }
}
