//! A weighted, non-negative least-squares fit of the whole IEEE 952 model
//! σ²(τ) = 3Q²/τ² + N²/τ + (2 ln2/π)B² + K²τ/3 + R²τ²/2 to an ADEV curve.
//!
//! Each point's variance estimate σ̂² has variance ≈ 2σ⁴/edf (a χ² with
//! edf degrees of freedom), so it is weighted by edf/(2σ⁴), with σ⁴ taken
//! from the model itself (iteratively reweighted: weighting by the noisy σ̂
//! would favour the points that happen to lie low). Non-negativity is exact:
//! with five coefficients every subset of active terms is solved, and of
//! those whose coefficients are all positive the one with the lowest
//! Bayesian information criterion is kept (a term is only let in when it
//! explains more than noise). The covariance of
//! the coefficients is scaled up by the reduced χ² when the model misses the
//! points by more than their scatter (real sensors are not exactly five
//! power laws), and no coefficient is given a smaller spread than the one
//! point that shows it best implies on its own (neighbouring taus share
//! data, so the points are not independent).

use nalgebra::{DMatrix, DVector};
use statrs::distribution::{ContinuousCDF, Normal};

use super::{PerTerm, Term, TermEstimate, TermValue};
use crate::Point;

/// Reweighting passes: the weights settle within a few.
const PASSES: usize = 4;

/// The fit's result.
#[derive(Debug, Clone, PartialEq)]
pub struct FitResult {
    /// Every term's estimate.
    pub terms: PerTerm<TermEstimate>,
    /// χ² of the fit over its degrees of freedom (≈ 1 for a good fit).
    pub chi2_reduced: Option<f64>,
    /// Points fitted.
    pub points: usize,
    /// Confidence level of the intervals.
    pub confidence: f64,
    /// τ of the points left out of the fit as outliers: points the model
    /// misses by far more than their scatter and than the others (a
    /// periodic bump, a tone), which no sum of the five terms describes.
    pub left_out: Vec<f64>,
}

impl FitResult {
    /// The estimate of one term.
    pub fn get(&self, term: Term) -> &TermEstimate {
        self.terms.get(term)
    }
}

/// The term's column in the design matrix, whose columns follow
/// [`Term::ALL`].
fn column(term: Term) -> usize {
    match term {
        Term::Quantization => 0,
        Term::WhiteNoise => 1,
        Term::BiasInstability => 2,
        Term::RateRandomWalk => 3,
        Term::RateRamp => 4,
    }
}

/// Bayesian information criterion of a solution: its χ² plus ln(n) per
/// active term. More terms always lower χ²; without the penalty a term of
/// noise-sized weight (a spurious Q beside N) would be kept and would bias
/// the terms it trades off with.
fn bic(s: &Solution, n: usize) -> f64 {
    s.ssr + s.active.len() as f64 * (n as f64).ln()
}

struct Solution {
    active: Vec<usize>,
    coef: Vec<f64>,
    ssr: f64,
}

/// Weighted least squares on the active columns; `None` if any coefficient
/// is not positive or the system is degenerate.
fn solve(a: &DMatrix<f64>, y: &DVector<f64>, w: &DVector<f64>, active: &[usize]) -> Option<Solution> {
    let n = a.nrows();
    let p = active.len();
    if p == 0 || p > n {
        return None;
    }
    // Rows scaled by √w; columns scaled to unit norm for conditioning (the
    // basis functions differ by many orders of magnitude across τ).
    let mut m = DMatrix::zeros(n, p);
    for (j, &k) in active.iter().enumerate() {
        for i in 0..n {
            m[(i, j)] = a[(i, k)] * w[i].sqrt();
        }
    }
    let norms: Vec<f64> = (0..p).map(|j| m.column(j).norm()).collect();
    if norms.iter().any(|v| !(v.is_finite() && *v > 0.0)) {
        return None;
    }
    for (j, nj) in norms.iter().enumerate() {
        m.column_mut(j).scale_mut(1.0 / nj);
    }
    let rhs = DVector::from_iterator(n, (0..n).map(|i| y[i] * w[i].sqrt()));
    let svd = m.clone().svd(true, true);
    let sol = svd.solve(&rhs, 1e-12).ok()?;
    let coef: Vec<f64> = (0..p).map(|j| sol[j] / norms[j]).collect();
    if coef.iter().any(|c| !(c.is_finite() && *c > 0.0)) {
        return None;
    }
    let resid = &m * &sol - &rhs;
    Some(Solution {
        active: active.to_vec(),
        coef,
        ssr: resid.norm_squared(),
    })
}

/// Largest EDF a point is weighted with: 2/0.01², a 1 % standard deviation
/// of σ². The short-τ points of a long recording have EDF in the hundreds
/// of thousands, but no sensor is five exact power laws down to τ0 (its
/// anti-alias filter, the sampling itself, a flicker spectrum that ends
/// somewhere): trusting those points to 0.1 % would let a model error of
/// that size decide N outside its interval.
pub const MAX_FIT_EDF: f64 = 20_000.0;

/// Share of the model variance a term must carry at some τ to be kept.
pub const SHOW_SHARE: f64 = 0.4;

