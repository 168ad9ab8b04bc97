//! Per-τ cost of the `allan` statistics engine, in-process, release build:
//!
//! - the total deviations and Thêo1 at a few averaging factors, as time per
//!   window and unit of m (their cost is O((N − 3m)·m) per τ);
//! - OADEV, MDEV and HDEV at single τ on 10^7 points against one read pass
//!   over them (the memory bandwidth, measured in the same run, on one
//!   thread): the ratio is the statistic's time in memory passes;
//! - `analyze` against the statistic alone on the octave, decade, many and
//!   every-τ grids, in CPU time on one thread, the difference being noise
//!   identification, EDF and intervals.
//!
//! cargo run --release -p allan --example allan_per_tau [N] [grids|passes]
//!
//! N defaults to 10^5 (the grids part runs only up to 2·10^5); `grids`
//! runs that part alone, `ident` times noise identification alone (one
//! call of `allan::noise_id::identify` per τ, OADEV and HDEV, white and
//! random-walk FM, m = 1, 2, 8, 64), `passes` the memory-pass part alone, at the
//! factors listed in `ALLAN_PER_TAU_M` (say `1024,4096,65536`) if set. The rate
//! series is reproducible white noise (white FM) and its running sum
//! (random-walk FM), so the lag-1 ACF, B1 and R(n) paths all run.

use std::time::Instant;

use allan::stats::{htotdev, mtotdev, theo1};
use allan::{DataType, Options, PhaseSeries, Stat, TauSpec, analyze_series, stats, taus};

/// xorshift64 uniform in [−0.5, 0.5): reproducible, no dependency.
fn white(len: usize, seed: u64) -> Vec<f64> {
    let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    (0..len)
        .map(|_| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        })
        .collect()
}

