//! How much each temperature bin's mean is worth: the inverse of its
//! variance, the white noise's σ²/n plus a floor τ² shared by every bin.
//!
//! The floor is what white noise does not explain: the bias wandering
//! (bias instability, random walk), which averaging over more samples does
//! not beat, and whatever the polynomial cannot follow. Where it is zero,
//! bins weigh as their sample counts, as a least-squares fit over the
//! samples themselves would; where it dominates, every bin weighs the same,
//! so the slow end of a cooling curve does not outweigh the rest. τ² is the
//! Paule–Mandel estimate (Paule & Mandel, J. Res. NBS 87, 377 (1982)): the
//! value at which the weighted residuals' sum of squares equals its degrees
//! of freedom.
//!
//! Under white noise alone that sum is χ² with its degrees of freedom, and
//! exceeds them by chance about half the time: an unguarded estimate would
//! then flatten the weights of a run that needs none, and the fit would
//! lose the efficiency of least squares over the samples. So the floor is
//! only estimated where the sum exceeds the χ² test's 99th percentile, the
//! usual heterogeneity test before a random-effects weight (Cochran's Q).

/// Bisection steps on log τ²: far below any noise figure's precision.
const STEPS: usize = 60;

/// The standard normal's 99th percentile: the level of the χ² test.
const Z_99: f64 = 2.326_347_874_040_841;

/// χ²'s 99th percentile with `dof` degrees of freedom, by Wilson &
/// Hilferty's cube-root normal approximation (PNAS 17, 684 (1931)), within
/// a fraction of a percent from a few degrees of freedom up.
fn chi2_99(dof: f64) -> f64 {
    let a = 2.0 / (9.0 * dof);
    dof * (1.0 - a + Z_99 * a.sqrt()).powi(3)
}

/// τ² for bins whose means have white variance `v` (σ²/n each), given the
/// residuals of a fit of `params` coefficients with weights 1/(v + τ²).
/// Zero where white noise explains the scatter, or where there are no
/// degrees of freedom to judge it by.
pub fn floor_variance(v: &[f64], params: usize, residuals: impl Fn(&[f64]) -> Option<Vec<f64>>) -> f64 {
    let m = v.len();
    if m <= params || v.iter().any(|x| !x.is_finite() || *x <= 0.0) {
        return 0.0;
    }
    let dof = (m - params) as f64;
    // Q(τ²) − dof, which falls as τ² grows.
    let excess = |tau2: f64| -> Option<f64> {
        let w: Vec<f64> = v.iter().map(|vi| 1.0 / (vi + tau2)).collect();
        let r = residuals(&w)?;
        let q: f64 = r.iter().zip(&w).map(|(r, w)| r * r * w).sum();
        q.is_finite().then_some(q - dof)
    };
    match excess(0.0) {
        Some(e) if e + dof > chi2_99(dof) => {}
        _ => return 0.0,
    }
    // A bracket: from the smallest white variance up until Q falls below
    // its degrees of freedom.
    let mut lo = v.iter().copied().fold(f64::INFINITY, f64::min) * 1e-6;
    let mut hi = lo;
    loop {
        hi *= 10.0;
        match excess(hi) {
            Some(e) if e <= 0.0 => break,
            Some(_) if hi < 1e300 => lo = hi,
            _ => return 0.0,
        }
    }
    for _ in 0..STEPS {
        let mid = (lo * hi).sqrt();
        match excess(mid) {
            Some(e) if e > 0.0 => lo = mid,
            Some(_) => hi = mid,
            None => return 0.0,
        }
    }
    (lo * hi).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Residuals from the weighted mean: the one-parameter fit.
    fn from_mean(x: &[f64]) -> impl Fn(&[f64]) -> Option<Vec<f64>> + '_ {
        move |w| {
            let mean = x.iter().zip(w).map(|(x, w)| x * w).sum::<f64>() / w.iter().sum::<f64>();
            Some(x.iter().map(|x| x - mean).collect())
        }
    }

    #[test]
    fn scatter_the_white_noise_explains_has_no_floor() {
        // Means at ±σ/√n exactly: Q = m·(1 − 1/m)… below m − 1 by a hair.
        let v = vec![1e-6; 40];
        let x: Vec<f64> = (0..40).map(|i| if i % 2 == 0 { 9e-4 } else { -9e-4 }).collect();
        assert_eq!(floor_variance(&v, 1, from_mean(&x)), 0.0);
    }

    #[test]
    fn scatter_beyond_the_white_noise_is_the_floor() {
        // White variance 1e-8 per bin, the bins scattered ±1e-3: the floor
        // makes Q equal its 39 degrees of freedom.
        let v = vec![1e-8; 40];
        let x: Vec<f64> = (0..40).map(|i| if i % 2 == 0 { 1e-3 } else { -1e-3 }).collect();
        let tau2 = floor_variance(&v, 1, from_mean(&x));
        let q: f64 = x.iter().map(|x| x * x / (1e-8 + tau2)).sum();
        assert!((q - 39.0).abs() < 1e-6, "{tau2} {q}");
        assert!((tau2 - 40.0 / 39.0 * 1e-6 + 1e-8).abs() < 1e-12, "{tau2}");
    }

    #[test]
    fn scatter_within_chance_of_white_noise_has_no_floor() {
        // Q = 1.2·dof: above its degrees of freedom, but well inside the
        // spread χ² with 40 degrees of freedom has by chance (99th
        // percentile 63.7).
        let v = vec![1e-6; 41];
        let x: Vec<f64> = (0..41)
            .map(|i| {
                let s = if i % 2 == 0 { 1.0 } else { -1.0 };
                s * (1.2f64 * 1e-6).sqrt()
            })
            .collect();
        assert_eq!(floor_variance(&v, 1, from_mean(&x)), 0.0);
    }

    #[test]
    fn chi2_percentile_matches_the_tables() {
        // χ²_{0.99} from the standard tables (Abramowitz & Stegun, table
        // 26.8): 10 dof 23.209, 30 dof 50.892, 100 dof 135.807.
        for (dof, q) in [(10.0, 23.209), (30.0, 50.892), (100.0, 135.807)] {
            assert!((chi2_99(dof) - q).abs() / q < 2e-3, "{dof} {}", chi2_99(dof));
        }
    }

    #[test]
    fn no_degrees_of_freedom_or_no_white_variance_gives_no_floor() {
        assert_eq!(floor_variance(&[1e-6], 1, from_mean(&[1.0])), 0.0);
        assert_eq!(
            floor_variance(&[0.0, 0.0, 0.0], 1, from_mean(&[1.0, 2.0, 3.0])),
            0.0
        );
    }
}