/// The best subset of the `allowed` terms (bit k for `Term::ALL[k]`), by
/// iteratively reweighted least squares, and its model variances.
fn select(
    a: &DMatrix<f64>,
    y: &DVector<f64>,
    edf: &DVector<f64>,
    allowed: u32,
) -> (Option<Solution>, DVector<f64>) {
    let n = a.nrows();
    let mut model = y.clone();
    let mut best: Option<Solution> = None;
    for _ in 0..PASSES {
        let w = DVector::from_iterator(n, (0..n).map(|i| edf[i] / (2.0 * model[i] * model[i])));
        best = (1u32..32)
            .filter(|mask| mask & !allowed == 0)
            .map(|mask| (0..5).filter(|k| mask & (1 << k) != 0).collect::<Vec<usize>>())
            .filter_map(|active| solve(a, y, &w, &active))
            .min_by(|s, t| bic(s, n).total_cmp(&bic(t, n)));
        let Some(s) = &best else { break };
        let next = DVector::from_iterator(
            n,
            (0..n).map(|i| {
                s.active
                    .iter()
                    .zip(&s.coef)
                    .map(|(&k, c)| a[(i, k)] * c)
                    .sum::<f64>()
            }),
        );
        if next.iter().any(|m| !(m.is_finite() && *m > 0.0)) {
            break;
        }
        model = next;
    }
    (best, model)
}

/// A point is left out when the model misses it by more than this many of
/// its standard deviations…
const OUTLIER_SIGMAS: f64 = 5.0;
/// …and by more than this many times the median miss (so that a model
/// that fits nothing well is not whittled down to the points it fits).
const OUTLIER_MEDIAN: f64 = 3.0;

/// Fits the model to `points` (octave taus of an OADEV curve are best:
/// nearly independent), with intervals at `confidence`. Points the model
/// misses far beyond their scatter (a periodic disturbance's bump, a
/// tone's ripple) are left out one at a time, worst first, up to a quarter
/// of them: they are no power-law term, and kept they would be explained
/// as one (a quantization that is a tone, a white noise lifted by a bump).
pub fn fit_model(points: &[Point], confidence: f64) -> FitResult {
    let mut pts: Vec<Point> = points.to_vec();
    let mut left_out = Vec::new();
    let budget = points.len() / 4;
    loop {
        let (mut result, misses) = fit_once(&pts, confidence);
        let mut order: Vec<f64> = misses.iter().map(|(_, r)| r.abs()).collect();
        order.sort_unstable_by(f64::total_cmp);
        let median = order.get(order.len() / 2).copied().unwrap_or(0.0);
        let worst = misses
            .iter()
            .copied()
            .filter(|(_, r)| r.abs() > OUTLIER_SIGMAS && r.abs() > OUTLIER_MEDIAN * median)
            .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()));
        match worst {
            Some((tau, _)) if left_out.len() < budget && pts.len() > 6 => {
                pts.retain(|p| p.tau != tau);
                left_out.push(tau);
            }
            _ => {
                left_out.sort_unstable_by(f64::total_cmp);
                result.left_out = left_out;
                return result;
            }
        }
    }
}

