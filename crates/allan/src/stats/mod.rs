//! One module per family of statistics, each computed on a [`PhaseSeries`].
//!
//! Every function takes the series and an averaging factor m (τ = m·τ0) and
//! returns `None` when the series cannot support that m.

mod allan_dev;
mod differences;
mod hadamard;
pub mod htotdev;
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
    use rayon::prelude::*;
    let order = match stat {
        Stat::Oadev => Some((differences::Order::Second, 2.0)),
        Stat::Ohdev => Some((differences::Order::Third, 6.0)),
        _ => None,
    };
    match order {
        Some((order, norm)) if !series.has_gaps() => {
            differences::sum_squared_overlapped_many(series.points(), ms, order)
                .into_iter()
                .zip(ms)
                .map(|((sum, n), &m)| {
                    (n > 0).then(|| {
                        let tau = m as f64 * series.tau0();
                        Estimate {
                            dev: (sum / (norm * n as f64 * tau * tau)).sqrt(),
                            n,
                        }
                    })
                })
                .collect()
        }
        _ => ms.par_iter().map(|&m| compute(stat, series, m)).collect(),
    }
}

/// Computes `stat` at averaging factor m.
pub fn compute(stat: Stat, series: &PhaseSeries, m: usize) -> Option<Estimate> {
    match stat {
        Stat::Adev => adev(series, m),
        Stat::Oadev => oadev(series, m),
        Stat::Mdev => mdev(series, m),
        Stat::Tdev => tdev(series, m),
        Stat::Hdev => hdev(series, m),
        Stat::Ohdev => ohdev(series, m),
        Stat::Totdev => totdev(series, m),
        Stat::Mtotdev => mtotdev::mtotdev(series.points(), m, series.tau0()),
        Stat::Ttotdev => mtotdev::ttotdev(series.points(), m, series.tau0()),
        Stat::Htotdev => htotdev::htotdev(series.points(), m, series.tau0()),
        Stat::Theo1 => theo1::theo1(series.points(), m, series.tau0()),
    }
}
