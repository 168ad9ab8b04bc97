//! One module per family of statistics, each computed on a [`PhaseSeries`].
//!
//! Every function takes the series and an averaging factor m (τ = m·τ0) and
//! returns `None` when the series cannot support that m.

mod allan_dev;
mod differences;
mod hadamard;
pub mod htotdev;
mod mdev_scan;
mod modified;
pub mod mtotdev;
pub mod theo1;
mod total;

pub use allan_dev::{adev, oadev};
pub use hadamard::{hdev, ohdev};
pub use modified::{mdev, tdev};
pub use total::totdev;

use crate::Stat;
use crate::phase::PhaseSeries;

/// A deviation estimated at one averaging factor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// The deviation (square root of the variance), in the unit of the rate
    /// data (or of its integral for TDEV/TTOTDEV).
    pub dev: f64,
    /// The number of terms summed (as AllanTools and Stable32 report it).
    pub n: usize,
}

/// Computes `stat` at every averaging factor of `ms` (each `None` where the
/// series cannot support it). OADEV and OHDEV on gap-free data take one
/// blocked sweep for all factors; everything else runs factor by factor in
/// parallel.
pub fn compute_many(stat: Stat, series: &PhaseSeries, ms: &[usize]) -> Vec<Option<Estimate>> {
    compute_many_with_progress(stat, series, ms, &|_| {})
}

/// [`compute_many`], reporting its work as it goes: the calls to
/// `progress` add up to [`crate::work::operations`] summed over `ms` (the
/// O(N·m) statistics report every block of windows; the others each
/// factor, or the whole sweep, as it ends).
pub fn compute_many_with_progress(
    stat: Stat,
    series: &PhaseSeries,
    ms: &[usize],
    progress: &(dyn Fn(u64) + Sync),
) -> Vec<Option<Estimate>> {
    use rayon::prelude::*;
    let order = match stat {
        Stat::Oadev => Some(differences::Order::Second),
        Stat::Ohdev => Some(differences::Order::Third),
        _ => None,
    };
    match order {
        Some(order) if !series.has_gaps() => {
            let sums = differences::sum_squared_overlapped_many(series.points(), ms, order);
            progress(
                ms.iter()
                    .map(|&m| crate::work::operations(stat, series.len(), m))
                    .sum(),
            );
            sums.into_iter()
                .zip(ms)
                .map(|(sum, &m)| order.deviation(sum, m, series.tau0()))
                .collect()
        }
        _ => ms
            .par_iter()
            .map(|&m| compute_with_progress(stat, series, m, progress))
            .collect(),
    }
}

/// Computes `stat` at averaging factor m.
pub fn compute(stat: Stat, series: &PhaseSeries, m: usize) -> Option<Estimate> {
    compute_with_progress(stat, series, m, &|_| {})
}

/// [`compute`], reporting its work as [`compute_many_with_progress`] does.
pub fn compute_with_progress(
    stat: Stat,
    series: &PhaseSeries,
    m: usize,
    progress: &(dyn Fn(u64) + Sync),
) -> Option<Estimate> {
    let (points, tau0) = (series.points(), series.tau0());
    let linear = |e: Option<Estimate>| {
        progress(crate::work::operations(stat, series.len(), m));
        e
    };
    match stat {
        Stat::Adev => linear(adev(series, m)),
        Stat::Oadev => linear(oadev(series, m)),
        Stat::Mdev => linear(mdev(series, m)),
        Stat::Tdev => linear(tdev(series, m)),
        Stat::Hdev => linear(hdev(series, m)),
        Stat::Ohdev => linear(ohdev(series, m)),
        Stat::Totdev => linear(totdev(series, m)),
        Stat::Mtotdev => mtotdev::mtotdev_with_progress(points, m, tau0, progress),
        Stat::Ttotdev => mtotdev::ttotdev_with_progress(points, m, tau0, progress),
        Stat::Htotdev => htotdev::htotdev_with_progress(points, m, tau0, progress),
        Stat::Theo1 => theo1::theo1_with_progress(points, m, tau0, progress),
    }
}
