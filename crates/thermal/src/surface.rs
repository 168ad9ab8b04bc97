//! The Allan deviation over temperature — the thesis's "3D ADEV": one
//! overlapping ADEV curve per temperature bin or per sliding time window,
//! with the noise terms of each.
//!
//! A temperature bin keeps the samples taken while the temperature was in
//! it; everything else becomes a gap, so terms never join stretches from
//! different visits to the bin (the engine skips terms that cross a gap), and
//! a τ is kept only where enough contiguous data support it.

use rayon::prelude::*;

use allan::noise_terms::{NoiseTerms, identify};
use allan::{Options, Point, Stat, TauSpec};

use crate::ThermalError;

/// How the recording is cut.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Slicing {
    /// Bins of this width in °C.
    Temperature {
        /// Bin width, °C.
        bin_width_c: f64,
    },
    /// Sliding windows (dynamic Allan variance).
    Time {
        /// Window length, s.
        window_s: f64,
        /// Step between windows, s.
        step_s: f64,
    },
}

/// One slice of the surface.
#[derive(Debug, Clone)]
pub struct SurfaceRow {
    /// Lower edge of the bin (°C) or start of the window (s).
    pub start: f64,
    /// Upper edge of the bin (°C) or end of the window (s).
    pub end: f64,
    /// Mean temperature of the samples used, °C.
    pub t_mean_c: f64,
    /// Temperature change over the slice (last − first sample), °C.
    pub t_change_c: f64,
    /// Samples used.
    pub samples: usize,
    /// The OADEV curve.
    pub points: Vec<Point>,
    /// Its noise terms.
    pub terms: NoiseTerms,
}

/// Fewest samples a slice must hold to be analysed.
pub const MIN_SLICE_SAMPLES: usize = 64;

/// The ADEV surface of `data` (rate samples at `rate_hz`) against the
/// temperature `temp` (same length), sliced as asked.
pub fn surface(
    data: &[f64],
    temp: &[f64],
    rate_hz: f64,
    slicing: Slicing,
    confidence: f64,
) -> Result<Vec<SurfaceRow>, ThermalError> {
    if data.len() != temp.len() {
        return Err(ThermalError::Invalid(format!(
            "{} samples but {} temperatures",
            data.len(),
            temp.len()
        )));
    }
    let opts = Options {
        stat: Stat::Oadev,
        data_type: allan::DataType::Freq,
        rate_hz,
        taus: TauSpec::Octave,
        confidence,
    };
    let analyse = |series: Vec<f64>, t: &[f64], start: f64, end: f64| -> Option<SurfaceRow> {
        let used: Vec<f64> = series
            .iter()
            .zip(t)
            .filter(|(v, _)| !v.is_nan())
            .map(|(_, &t)| t)
            .collect();
        if used.len() < MIN_SLICE_SAMPLES {
            return None;
        }
        let t_mean_c = used.iter().sum::<f64>() / used.len() as f64;
        let t_change_c = used.last().copied().unwrap_or(0.0) - used.first().copied().unwrap_or(0.0);
        let samples = used.len();
        let curve = allan::analyze_vec(series, &opts).ok()?;
        let terms = identify(&curve.points, &curve.points, confidence);
        Some(SurfaceRow {
            start,
            end,
            t_mean_c,
            t_change_c,
            samples,
            points: curve.points,
            terms,
        })
    };
    match slicing {
        Slicing::Temperature { bin_width_c } => {
            if !(bin_width_c.is_finite() && bin_width_c > 0.0) {
                return Err(ThermalError::Invalid(format!(
                    "bin width {bin_width_c} °C must be positive"
                )));
            }
            let (lo, hi) = temp
                .iter()
                .filter(|t| t.is_finite())
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &t| {
                    (a.min(t), b.max(t))
                });
            if !lo.is_finite() {
                return Err(ThermalError::NoTemperature);
            }
            let first = (lo / bin_width_c).floor() as i64;
            let last = (hi / bin_width_c).floor() as i64;
            Ok((first..=last)
                .into_par_iter()
                .filter_map(|k| {
                    let (a, b) = (k as f64 * bin_width_c, (k + 1) as f64 * bin_width_c);
                    let series: Vec<f64> = data
                        .iter()
                        .zip(temp)
                        .map(|(&v, &t)| if t >= a && t < b { v } else { f64::NAN })
                        .collect();
                    analyse(series, temp, a, b)
                })
                .collect())
        }
        Slicing::Time { window_s, step_s } => {
            if !(window_s > 0.0 && step_s > 0.0 && window_s.is_finite() && step_s.is_finite()) {
                return Err(ThermalError::Invalid(format!(
                    "window {window_s} s and step {step_s} s must be positive"
                )));
            }
            let w = (window_s * rate_hz).round() as usize;
            let s = ((step_s * rate_hz).round() as usize).max(1);
            if w < MIN_SLICE_SAMPLES || w > data.len() {
                return Err(ThermalError::Invalid(format!(
                    "a window of {window_s} s holds {w} samples; it must hold at least {MIN_SLICE_SAMPLES} and at most the {} of the recording",
                    data.len()
                )));
            }
            let starts: Vec<usize> = (0..=data.len() - w).step_by(s).collect();
            Ok(starts
                .into_par_iter()
                .filter_map(|i| {
                    analyse(
                        data[i..i + w].to_vec(),
                        &temp[i..i + w],
                        i as f64 / rate_hz,
                        (i + w) as f64 / rate_hz,
                    )
                })
                .collect())
        }
    }
}
