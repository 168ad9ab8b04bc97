//! One statistic over a tau grid, with EDF, confidence interval and noise type
//! at every point: what `imutherm adev` prints.

use rayon::prelude::*;

use std::collections::HashMap;

use crate::confidence::{chi2_interval_from, interval_quantiles};
use crate::edf::edf_for;
use crate::noise_id::{self, NoiseId, NoiseIdMethod, Staged};
use crate::phase::PhaseSeries;
use crate::stats::{self, Estimate};
use crate::taus::{self, TauSpec};
use crate::{AllanError, DataType, Stat};

/// Stable32's and imutherm's default confidence level, "68.3 %".
pub const DEFAULT_CONFIDENCE: f64 = 0.683;

/// Smallest number of terms a point may rest on; AllanTools drops n ≤ 1 too.
const MIN_TERMS: usize = 2;

/// What to compute.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    /// The statistic.
    pub stat: Stat,
    /// Whether the samples are rate (frequency) or phase (integrated) data.
    pub data_type: DataType,
    /// Sample rate in Hz (τ0 = 1/rate).
    pub rate_hz: f64,
    /// The tau grid.
    pub taus: TauSpec,
    /// Two-sided confidence level of the interval, in (0, 1).
    pub confidence: f64,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            stat: Stat::Oadev,
            data_type: DataType::Freq,
            rate_hz: 1.0,
            taus: TauSpec::Octave,
            confidence: DEFAULT_CONFIDENCE,
        }
    }
}

/// One point of a stability curve. Serialized as a point of the
/// `imutherm.adev/1` document, whose field order this is.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Point {
    /// τ in seconds.
    pub tau: f64,
    /// Averaging factor, τ = m·τ0 (0.75·m·τ0 for Theo1).
    pub m: usize,
    /// The deviation, in the unit of the rate data (of its integral for
    /// TDEV/TTOTDEV).
    pub dev: f64,
    /// Number of terms in the estimate.
    pub n: usize,
    /// Equivalent degrees of freedom for the identified noise type.
    pub edf: f64,
    /// Lower bound of the confidence interval.
    pub dev_lo: f64,
    /// Upper bound of the confidence interval.
    pub dev_hi: f64,
    /// Power-law exponent α of the rate noise (S_y ∝ f^α) used for the EDF.
    pub alpha: i32,
    /// How α was found.
    pub noise_id: NoiseIdMethod,
}

/// A stability curve: one statistic of one series over a tau grid.
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    /// The statistic.
    pub stat: Stat,
    /// The input's data type.
    pub data_type: DataType,
    /// The sample rate, Hz.
    pub rate_hz: f64,
    /// The confidence level of the intervals.
    pub confidence: f64,
    /// Number of input samples, gaps included.
    pub samples: usize,
    /// Number of NaN (gap) samples in the input, including trimmed edges.
    pub nan_samples: usize,
    /// The points, by increasing τ; taus the data cannot support are absent.
    pub points: Vec<Point>,
}

/// Computes `opts.stat` on `data` over the tau grid.
///
/// Errors when the options are invalid, when the series is too short for any
/// requested tau, or when it has gaps and the statistic cannot skip them.
pub fn analyze(data: &[f64], opts: &Options) -> Result<Curve, AllanError> {
    analyze_vec(crate::phase::copy_with_room(data), opts)
}

/// [`analyze`], taking the samples by value so that they are turned into
/// phase in place: memory stays at the size of the data. Rate data gain one
/// phase point, so a vector built in a [`crate::buffer_for`] its length is
/// not reallocated.
pub fn analyze_vec(data: Vec<f64>, opts: &Options) -> Result<Curve, AllanError> {
    analyze_vec_with_progress(data, opts, &|_| {})
}