/// Best of `reps` runs of `f`, in seconds.
fn best<T>(reps: usize, mut f: impl FnMut() -> T) -> f64 {
    (0..reps)
        .map(|_| {
            let t0 = Instant::now();
            std::hint::black_box(f());
            t0.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .map(|a| a.parse().expect("N is a positive integer"))
        .unwrap_or(100_000);
    let rate = white(n, 7);
    match std::env::args().nth(2).as_deref() {
        Some("grids") => {
            per_tau_overhead(&rate);
            return;
        }
        Some("passes") => {
            bandwidth_ratios();
            return;
        }
        Some("ident") => {
            identification(&rate);
            return;
        }
        _ => {}
    }
    let series = PhaseSeries::new(&rate, DataType::Freq, 1.0).expect("finite samples");
    let phase = series.points();
    println!("N = {n} rate samples ({} phase points)", phase.len());

    println!("\n-- total deviations and Thêo1, one τ each --");
    println!(
        "{:<8} {:>8} {:>10} {:>14}",
        "stat", "m", "time s", "ns/(window·m)"
    );
    for m in [16usize, 256, 4096] {
        if 3 * m >= phase.len() {
            continue;
        }
        let windows = (phase.len() - 3 * m) as f64;
        let runs: [(&str, f64); 3] = [
            ("mtotdev", best(1, || mtotdev::mtotdev(phase, m, 1.0))),
            ("htotdev", best(1, || htotdev::htotdev(phase, m, 1.0))),
            ("theo1", best(1, || theo1::theo1(phase, m, 1.0))),
        ];
        for (name, t) in runs {
            let per = if name == "theo1" {
                // (N − m)·m/2 terms.
                t * 1e9 / ((phase.len() - m) as f64 * m as f64 / 2.0)
            } else {
                t * 1e9 / (windows * m as f64)
            };
            println!("{name:<8} {m:>8} {t:>10.4} {per:>14.3}");
        }
    }

    bandwidth_ratios();

    if n > 200_000 {
        // Every τ is O(N²) in all: minutes at 10^6 on a small machine.
        println!("\n(analyze with every τ skipped above N = 200000)");
        return;
    }
    per_tau_overhead(&rate);
}

/// CPU time of the calling thread, in seconds: on a shared machine it
/// counts this run's work alone, where wall time counts the neighbours'.
fn thread_cpu_seconds() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec for the whole call.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    assert_eq!(rc, 0, "clock_gettime(CLOCK_THREAD_CPUTIME_ID)");
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

/// Least CPU time of `reps` runs of `f` on this thread.
fn best_cpu<T>(reps: usize, mut f: impl FnMut() -> T) -> f64 {
    (0..reps)
        .map(|_| {
            let t0 = thread_cpu_seconds();
            std::hint::black_box(f());
            thread_cpu_seconds() - t0
        })
        .fold(f64::INFINITY, f64::min)
}

/// `analyze` against the statistic alone on each grid, in CPU time on one
/// thread: the rest is noise identification, EDF and intervals (goal:
/// rest/stat ≤ 0.10).
fn per_tau_overhead(rate: &[f64]) {
    println!("\n-- analyze against the statistic alone, CPU time on one thread --");
    println!(
        "{:<8} {:<7} {:>6} {:>10} {:>10} {:>10} {:>9}",
        "stat", "grid", "taus", "stat s", "curve s", "rest s", "rest/stat"
    );
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("thread pool");
    let grids = [
        ("octave", TauSpec::Octave),
        ("decade", TauSpec::Decade),
        ("many", TauSpec::Many),
        ("all", TauSpec::All),
    ];
    pool.install(|| {
        for (label, data) in [("wfm", rate.to_vec()), ("rwfm", integrate(rate))] {
            let s = PhaseSeries::new(&data, DataType::Freq, 1.0).expect("finite samples");
            for stat in [Stat::Oadev, Stat::Mdev, Stat::Hdev] {
                for (grid_name, grid) in &grids {
                    if *grid_name == "all" && rate.len() > 200_000 {
                        // O(N²) in all: minutes per statistic at 10^6.
                        continue;
                    }
                    let ms = taus::averaging_factors(grid, stat, s.len(), s.tau0());
                    // Short runs repeat more: their minimum needs more draws.
                    let reps = if *grid_name == "all" { 3 } else { 9 };
                    let t_stat = best_cpu(reps, || stats::compute_many(stat, &s, &ms));
                    let opts = Options {
                        stat,
                        taus: grid.clone(),
                        ..Options::default()
                    };
                    let t_curve = best_cpu(reps, || {
                        analyze_series(&s, &opts).expect("the series supports the grid")
                    });
                    let rest = t_curve - t_stat;
                    println!(
                        "{:<8} {grid_name:<7} {:>6} {:>10.4} {:>10.4} {:>10.4} {:>9.3}   ({label})",
                        stat.name(),
                        ms.len(),
                        t_stat,
                        t_curve,
                        rest,
                        rest / t_stat
                    );
                }
            }
        }
    });
}

/// One identification per τ, best of many calls, in µs: what the lag-1
/// ACF costs where it reads its cap of points (m small against N) and
/// beyond.
fn identification(rate: &[f64]) {
    println!("\n-- noise identification, one τ, best of 2000 calls --");
    println!(
        "{:<6} {:<6} {:>6} {:>10} {:>6} {:>4}",
        "noise", "stat", "m", "time µs", "alpha", "d"
    );
    for (label, data) in [("wfm", rate.to_vec()), ("rwfm", integrate(rate))] {
        let s = PhaseSeries::new(&data, DataType::Freq, 1.0).expect("finite samples");
        for stat in [Stat::Oadev, Stat::Hdev] {
            for m in [1usize, 2, 8, 64] {
                let mut id = None;
                let t = best(2000, || {
                    id = Some(allan::noise_id::identify(s.points(), m, stat));
                });
                let id = id.expect("identified");
                println!(
                    "{label:<6} {:<6} {m:>6} {:>10.1} {:>6} {:>4}",
                    stat.name(),
                    t * 1e6,
                    id.alpha,
                    id.differences.map_or("-".to_string(), |d| d.to_string())
                );
            }
        }
    }
}

/// Phase points of the bandwidth section: 80 MB, well beyond any cache.
const PASS_POINTS: usize = 10_000_000;

/// One read pass over `x`, as fast as this machine reads: sixteen lanes,
/// and each cache line asked for 16 KiB ahead. Four lanes and the hardware
/// prefetcher alone, as first written, read 15–20 % slower on a Zen 5 EPYC
/// (about 33 against 36–41 GB/s), so the statistics, which prefetch their
/// leading stream, looked closer to the bus than they are.
fn one_pass(x: &[f64]) -> f64 {
    let (chunks, tail) = x.as_chunks::<16>();
    let mut lanes = [0.0f64; 16];
    for (i, c) in chunks.iter().enumerate() {
        for line in [0, 8] {
            prefetch(x.as_ptr().wrapping_add(16 * i + line + 2048));
        }
        for l in 0..16 {
            lanes[l] += c[l];
        }
    }
    lanes.iter().sum::<f64>() + tail.iter().sum::<f64>()
}

/// A hint to load the cache line at `p`; nothing off x86-64.
#[inline(always)]
fn prefetch(p: *const f64) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: SSE is part of the x86-64 baseline, and the pointer need not
    // be valid (PREFETCHT0 does not trap).
    unsafe {
        std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(p.cast::<i8>())
    };
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
}

/// The O(N) statistics at one τ each against one memory pass over the
/// same phase points, measured in the same run on one thread: the ratio
/// is how many passes' worth of time a τ costs (goal ≤ 1.5).
fn bandwidth_ratios() {
    let factors = pass_factors();
    let rate = white(PASS_POINTS - 1, 11);
    let series = PhaseSeries::new(&rate, DataType::Freq, 1.0).expect("finite samples");
    let phase = series.points();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("thread pool");
    pool.install(|| {
        let pass = best(5, || one_pass(std::hint::black_box(phase)));
        let bytes = std::mem::size_of_val(phase) as f64;
        println!(
            "\n-- O(N) statistics against one memory pass ({} points, {:.1} GB/s on one thread) --",
            phase.len(),
            bytes / pass / 1e9
        );
        println!("{:<8} {:>8} {:>10} {:>14}", "stat", "m", "time s", "passes");
        for stat in [Stat::Oadev, Stat::Mdev, Stat::Hdev] {
            for &m in &factors {
                // The pass and the statistic in turn, five times, best of
                // each: on a shared machine the bandwidth moves with the
                // load, and taken far apart the two would not see the same.
                let (mut t, mut p) = (f64::INFINITY, f64::INFINITY);
                for _ in 0..5 {
                    p = p.min(best(1, || one_pass(std::hint::black_box(phase))));
                    t = t.min(best(1, || stats::compute(stat, &series, m)));
                }
                println!("{:<8} {m:>8} {t:>10.4} {:>14.2}", stat.name(), t / p);
            }
        }
    });
}

/// The averaging factors of the memory-pass part: 1, 16, 256 and 4096, or
/// the comma-separated list in `ALLAN_PER_TAU_M`.
fn pass_factors() -> Vec<usize> {
    match std::env::var("ALLAN_PER_TAU_M") {
        Ok(list) => list
            .split(',')
            .map(|t| match t.trim().parse::<usize>() {
                Ok(m) if m > 0 => m,
                _ => panic!("ALLAN_PER_TAU_M: {t:?} is not a positive averaging factor"),
            })
            .collect(),
        Err(_) => vec![1, 16, 256, 4096],
    }
}

/// Running sum, a random-walk FM rate from a white FM one.
fn integrate(y: &[f64]) -> Vec<f64> {
    let mut acc = 0.0;
    y.iter()
        .map(|v| {
            acc += v;
            acc
        })
        .collect()
}
