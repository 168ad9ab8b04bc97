//! How well a compensation holds on a run: the bias left over
//! temperature (1 °C bin means and their spread) and the ADEV minimum per
//! temperature slice, before and after.

use allan::noise_terms::slope_method;

use crate::ThermalError;
use crate::surface::bin_curves;

/// One 1 °C bin: mean temperature, mean value, standard error of the mean.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BinMean {
    /// Mean temperature of the bin's samples, °C.
    pub t: f64,
    /// Mean of the bin's samples.
    pub mean: f64,
    /// Standard error of that mean.
    pub se: f64,
}

/// Bin means of `x` over 1 °C bins holding at least `min_samples` samples.
/// The standard error is that of white samples (0 for a single sample);
/// correlated noise makes it a lower bound.
pub fn bin_means(x: &[f64], t: &[f64], min_samples: usize) -> Vec<BinMean> {
    let mut bins: std::collections::BTreeMap<i64, (f64, f64, f64, usize)> = Default::default();
    for (&v, &tt) in x.iter().zip(t) {
        if v.is_finite() && tt.is_finite() {
            let e = bins.entry(tt.floor() as i64).or_default();
            e.0 += tt;
            e.1 += v;
            e.2 += v * v;
            e.3 += 1;
        }
    }
    bins.values()
        .filter(|b| b.3 >= min_samples.max(1))
        .map(|&(t, s, s2, n)| {
            let nf = n as f64;
            let mean = s / nf;
            let var = ((s2 - s * mean) / (nf - 1.0)).max(0.0);
            BinMean {
                t: t / nf,
                mean,
                se: (var / nf).sqrt(),
            }
        })
        .collect()
}

/// The bias left over temperature: how far the bin means stray from
/// their mean.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spread {
    /// RMS deviation of the bin means from their mean.
    pub rms: f64,
    /// Largest deviation.
    pub max: f64,
}

/// RMS and largest deviation of the bin means from their mean.
pub fn spread(bins: &[BinMean]) -> Spread {
    let mean = level(bins);
    let rms = (bins.iter().map(|b| (b.mean - mean).powi(2)).sum::<f64>() / bins.len().max(1) as f64).sqrt();
    let max = bins.iter().fold(0.0f64, |m, b| m.max((b.mean - mean).abs()));
    Spread { rms, max }
}

/// The mean of the bin means: the reading's level over temperature (for an
/// accelerometer at rest, gravity's share, which a correction must keep).
pub fn level(bins: &[BinMean]) -> f64 {
    bins.iter().map(|b| b.mean).sum::<f64>() / bins.len().max(1) as f64
}

/// The ADEV minimum of one temperature slice.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SliceMinimum {
    /// Mean temperature of the slice, °C.
    pub t_c: f64,
    /// σ_min.
    pub sigma_min: f64,
    /// Its τ, s (NaN where the slice has none).
    pub tau: f64,
}

/// σ_min of each `bin_width_c` slice of the ADEV surface; a run the
/// surface cannot be drawn for has none.
pub fn surface_minima(x: &[f64], t: &[f64], rate_hz: f64, bin_width_c: f64) -> Vec<SliceMinimum> {
    slice_minima(x, t, rate_hz, bin_width_c).unwrap_or_default()
}

/// σ_min of each `bin_width_c` slice, or why the run cannot be sliced so.
/// Only the slope reading of each slice's curve is taken: the noise model
/// that [`crate::surface::surface`] also fits per slice is by far the dearest
/// part of it, and none of it is needed here.
pub fn slice_minima(
    x: &[f64],
    t: &[f64],
    rate_hz: f64,
    bin_width_c: f64,
) -> Result<Vec<SliceMinimum>, ThermalError> {
    let (rows, _) = bin_curves(
        x,
        t,
        rate_hz,
        bin_width_c,
        allan::DEFAULT_CONFIDENCE,
        |_, label, points| {
            slope_method(&points).sigma_min.map(|m| SliceMinimum {
                t_c: label.t_mean_c(),
                sigma_min: m.value,
                tau: m.tau.unwrap_or(f64::NAN),
            })
        },
    )?;
    Ok(rows.into_iter().flatten().collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bins_average_within_a_degree_and_the_spread_is_about_their_mean() {
        // Two bins, 20 °C (values 1 and 3) and 21 °C (5 and 7).
        let t = [20.2, 20.8, 21.1, 21.9];
        let x = [1.0, 3.0, 5.0, 7.0];
        let b = bin_means(&x, &t, 2);
        assert_eq!(b.len(), 2);
        assert!((b[0].t - 20.5).abs() < 1e-12 && (b[0].mean - 2.0).abs() < 1e-12);
        // Sample SD √2, over √2 samples: 1.
        assert!((b[0].se - 1.0).abs() < 1e-12);
        assert_eq!(level(&b), 4.0);
        let s = spread(&b);
        assert!((s.rms - 2.0).abs() < 1e-12 && (s.max - 2.0).abs() < 1e-12);
        assert!(bin_means(&x, &t, 3).is_empty());
    }

    #[test]
    fn slice_minima_are_the_surfaces_minima() {
        // A cooling ramp of white data: the minima read from the curves
        // alone are those of the full surface, slice for slice.
        let n = 40_000;
        let q = 1.0 / 333.87;
        let t: Vec<f64> = (0..n)
            .map(|i| ((60.0 - 30.0 * i as f64 / n as f64) / q).round() * q)
            .collect();
        let x: Vec<f64> = (0..n).map(|i| ((i * 7919) % 101) as f64 - 50.0).collect();
        let got = slice_minima(&x, &t, 100.0, 5.0).unwrap();
        let want: Vec<SliceMinimum> = crate::surface::surface(
            &x,
            &t,
            100.0,
            crate::surface::Slicing::Temperature { bin_width_c: 5.0 },
            allan::DEFAULT_CONFIDENCE,
        )
        .unwrap()
        .iter()
        .filter_map(|r| {
            r.terms.slope.sigma_min.map(|m| SliceMinimum {
                t_c: r.t_mean_c,
                sigma_min: m.value,
                tau: m.tau.unwrap_or(f64::NAN),
            })
        })
        .collect();
        assert!(got.len() >= 6, "{got:?}");
        assert_eq!(got, want);
        assert!(slice_minima(&x, &t, 100.0, 0.0).is_err());
    }
}
