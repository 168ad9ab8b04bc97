//! How much work a curve is, known before it starts: the operations each τ
//! costs and the time one operation takes on this machine. The total
//! deviations and Thêo1 are O(N·m) per τ (their module notes say why they
//! stay so), which over a grid reaching N/3 is O(N²): minutes to hours on a
//! long recording. A caller can say so up front, and follow the work with
//! the `*_with_progress` functions, whose reports add up to these counts.

use std::time::Instant;

use crate::analysis::Options;
use crate::phase::PhaseSeries;
use crate::stats;
use crate::taus;
use crate::{DataType, Stat};

/// The operations `stat` takes at averaging factor m on `points` phase
/// points, in the unit its progress is reported in: windows × m for
/// MTOTDEV, TTOTDEV and HTOTDEV (m ≥ 2), terms of the double sum for Thêo1,
/// and the points for every O(N) statistic. Zero where the series cannot
/// support m.
pub fn operations(stat: Stat, points: usize, m: usize) -> u64 {
    let (n, m64) = (points as u64, m as u64);
    match stat {
        Stat::Mtotdev | Stat::Ttotdev => (n + 1).saturating_sub(3 * m64) * m64,
        Stat::Htotdev if m >= 2 => n.saturating_sub(3 * m64) * m64,
        Stat::Theo1 => n.saturating_sub(m64) * (m64 / 2),
        _ => n,
    }
}

/// The work of one curve, before it is computed.
#[derive(Debug, Clone, PartialEq)]
pub struct Workload {
    /// The averaging factors of the grid.
    pub factors: Vec<usize>,
    /// Operations over the whole grid (see [`operations`]).
    pub operations: u64,
}

/// The work `opts` asks for on `samples` input samples (rate samples give
/// one phase point more): the same grid [`crate::analyze`] computes.
pub fn workload(samples: usize, opts: &Options) -> Workload {
    let points = match opts.data_type {
        DataType::Freq => samples + 1,
        DataType::Phase => samples,
    };
    let tau0 = 1.0 / opts.rate_hz;
    let factors = taus::averaging_factors(&opts.taus, opts.stat, points, tau0);
    let operations = factors.iter().map(|&m| operations(opts.stat, points, m)).sum();
    Workload { factors, operations }
}

/// Estimates above this many seconds are announced before the work starts.
pub const ANNOUNCE_SECONDS: f64 = 3.0;

/// The wall time `operations` of `stat` should take on `cores` cores, from
/// one operation's time measured here and now.
pub fn estimated_seconds(stat: Stat, operations: u64, cores: usize) -> f64 {
    operations as f64 * seconds_per_operation(stat) / cores.max(1) as f64
}

/// What to say before a long computation (the total deviations and Thêo1
/// are O(N·m) per τ, so O(N²) over a grid), estimated to take `seconds`
/// on `cores`: `None` for a short one. The command line and Python say
/// the same.
pub fn long_run_note(stat: Stat, operations: u64, seconds: f64, cores: usize) -> Option<String> {
    (seconds > ANNOUNCE_SECONDS).then(|| {
        let time = match seconds {
            s if s < 120.0 => format!("{s:.0} s"),
            s if s < 7200.0 => format!("{:.0} min", s / 60.0),
            s => format!("{:.1} h", s / 3600.0),
        };
        format!(
            "{stat} will take about {time} on {} cores ({operations:.3e} operations); \
             its cost grows with N·m per τ",
            cores.max(1),
            operations = operations as f64
        )
    })
}

/// Seconds one operation of `stat` takes on one core of this machine,
/// measured on the spot (best of three runs of a few milliseconds on a
/// synthetic series), so that an estimate holds on any hardware.
pub fn seconds_per_operation(stat: Stat) -> f64 {
    const POINTS: usize = 20_000;
    const M: usize = 32;
    // Every statistic accepts a random walk.
    let phase = random_walk(POINTS, 1);
    let Ok(series) = PhaseSeries::new(&phase, DataType::Phase, 1.0) else {
        return f64::NAN;
    };
    let ops = operations(stat, POINTS, M) as f64;
    (0..3)
        .map(|_| {
            let t0 = Instant::now();
            std::hint::black_box(stats::compute(stat, &series, M));
            t0.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
        / ops
}

/// Reproducible uniform samples in [0, 1): xorshift64 (Marsaglia,
/// "Xorshift RNGs", J. Stat. Softw. 8(14), 2003, shifts 13, 7, 17) from
/// `state` (which must not be 0), the top 53 bits of each state. The fixed
/// noise of imutherm's tests and timings.
pub fn uniform(mut state: u64) -> impl Iterator<Item = f64> {
    std::iter::repeat_with(move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    })
}

/// A reproducible random walk of `len` points: [`uniform`] steps less 0.5,
/// from a state spread from `seed`.
pub(crate) fn random_walk(len: usize, seed: u64) -> Vec<f64> {
    let mut acc = 0.0;
    uniform(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
        .take(len)
        .map(|u| {
            acc += u - 0.5;
            acc
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::TauSpec;
    use std::sync::atomic::{AtomicU64, Ordering};

    fn walk(len: usize) -> Vec<f64> {
        let mut acc = 0.0;
        (0..len)
            .map(|i| {
                acc += ((i * 7919) % 101) as f64 / 101.0 - 0.5;
                acc
            })
            .collect()
    }

    #[test]
    fn progress_adds_up_to_the_operations_counted_up_front() {
        let phase = walk(3001);
        for stat in [
            Stat::Mtotdev,
            Stat::Ttotdev,
            Stat::Htotdev,
            Stat::Theo1,
            Stat::Oadev,
            Stat::Mdev,
            Stat::Hdev,
            Stat::Totdev,
        ] {
            let opts = Options {
                stat,
                data_type: DataType::Phase,
                taus: TauSpec::Octave,
                ..Options::default()
            };
            let load = workload(phase.len(), &opts);
            let series = PhaseSeries::new(&phase, DataType::Phase, 1.0).unwrap();
            let done = AtomicU64::new(0);
            let calls = AtomicU64::new(0);
            let report = |ops: u64| {
                done.fetch_add(ops, Ordering::Relaxed);
                calls.fetch_add(1, Ordering::Relaxed);
            };
            let with = stats::compute_many_with_progress(stat, &series, &load.factors, &report);
            let without = stats::compute_many(stat, &series, &load.factors);
            assert_eq!(with, without, "{stat:?}");
            assert_eq!(done.load(Ordering::Relaxed), load.operations, "{stat:?}");
            assert!(calls.load(Ordering::Relaxed) >= 1, "{stat:?}");
        }
    }

    #[test]
    fn the_quadratic_statistics_count_windows_times_m() {
        // MTOT at N = 1000, m = 10: 971 windows of 3m points, × m.
        assert_eq!(operations(Stat::Mtotdev, 1000, 10), 971 * 10);
        // HTOT: N − 3m rate windows; Thêo1: (N − m)·m/2 terms.
        assert_eq!(operations(Stat::Htotdev, 1000, 10), 970 * 10);
        assert_eq!(operations(Stat::Theo1, 1000, 10), 990 * 5);
        assert_eq!(operations(Stat::Mtotdev, 10, 4), 0);
        let s = seconds_per_operation(Stat::Mtotdev);
        assert!(s > 0.0 && s < 1e-6, "{s}");
    }
}
