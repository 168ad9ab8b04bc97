//! Navigation from many start points of one recording, and the error
//! statistics over them at each time since alignment.

use rayon::prelude::*;

use crate::InsError;
use crate::strapdown::{ImuData, NavOptions, StaticError, align_samples, navigate_window};

/// The times since alignment imutherm reports, s, before the horizon: to
/// two minutes, where a MEMS IMU is still of use, then on to an hour, past
/// the Schuler loop's turn (1/ω_s = 13 min).
pub const STANDARD_TIMES_S: [f64; 9] = [1.0, 10.0, 30.0, 60.0, 120.0, 300.0, 600.0, 1200.0, 1800.0];

/// The standard times up to `horizon_s`, and the horizon itself, ascending.
pub fn report_times(horizon_s: f64) -> Vec<f64> {
    let mut t: Vec<f64> = STANDARD_TIMES_S
        .iter()
        .copied()
        .filter(|&t| t < horizon_s)
        .collect();
    t.push(horizon_s);
    t
}

/// RMS, median and 95th percentile of one error over the windows.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Spread {
    /// Root mean square over the windows.
    pub rms: f64,
    /// Median.
    pub p50: f64,
    /// 95th percentile.
    pub p95: f64,
}

impl Spread {
    /// Of `values` (non-empty); percentiles interpolate linearly between
    /// order statistics (Hyndman & Fan's type 7, numpy's default).
    pub fn of(values: &mut [f64]) -> Spread {
        if values.is_empty() {
            return Spread::default();
        }
        values.sort_by(f64::total_cmp);
        let rms = (values.iter().map(|v| v * v).sum::<f64>() / values.len() as f64).sqrt();
        Spread {
            rms,
            p50: percentile(values, 0.5),
            p95: percentile(values, 0.95),
        }
    }

    /// Every figure times `k` (a change of unit).
    pub fn scaled(self, k: f64) -> Spread {
        Spread {
            rms: self.rms * k,
            p50: self.p50 * k,
            p95: self.p95 * k,
        }
    }
}

fn percentile(sorted: &[f64], p: f64) -> f64 {
    let h = (sorted.len() - 1) as f64 * p;
    let (lo, frac) = (h.floor() as usize, h - h.floor());
    match sorted.get(lo + 1) {
        Some(&hi) => sorted[lo] + frac * (hi - sorted[lo]),
        None => sorted[lo],
    }
}

