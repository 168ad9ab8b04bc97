//! One noise model's cost, in-process, release build: the octave OADEV of
//! one column of a text file of samples (one sample per line, or the
//! comma-separated column given), then `allan::noise_model::estimate` on it
//! `REPS` times, on one thread; prints the process's CPU time per model
//! (the least of the repetitions) and the model (its Debug form, for
//! comparing two builds byte for byte).
//!
//! cargo run --release -p allan --example noise_model_cost -- FILE RATE_HZ [COLUMN] [REPS]

use allan::noise_model::estimate;
use allan::{Options, Stat, TauSpec, analyze};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let file = args.get(1).expect("a file of samples");
    let rate_hz: f64 = args.get(2).map_or(100.0, |s| s.parse().expect("a rate in Hz"));
    let column: usize = args.get(3).map_or(0, |s| s.parse().expect("a column index"));
    let reps: usize = args.get(4).map_or(3, |s| s.parse().expect("a repetition count"));
    let text = std::fs::read_to_string(file).expect("the samples");
    let y: Vec<f64> = text
        .lines()
        .filter_map(|l| l.split(',').nth(column)?.trim().parse().ok())
        .collect();
    let opts = Options {
        stat: Stat::Oadev,
        taus: TauSpec::Octave,
        confidence: 0.95,
        rate_hz,
        ..Options::default()
    };
    let curve = analyze(&y, &opts).expect("the curve");
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a pool");
    let mut best = f64::INFINITY;
    let mut model = None;
    for _ in 0..reps {
        let start = cpu_seconds();
        let m = pool.install(|| estimate(&curve.points, 0.95));
        best = best.min(cpu_seconds() - start);
        model = Some(m);
    }
    println!("{} samples, {} points", y.len(), curve.points.len());
    println!("{model:#?}");
    println!("best of {reps}: {:.1} ms of CPU per model", best * 1e3);
}

/// The process's CPU time, s (user + system): the machine may be shared.
fn cpu_seconds() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes one timespec into the value passed.
    unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut ts) };
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}
