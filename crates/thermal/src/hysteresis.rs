//! The difference between the heating and the cooling branch of a channel,
//! reported only where the data show one.
//!
//! Each temperature bin visited both ways gives one difference of the two
//! branches' residuals from the fitted polynomial (so that a bin's two mean
//! temperatures, which differ a little, do not count as hysteresis). The
//! differences' mean and its Student-t 95 % interval, over the bins, are
//! kept when the interval excludes zero. The interval rests on the spread
//! of the differences across bins, not on the samples' white noise, which
//! would understate it wherever the bias wanders slowly.

use serde::{Deserialize, Serialize};

/// Fewest samples each branch of a bin needs for the bin to count.
pub const MIN_BRANCH_SAMPLES: usize = 20;

/// Fewest bins visited both ways for a hysteresis to be judged.
pub const MIN_BINS: usize = 3;

/// The heating branch minus the cooling branch, where the data show a
/// difference.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Hysteresis {
    /// Mean over the bins of heating − cooling, in the channel's unit.
    pub heating_minus_cooling: f64,
    /// Its 95 % interval (Student t over the bins).
    pub interval_95: [f64; 2],
    /// Bins visited both ways.
    pub bins: usize,
    /// The lowest and highest of those bins' temperatures, °C.
    pub t_range_c: [f64; 2],
}

/// One branch of one bin: its key, direction, sample count, mean
/// temperature and residual from the fit.
#[derive(Debug, Clone, Copy)]
pub struct BranchResidual {
    /// The bin (floor of T / width).
    pub bin: i64,
    /// Heating (`true`) or cooling.
    pub heating: bool,
    /// Samples.
    pub n: usize,
    /// Mean temperature, °C.
    pub t: f64,
    /// Bin mean minus the fitted polynomial.
    pub residual: f64,
}

/// The hysteresis of one channel, `None` where no bin is visited both ways
/// by enough samples or the difference is within its interval of zero.
pub fn hysteresis(branches: &[BranchResidual]) -> Option<Hysteresis> {
    use std::collections::BTreeMap;
    // Per (bin, direction): sample-weighted residual over the runs.
    let mut acc: BTreeMap<(i64, bool), (usize, f64, f64)> = BTreeMap::new();
    for b in branches {
        let e = acc.entry((b.bin, b.heating)).or_insert((0, 0.0, 0.0));
        e.0 += b.n;
        e.1 += b.n as f64 * b.residual;
        e.2 += b.n as f64 * b.t;
    }
    let mut diffs = Vec::new();
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for (&(bin, heating), &(n, r, t)) in &acc {
        if !heating || n < MIN_BRANCH_SAMPLES {
            continue;
        }
        if let Some(&(nc, rc, tc)) = acc.get(&(bin, false))
            && nc >= MIN_BRANCH_SAMPLES
        {
            diffs.push(r / n as f64 - rc / nc as f64);
            let t = (t + tc) / (n + nc) as f64;
            lo = lo.min(t);
            hi = hi.max(t);
        }
    }
    let m = diffs.len();
    if m < MIN_BINS {
        return None;
    }
    let mean = diffs.iter().sum::<f64>() / m as f64;
    let var = diffs.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / (m - 1) as f64;
    let half = t_975(m - 1) * (var / m as f64).sqrt();
    let shown = mean.is_finite() && half.is_finite() && mean.abs() > half;
    shown.then_some(Hysteresis {
        heating_minus_cooling: mean,
        interval_95: [mean - half, mean + half],
        bins: m,
        t_range_c: [lo, hi],
    })
}

/// The 97.5 % quantile of Student's t with `df` degrees of freedom
/// (standard tables, e.g. NIST/SEMATECH e-Handbook 1.3.6.7.2).
fn t_975(df: usize) -> f64 {
    const TABLE: [f64; 30] = [
        12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160, 2.145,
        2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048,
        2.045, 2.042,
    ];
    match df {
        0 => f64::INFINITY,
        1..=30 => TABLE[df - 1],
        31..=60 => 2.000,
        61..=120 => 1.980,
        _ => 1.960,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn branches(offset: f64, noise: f64) -> Vec<BranchResidual> {
        (0..10)
            .flat_map(|bin| {
                let wobble = if bin % 2 == 0 { noise } else { -noise };
                [true, false].map(|heating| BranchResidual {
                    bin,
                    heating,
                    n: 500,
                    t: bin as f64 + 0.5,
                    residual: if heating {
                        offset / 2.0 + wobble
                    } else {
                        -offset / 2.0
                    },
                })
            })
            .collect()
    }

    #[test]
    fn a_difference_the_bins_agree_on_is_reported_with_its_interval() {
        let h = hysteresis(&branches(1e-3, 1e-4)).unwrap();
        assert!((h.heating_minus_cooling - 1e-3).abs() < 1e-12);
        assert!(h.interval_95[0] > 0.0 && h.interval_95[0] < 1e-3 && h.interval_95[1] > 1e-3);
        assert_eq!(h.bins, 10);
        assert_eq!(h.t_range_c, [0.5, 9.5]);
    }

    #[test]
    fn no_difference_or_too_few_samples_reports_nothing() {
        assert_eq!(hysteresis(&branches(0.0, 1e-4)), None);
        let mut few = branches(1e-3, 1e-4);
        for b in few.iter_mut().filter(|b| !b.heating) {
            b.n = MIN_BRANCH_SAMPLES - 1;
        }
        assert_eq!(hysteresis(&few), None, "a few cooling samples are not a branch");
        let one_way: Vec<_> = branches(1e-3, 0.0).into_iter().filter(|b| b.heating).collect();
        assert_eq!(hysteresis(&one_way), None);
    }

    #[test]
    fn the_t_quantile_falls_to_the_normal_one() {
        assert_eq!(t_975(1), 12.706);
        assert!(t_975(30) > t_975(200));
        assert_eq!(t_975(1000), 1.96);
    }
}