/// One fit of all `points`, and each fitted point's miss (τ, (σ̂² − model)
/// in standard deviations of σ̂²).
fn fit_once(points: &[Point], confidence: f64) -> (FitResult, Vec<(f64, f64)>) {
    let pts: Vec<&Point> = points
        .iter()
        .filter(|p| p.dev.is_finite() && p.dev > 0.0 && p.edf.is_finite() && p.edf > 0.0 && p.tau > 0.0)
        .collect();
    let n = pts.len();
    let not_enough = |why: &str| FitResult {
        terms: PerTerm::from_fn(|_| TermEstimate::NotIdentifiable(why.to_string())),
        chi2_reduced: None,
        points: n,
        confidence,
        left_out: Vec::new(),
    };
    if n < 2 {
        return (
            not_enough("not identifiable: fewer than 2 points to fit"),
            Vec::new(),
        );
    }
    let a = DMatrix::from_fn(n, 5, |i, k| Term::ALL[k].variance_basis(pts[i].tau));
    let y = DVector::from_iterator(n, pts.iter().map(|p| p.dev * p.dev));
    let edf = DVector::from_iterator(n, pts.iter().map(|p| p.edf.min(MAX_FIT_EDF)));
    let mut allowed: u32 = 0b11111;
    let (mut best, mut model) = select(&a, &y, &edf, allowed);
    // A term must show: carry at least SHOW_SHARE of the variance at some
    // τ. One that never does is buried under the others; its coefficient
    // would only soak up the scatter of the points and bias the terms it
    // trades off with, so it is taken out and the rest refitted.
    // Quantization must show at two points at least: at the shortest τ
    // alone, a tone near the Nyquist frequency, an aliasing artefact or the
    // anti-alias filter lifts the curve the way 3Q²/τ² would.
    while let Some(s) = &best {
        let buried = s.active.iter().zip(&s.coef).find(|&(&k, &c)| {
            let shows = (0..n).filter(|&i| c * a[(i, k)] >= SHOW_SHARE * model[i]).count();
            shows < if Term::ALL[k] == Term::Quantization { 2 } else { 1 }
        });
        match buried {
            Some((&k, _)) => {
                allowed &= !(1 << k);
                (best, model) = select(&a, &y, &edf, allowed);
            }
            None => break,
        }
    }
    let Some(sol) = best else {
        return (
            not_enough("not identifiable: no positive combination of the terms fits the curve"),
            Vec::new(),
        );
    };

    // Covariance of the active coefficients: (AᵀWA)⁻¹, scaled by the
    // reduced χ² when the fit is worse than the points' own scatter.
    let w = DVector::from_iterator(n, (0..n).map(|i| edf[i] / (2.0 * model[i] * model[i])));
    let p = sol.active.len();
    let dof = n.saturating_sub(p);
    let chi2_reduced = (dof > 0).then(|| sol.ssr / dof as f64);
    let inflate = chi2_reduced.map_or(1.0, |c| c.max(1.0));
    let normal = DMatrix::from_fn(p, p, |r, c| {
        (0..n)
            .map(|i| w[i] * a[(i, sol.active[r])] * a[(i, sol.active[c])])
            .sum::<f64>()
    });
    let cov = normal.clone().pseudo_inverse(1e-300).ok();
    let z = Normal::new(0.0, 1.0)
        .map(|d| d.inverse_cdf(0.5 + confidence / 2.0))
        .unwrap_or(1.0);

    let (tau_min, tau_max) = (pts[0].tau, pts[n - 1].tau);
    let model_without = |skip: usize, tau: f64| -> f64 {
        sol.active
            .iter()
            .zip(&sol.coef)
            .filter(|(k, _)| **k != skip)
            .map(|(&k, c)| c * Term::ALL[k].variance_basis(tau))
            .sum()
    };
    let terms = PerTerm::from_fn(|term| {
        let k = column(term);
        let pos = sol.active.iter().position(|&j| j == k);
        // Neighbouring taus of an OADEV curve share most of their data,
        // so the independent-points covariance is too optimistic. No
        // coefficient is known better than the single most telling
        // point determines it alone (the full-correlation bound), and
        // that bound is kept when larger.
        let single = (0..n)
            .map(|i| model[i] * (2.0 / edf[i]).sqrt() / a[(i, k)])
            .filter(|v| v.is_finite())
            .fold(f64::INFINITY, f64::min);
        let sd = match (pos, &cov) {
            (Some(j), Some(cv)) => (cv[(j, j)] * inflate).max(0.0).sqrt().max(single),
            // An inactive term: the spread a coefficient of it alone
            // would have had — its detectable size.
            _ => {
                let fw: f64 = (0..n).map(|i| w[i] * a[(i, k)].powi(2)).sum();
                (inflate / fw).sqrt()
            }
        };
        let c = pos.map_or(0.0, |j| sol.coef[j]);
        let (lo, hi) = (c - z * sd, c + z * sd);
        if pos.is_some() && lo > 0.0 {
            return TermEstimate::Value(TermValue {
                value: c.sqrt(),
                lo: lo.sqrt(),
                hi: hi.sqrt(),
                tau: None,
            });
        }
        TermEstimate::NotIdentifiable(why_not(term, k, hi.max(0.0), tau_min, tau_max, &model_without))
    });
    let misses = (0..n)
        .map(|i| (pts[i].tau, (y[i] - model[i]) / (model[i] * (2.0 / edf[i]).sqrt())))
        .collect();
    (
        FitResult {
            terms,
            chi2_reduced,
            points: n,
            confidence,
            left_out: Vec::new(),
        },
        misses,
    )
}

/// Says where a term of variance coefficient at most `c_hi` would come out
/// of the other terms: the τ the recording would have to reach.
fn why_not(
    term: Term,
    k: usize,
    c_hi: f64,
    tau_min: f64,
    tau_max: f64,
    others: &dyn Fn(usize, f64) -> f64,
) -> String {
    let shows = |tau: f64| c_hi * term.variance_basis(tau) >= others(k, tau);
    if c_hi <= 0.0 {
        return "not identifiable: the fit gives it no weight at all".to_string();
    }
    if term == Term::BiasInstability {
        return format!(
            "not identifiable: buried under the other terms at every τ from {tau_min:.4} to {tau_max:.4} s"
        );
    }
    let step: f64 = if term.is_short_tau() { 1.0 / 1.15 } else { 1.15 };
    let mut tau = if term.is_short_tau() { tau_min } else { tau_max };
    for _ in 0..200 {
        tau *= step;
        if shows(tau) {
            return if term.is_short_tau() {
                format!(
                    "not identifiable: buried under the other terms; needs τ down to ≈ {tau:.3e} s \
                     (the shortest here is {tau_min:.3e} s: sample faster)"
                )
            } else {
                format!(
                    "not identifiable: needs τ up to ≈ {tau:.3e} s (the longest here is {tau_max:.3e} s: \
                     record longer)"
                )
            };
        }
    }
    "not identifiable: too small against the other terms at any τ".to_string()
}
