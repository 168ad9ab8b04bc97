//! # allan — Allan-family stability statistics
//!
//! The numerical heart of imutherm: ADEV, OADEV, MDEV, TDEV, HDEV, OHDEV,
//! TOTDEV, MTOTDEV, TTOTDEV, HTOTDEV and Theo1 on evenly spaced samples, with
//! tau grids, equivalent degrees of freedom (Greenhall & Riley), power-law
//! noise identification (lag-1 autocorrelation, Riley & Greenhall 2004) and
//! chi-squared confidence intervals. Results reproduce NIST SP 1065 Tables 30
//! and 31, Stable32 and AllanTools.
//!
//! **What it is not:** it knows nothing of files, IMUs, units or temperature.
//! It takes a `&[f64]` and a sample rate; reading recordings lives in the
//! `imu` crate, noise-term identification on top of these curves in later
//! modules, printing in the `imutherm` binary.
//!
//! Every statistic is computed on phase (integrated) data: rate samples
//! (`DataType::Freq`, an IMU's output and the default) are integrated after
//! removing their mean, N rate samples giving N+1 phase points. Each tau costs
//! one O(N) pass; taus run in parallel. NaN samples are gaps: ADEV, OADEV,
//! MDEV, TDEV, HDEV and OHDEV skip the terms that cross them; the total
//! statistics refuse gapped data with an error.
//!
//! ```
//! use allan::{analyze, Options, Stat, TauSpec};
//!
//! // Riley's 9-point test set (NIST SP 1065 Table 30).
//! let y = [892.0, 809.0, 823.0, 798.0, 671.0, 644.0, 883.0, 903.0, 677.0];
//! let opts = Options { stat: Stat::Adev, taus: TauSpec::Octave, ..Options::default() };
//! let curve = analyze(&y, &opts).unwrap();
//! assert!((curve.points[0].dev - 91.22945).abs() < 1e-5);
//! assert_eq!(curve.points[1].tau, 2.0);
//! ```

mod analysis;
mod decimate;
mod error;
mod lanes;
mod phase;
mod prefetch;
mod stat;

pub mod confidence;
pub mod edf;
pub mod noise_id;
pub mod noise_model;
pub mod noise_terms;
pub mod stats;
pub mod taus;
pub mod work;

pub use analysis::{
    Curve, DEFAULT_CONFIDENCE, Options, Point, analyze, analyze_series, analyze_series_grids,
    analyze_series_with_progress, analyze_vec, analyze_vec_with_progress,
};
pub use error::AllanError;
pub use noise_id::NoiseIdMethod;
pub use phase::{PhaseSeries, buffer_for};
pub use stat::{DataType, Stat};
pub use taus::TauSpec;