/// The 95 % confidence interval of the rms of `values`, from independent
/// draws (the runs of a Monte Carlo, not overlapping windows): the mean of
/// the squares ± 1.96 standard errors, its square roots. Empty: (0, 0).
pub fn rms_interval_95(values: &[f64]) -> [f64; 2] {
    let n = values.len() as f64;
    if values.len() < 2 {
        let v = values.first().map_or(0.0, |v| v.abs());
        return [v, v];
    }
    let mean = values.iter().map(|v| v * v).sum::<f64>() / n;
    let var = values.iter().map(|v| (v * v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    let half = 1.96 * (var / n).sqrt();
    [(mean - half).max(0.0).sqrt(), (mean + half).sqrt()]
}

/// The errors at one time since alignment, over the windows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurvePoint {
    /// Time since alignment, s.
    pub t_s: f64,
    /// Horizontal position error (distance from the start), m.
    pub horizontal_position_m: Spread,
    /// Horizontal velocity error, m/s.
    pub horizontal_velocity_m_s: Spread,
    /// Height error, m.
    pub vertical_position_m: Spread,
    /// Tilt error (roll and pitch together), rad.
    pub tilt_rad: Spread,
    /// Heading error, rad.
    pub heading_rad: Spread,
}

/// The error growth of a recording over its windows.
#[derive(Debug, Clone, PartialEq)]
pub struct Drift {
    /// Windows navigated.
    pub windows: usize,
    /// Windows left out because they crossed a gap.
    pub windows_with_gaps: usize,
    /// One point per time asked for.
    pub curve: Vec<CurvePoint>,
}

/// Navigates one window every `every_s` seconds, each aligned on its own
/// first `opts.align_s` seconds and run for the largest of `times_s`, and
/// gathers the errors at each time. Windows run in parallel.
pub fn drift_over_windows(
    imu: &ImuData,
    opts: &NavOptions,
    every_s: f64,
    times_s: &[f64],
) -> Result<Drift, InsError> {
    opts.validate()?;
    if !(imu.rate_hz.is_finite() && imu.rate_hz > 0.0) {
        return Err(InsError::Invalid(format!(
            "sample rate {} Hz: must be positive",
            imu.rate_hz
        )));
    }
    if !(every_s.is_finite() && every_s > 0.0) {
        return Err(InsError::Invalid(format!(
            "window step {every_s} s: must be a positive number of seconds"
        )));
    }
    let mut times: Vec<f64> = times_s.to_vec();
    if times.iter().any(|t| !(t.is_finite() && *t > 0.0)) || times.is_empty() {
        return Err(InsError::Invalid(
            "times since alignment must be positive numbers of seconds".into(),
        ));
    }
    times.sort_by(f64::total_cmp);
    let horizon_s = times[times.len() - 1];
    let span = align_samples(opts.align_s, imu.rate_hz) + (horizon_s * imu.rate_hz).round() as usize;
    let n = imu.len();
    if span > n {
        return Err(InsError::TooShort {
            needed_s: span as f64 / imu.rate_hz,
            align_s: opts.align_s,
            horizon_s,
            have_s: n as f64 / imu.rate_hz,
        });
    }
    let step = ((every_s * imu.rate_hz).round() as usize).max(1);
    let starts: Vec<usize> = (0..=n - span).step_by(step).collect();
    let results: Vec<Option<Vec<StaticError>>> = starts
        .par_iter()
        .map(|&s| navigate_window(imu, s, opts, &times))
        .collect();
    let total = results.len();
    let runs: Vec<Vec<StaticError>> = results.into_iter().flatten().collect();
    if runs.is_empty() {
        return Err(InsError::NoWindow);
    }
    Ok(Drift {
        windows: runs.len(),
        windows_with_gaps: total - runs.len(),
        curve: curve_of(&runs, &times),
    })
}

/// The spreads at each time of a set of runs (each with one error per time).
pub fn curve_of(runs: &[Vec<StaticError>], times: &[f64]) -> Vec<CurvePoint> {
    (0..times.len())
        .map(|j| {
            let col = |f: fn(&StaticError) -> f64| -> Spread {
                let mut v: Vec<f64> = runs.iter().map(|r| f(&r[j])).collect();
                Spread::of(&mut v)
            };
            CurvePoint {
                t_s: times[j],
                horizontal_position_m: col(|e| e.horizontal_position_m),
                horizontal_velocity_m_s: col(|e| e.horizontal_velocity_m_s),
                vertical_position_m: col(|e| e.vertical_position_m),
                tilt_rad: col(|e| e.tilt_rad),
                heading_rad: col(|e| e.heading_rad),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_interpolate_as_numpy_does() {
        // numpy.percentile([1, 2, 3, 4, 10], [50, 95]) = [3.0, 8.8].
        let mut v = vec![10.0, 2.0, 4.0, 1.0, 3.0];
        let s = Spread::of(&mut v);
        assert_eq!(s.p50, 3.0);
        assert!((s.p95 - 8.8).abs() < 1e-12);
        assert!((s.rms - (130.0f64 / 5.0).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn the_rms_interval_is_the_mean_square_s_by_hand() {
        // Squares 1, 4, 9, 16: mean 7.5, sample variance 129/3 = 43,
        // standard error √(43/4); 7.5 ± 1.96·3.2787.
        let [lo, hi] = rms_interval_95(&[1.0, -2.0, 3.0, 4.0]);
        let half = 1.96 * (43.0f64 / 4.0).sqrt();
        assert!((lo - (7.5 - half).sqrt()).abs() < 1e-12, "{lo}");
        assert!((hi - (7.5 + half).sqrt()).abs() < 1e-12, "{hi}");
    }

    #[test]
    fn report_times_stop_at_the_horizon() {
        assert_eq!(report_times(45.0), vec![1.0, 10.0, 30.0, 45.0]);
        assert_eq!(report_times(120.0), vec![1.0, 10.0, 30.0, 60.0, 120.0]);
        assert_eq!(report_times(300.0), vec![1.0, 10.0, 30.0, 60.0, 120.0, 300.0]);
        assert_eq!(
            report_times(3600.0),
            vec![1.0, 10.0, 30.0, 60.0, 120.0, 300.0, 600.0, 1200.0, 1800.0, 3600.0]
        );
    }
}