/// [`analyze_vec`], reporting the statistic's work as it goes: the calls
/// to `progress` add up to [`crate::work::workload`]'s operations (for
/// data without NaN edges, which are trimmed before the grid is made).
pub fn analyze_vec_with_progress(
    data: Vec<f64>,
    opts: &Options,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Curve, AllanError> {
    let samples = data.len();
    let series = PhaseSeries::from_vec(data, opts.data_type, opts.rate_hz)?;
    let points = analyze_series_with_progress(&series, opts, progress)?;
    Ok(Curve {
        stat: opts.stat,
        data_type: opts.data_type,
        rate_hz: opts.rate_hz,
        confidence: opts.confidence,
        samples,
        nan_samples: series.nan_samples(),
        points,
    })
}

/// Computes `opts.stat` on an already built phase series (its rate and data
/// type are those it was built with; the ones in `opts` are not used). Taus
/// run in parallel.
pub fn analyze_series(series: &PhaseSeries, opts: &Options) -> Result<Vec<Point>, AllanError> {
    analyze_series_with_progress(series, opts, &|_| {})
}

/// [`analyze_series`], reporting the statistic's work as
/// [`analyze_vec_with_progress`] does.
pub fn analyze_series_with_progress(
    series: &PhaseSeries,
    opts: &Options,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<Point>, AllanError> {
    let mut curves =
        analyze_series_grids_with_progress(series, opts, std::slice::from_ref(&opts.taus), progress)?;
    Ok(curves.pop().unwrap_or_default())
}

/// [`analyze_series`] on several tau grids at once (`opts.taus` is not
/// used): the statistic and the noise identification run once per
/// averaging factor of their union, and each grid's points are then made
/// from its own factors alone, exactly as [`analyze_series`] makes them on
/// that grid. One curve per grid, in the order of `grids`.
pub fn analyze_series_grids(
    series: &PhaseSeries,
    opts: &Options,
    grids: &[TauSpec],
) -> Result<Vec<Vec<Point>>, AllanError> {
    analyze_series_grids_with_progress(series, opts, grids, &|_| {})
}

fn analyze_series_grids_with_progress(
    series: &PhaseSeries,
    opts: &Options,
    grids: &[TauSpec],
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<Vec<Point>>, AllanError> {
    let stat = opts.stat;
    if !(opts.confidence > 0.0 && opts.confidence < 1.0) {
        return Err(AllanError::InvalidConfidence(opts.confidence));
    }
    if series.has_gaps() && !stat.supports_gaps() {
        let first = series.first_gap().unwrap_or_default();
        return Err(AllanError::GapsNotSupported {
            stat: stat.name(),
            count: series.nan_samples(),
            first,
        });
    }
    let n_phase = series.len();
    let needed = stat.stop_ratio().max(3);
    if n_phase < needed {
        return Err(AllanError::TooShort {
            stat: stat.name(),
            needed,
            got: n_phase,
        });
    }
    let tau0 = series.tau0();
    let grid_ms: Vec<Vec<usize>> = grids
        .iter()
        .map(|g| taus::averaging_factors(g, stat, n_phase, tau0))
        .collect();
    let mut ms: Vec<usize> = grid_ms.iter().flatten().copied().collect();
    ms.sort_unstable();
    ms.dedup();
    // Noise type is identified on data no gap crosses.
    let clean = series.longest_clean_stretch();
    let n_valid = n_phase.saturating_sub(series.nan_samples() - series.trimmed_samples());

    let estimates = stats::compute_many_with_progress(stat, series, &ms, progress);
    let found: Vec<Option<(Estimate, Staged)>> = ms
        .par_iter()
        .zip(estimates)
        .map(|(&m, est)| {
            let est = est?;
            if est.n < MIN_TERMS || !est.dev.is_finite() {
                return None;
            }
            Some((est, noise_id::identify_finite_staged(clean, m, stat)))
        })
        .collect();
    // Each grid's usable factors, ascending, with the noise type wherever it
    // is known without R(n) under the grid's cap: the cap reads the shorter
    // taus of the grid only.
    let max_abs = std::sync::OnceLock::new();
    let max_abs = || *max_abs.get_or_init(|| largest_magnitude(clean));
    let settled: Vec<Vec<(usize, usize, Option<NoiseId>)>> = grid_ms
        .iter()
        .map(|g| {
            let mut ceiling = None;
            g.iter()
                .filter_map(|&m| {
                    let i = ms.binary_search(&m).ok()?;
                    let (_, staged) = found[i].as_ref()?;
                    let id = match *staged {
                        Staged::Final(id) => {
                            if id.method == NoiseIdMethod::Lag1Acf {
                                ceiling = Some(id.alpha);
                            }
                            Some(id)
                        }
                        Staged::PhaseNoise { b1 } => {
                            noise_id::capped_without_rn(ceiling, clean, m, b1, max_abs)
                        }
                    };
                    Some((m, i, id))
                })
                .collect()
        })
        .collect();
    // R(n), O(N), only where some grid's cap leaves white and flicker PM
    // apart; once per factor however many grids need it.
    let mut need: Vec<usize> = settled
        .iter()
        .flatten()
        .filter(|(_, _, id)| id.is_none())
        .map(|&(_, i, _)| i)
        .collect();
    need.sort_unstable();
    need.dedup();
    let split: Vec<NoiseId> = need
        .par_iter()
        .map(|&i| match found[i] {
            Some((_, Staged::PhaseNoise { b1 })) => noise_id::split_phase_noise(clean, ms[i], b1),
            // Only phase-noise readings are left unsettled.
            _ => NoiseId::assumed(noise_id::DEFAULT_ALPHA),
        })
        .collect();
    settled
        .iter()
        .zip(grids)
        .map(|(g, spec)| {
            let own: Vec<(usize, Estimate, NoiseId)> = g
                .iter()
                .filter_map(|&(m, i, id)| {
                    let (est, _) = found[i]?;
                    let id = match id {
                        Some(id) => id,
                        None => split[need.binary_search(&i).ok()?],
                    };
                    Some((m, est, id))
                })
                .collect();
            let mut ids: Vec<NoiseId> = own.iter().map(|f| f.2).collect();
            noise_id::cap_by_shorter_tau(&mut ids);
            // The interval's two quantiles by EDF, computed once for the
            // points that share it (the same bits as computed afresh).
            let mut quantiles: HashMap<u64, (f64, f64)> = HashMap::new();
            let points: Vec<Point> = own
                .iter()
                .zip(ids)
                .map(|(&(m, ref est, _), id)| {
                    let edf = match edf_for(stat, id.alpha, m, n_valid) {
                        Some(e) if e.is_finite() && e > 0.0 => e,
                        // Outside the EDF model's range (a noise steeper than the
                        // statistic can converge on): fall back to the number of
                        // terms, which is the white-noise, non-overlapped bound.
                        _ => est.n as f64,
                    };
                    let (dev_lo, dev_hi) = chi2_interval_from(est.dev, edf, opts.confidence, |edf, c| {
                        *quantiles
                            .entry(edf.to_bits())
                            .or_insert_with(|| interval_quantiles(edf, c))
                    });
                    Point {
                        tau: taus::tau_of(stat, m, tau0),
                        m,
                        dev: est.dev,
                        n: est.n,
                        edf,
                        dev_lo,
                        dev_hi,
                        alpha: id.alpha,
                        noise_id: id.method,
                    }
                })
                .collect();
            if points.is_empty() {
                let max_m = taus::max_factor(stat, n_phase);
                return Err(AllanError::NoUsableTau {
                    stat: stat.name(),
                    n: n_phase,
                    rate_hz: 1.0 / tau0,
                    max_m,
                    constraint: taus::constraint(stat, spec, tau0, max_m),
                });
            }
            Ok(points)
        })
        .collect()
}

/// The largest |x| of `x`, NaNs ignored (0 for none), as
/// `fold(0.0, |a, v| a.max(v.abs()))` gives it, in eight lanes: that fold is
/// one chain of dependent maxima, and at 10^6 points it took a quarter of
/// the time noise identification spends on an octave grid. The largest of
/// the lanes' largest is the same whatever their order.
fn largest_magnitude(x: &[f64]) -> f64 {
    // `v > a` is false for a NaN v, which is skipped, as `f64::max` does.
    let larger = |a: f64, v: f64| if v > a { v } else { a };
    let (chunks, tail) = x.as_chunks::<8>();
    let mut lanes = [0.0f64; 8];
    for chunk in chunks {
        for l in 0..8 {
            lanes[l] = larger(lanes[l], chunk[l].abs());
        }
    }
    let tail = tail.iter().fold(0.0f64, |a, v| larger(a, v.abs()));
    lanes.iter().fold(tail, |a, &v| larger(a, v))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A reproducible series of `len` samples with `gaps` NaN among them:
    /// white noise (kind 0), its running sum (1), or white noise on a slow
    /// walk (2).
    fn noisy_series(seed: u64, len: usize, kind: usize, gaps: usize) -> Vec<f64> {
        let mut noise = crate::work::uniform(seed | 1);
        let mut next = || noise.next().unwrap() - 0.5;
        let mut acc = 0.0;
        let mut y: Vec<f64> = (0..len)
            .map(|_| match kind {
                0 => next(),
                1 => {
                    acc += next();
                    acc
                }
                _ => {
                    acc += 0.01 * next();
                    acc + next()
                }
            })
            .collect();
        for _ in 0..gaps {
            let at = ((next() + 0.5) * len as f64) as usize % len;
            y[at] = f64::NAN;
        }
        y
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(32))]
        /// Several grids at once give each grid's curve exactly as it alone
        /// gives it: the noise type's cap reads only the grid's own taus.
        #[test]
        fn grids_at_once_are_each_grid_alone(
            seed in proptest::prelude::any::<u64>(),
            len in 8usize..3000,
            gaps in 0usize..20,
            kind in 0usize..3,
        ) {
            let y = noisy_series(seed, len, kind, gaps);
            let grids = [TauSpec::Octave, TauSpec::Many, TauSpec::Decade];
            for stat in [Stat::Oadev, Stat::Mdev, Stat::Hdev] {
                let series = PhaseSeries::new(&y, DataType::Freq, 10.0).unwrap();
                let opts = Options { stat, rate_hz: 10.0, ..Options::default() };
                let together = analyze_series_grids(&series, &opts, &grids);
                // Each grid alone, the first refusal standing for all.
                let alone: Result<Vec<Vec<Point>>, AllanError> = grids
                    .iter()
                    .map(|g| analyze_series(&series, &Options { taus: g.clone(), ..opts.clone() }))
                    .collect();
                match (together, alone) {
                    (Ok(t), Ok(a)) => proptest::prop_assert_eq!(t, a),
                    (Err(t), Err(a)) => proptest::prop_assert_eq!(t.to_string(), a.to_string()),
                    (t, a) => proptest::prop_assert!(false, "{stat:?}: {t:?} against {a:?}"),
                }
            }
        }
    }

    /// The curve's noise types as first computed: the full identification,
    /// R(n) included, at every usable factor, then the cap.
    fn noise_types_in_full(
        series: &PhaseSeries,
        stat: Stat,
        grid: &TauSpec,
    ) -> Vec<(usize, i32, NoiseIdMethod)> {
        let ms = taus::averaging_factors(grid, stat, series.len(), series.tau0());
        let clean = series.longest_clean_stretch();
        let usable: Vec<usize> = ms
            .iter()
            .zip(stats::compute_many(stat, series, &ms))
            .filter(|(_, est)| est.is_some_and(|e| e.n >= MIN_TERMS && e.dev.is_finite()))
            .map(|(&m, _)| m)
            .collect();
        let mut ids: Vec<NoiseId> = usable
            .iter()
            .map(|&m| noise_id::identify_finite(clean, m, stat))
            .collect();
        noise_id::cap_by_shorter_tau(&mut ids);
        usable
            .iter()
            .zip(ids)
            .map(|(&m, id)| (m, id.alpha, id.method))
            .collect()
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(24))]
        /// R(n) left out where the cap makes it moot changes no point: white
        /// PM (phase data), white FM and random-walk FM, with gaps.
        #[test]
        fn noise_types_equal_the_full_identification(
            seed in proptest::prelude::any::<u64>(),
            len in 8usize..1500,
            gaps in 0usize..6,
            kind in 0usize..3,
        ) {
            // White (as phase, white PM; as rates, white FM) or random-walk FM.
            let y = noisy_series(seed, len, [0, 0, 1][kind], gaps);
            let data_type = if kind == 0 { DataType::Phase } else { DataType::Freq };
            let series = PhaseSeries::new(&y, data_type, 10.0).unwrap();
            for stat in [Stat::Oadev, Stat::Mdev, Stat::Hdev, Stat::Adev] {
                for grid in [TauSpec::All, TauSpec::Octave, TauSpec::Many] {
                    let opts = Options { stat, rate_hz: 10.0, taus: grid.clone(), data_type, ..Options::default() };
                    let Ok(points) = analyze_series(&series, &opts) else { continue };
                    let got: Vec<(usize, i32, NoiseIdMethod)> =
                        points.iter().map(|p| (p.m, p.alpha, p.noise_id)).collect();
                    proptest::prop_assert_eq!(got, noise_types_in_full(&series, stat, &grid), "{:?} {:?}", stat, grid);
                }
            }
        }
    }

    /// Quantiles shared by points of equal EDF give each point the interval
    /// computed afresh, bit for bit; with every τ of HDEV most points share.
    #[test]
    fn shared_quantiles_give_each_point_its_own_interval() {
        let y = noisy_series(11, 3000, 0, 0);
        for stat in [Stat::Hdev, Stat::Oadev] {
            let opts = Options {
                stat,
                taus: TauSpec::All,
                confidence: 0.9,
                ..Options::default()
            };
            let points = analyze(&y, &opts).unwrap().points;
            let mut edfs: Vec<u64> = points.iter().map(|p| p.edf.to_bits()).collect();
            edfs.sort_unstable();
            edfs.dedup();
            if stat == Stat::Hdev {
                assert!(
                    edfs.len() * 4 < points.len(),
                    "{} EDFs for {} points",
                    edfs.len(),
                    points.len()
                );
            }
            for p in &points {
                let (lo, hi) = crate::confidence::chi2_interval(p.dev, p.edf, 0.9);
                assert_eq!(
                    (p.dev_lo.to_bits(), p.dev_hi.to_bits()),
                    (lo.to_bits(), hi.to_bits()),
                    "{stat:?} m={}",
                    p.m
                );
            }
        }
    }

    #[test]
    fn a_statistic_that_cannot_skip_gaps_names_the_first_one_in_the_input() {
        let mut y: Vec<f64> = (0..400).map(|i| ((i * 7919) % 13) as f64).collect();
        y[0] = f64::NAN;
        y[57] = f64::NAN;
        y[200] = f64::NAN;
        for data_type in [DataType::Freq, DataType::Phase] {
            let opts = Options {
                stat: Stat::Totdev,
                data_type,
                ..Options::default()
            };
            match analyze(&y, &opts) {
                Err(AllanError::GapsNotSupported { count, first, .. }) => {
                    assert_eq!((count, first), (3, 57), "{data_type:?}");
                }
                other => panic!("{data_type:?}: {other:?}"),
            }
        }
    }

    proptest::proptest! {
        /// The lanes' largest |x| is the serial fold's, NaNs, infinities
        /// and negative zeros included.
        #[test]
        fn largest_magnitude_is_the_folds(
            x in proptest::collection::vec(
                proptest::prop_oneof![
                    proptest::num::f64::ANY,
                    proptest::strategy::Just(f64::NAN),
                    proptest::strategy::Just(-0.0),
                ],
                0..100,
            )
        ) {
            let fold = x.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            proptest::prop_assert_eq!(super::largest_magnitude(&x).to_bits(), fold.to_bits());
        }
    }
}
