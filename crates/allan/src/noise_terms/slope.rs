//! The slope method of IEEE Std 952 Annex C, as the thesis and MATLAB's
//! `allanvar` example apply it: find where the log-log slope of σ(τ) is
//! closest to the term's slope, draw the line of that slope through the
//! point, and read it at the term's τ (1 s for N, 3 s for K, √3 s for Q,
//! √2 s for R). Bias instability is the minimum σ_min over 0.664.

use super::{Term, TermEstimate, TermValue, flicker_floor};
use crate::Point;

/// Largest distance between the curve's local slope and a term's slope for
/// the term to be read there: half the spacing of the slopes of
/// neighbouring terms.
pub const SLOPE_TOLERANCE: f64 = 0.25;

/// The slope method's result.
#[derive(Debug, Clone, PartialEq)]
pub struct SlopeResult {
    /// Every term, in [`Term::ALL`] order.
    pub terms: Vec<(Term, TermEstimate)>,
    /// The ADEV minimum σ_min with its interval and τ: what the thesis
    /// tables quote as bias instability "at τ s".
    pub sigma_min: Option<TermValue>,
}

impl SlopeResult {
    /// The estimate of one term.
    pub fn get(&self, term: Term) -> &TermEstimate {
        // Every term is present by construction.
        &self.terms[Term::ALL.iter().position(|t| *t == term).unwrap_or(0)].1
    }
}

/// τ at which the term's line is read.
fn reading_tau(term: Term) -> f64 {
    match term {
        Term::Quantization => 3f64.sqrt(),
        Term::WhiteNoise => 1.0,
        Term::BiasInstability => 1.0,
        Term::RateRandomWalk => 3.0,
        Term::RateRamp => 2f64.sqrt(),
    }
}

/// Local log-log slopes: central differences inside, one-sided at the ends.
fn local_slopes(points: &[Point]) -> Vec<f64> {
    let n = points.len();
    let lt: Vec<f64> = points.iter().map(|p| p.tau.ln()).collect();
    let ls: Vec<f64> = points.iter().map(|p| p.dev.ln()).collect();
    (0..n)
        .map(|i| {
            let (a, b) = (i.saturating_sub(1), (i + 1).min(n - 1));
            if a == b {
                f64::NAN
            } else {
                (ls[b] - ls[a]) / (lt[b] - lt[a])
            }
        })
        .collect()
}

/// Applies the slope method to an ADEV curve (points by increasing τ).
pub fn slope_method(points: &[Point]) -> SlopeResult {
    let usable: Vec<Point> = points
        .iter()
        .copied()
        .filter(|p| p.dev.is_finite() && p.dev > 0.0 && p.tau > 0.0)
        .collect();
    if usable.len() < 3 {
        let why = "not identifiable: fewer than 3 points on the ADEV curve".to_string();
        return SlopeResult {
            terms: Term::ALL
                .iter()
                .map(|&t| (t, TermEstimate::NotIdentifiable(why.clone())))
                .collect(),
            sigma_min: None,
        };
    }
    let slopes = local_slopes(&usable);
    let (tau_min, tau_max) = (usable[0].tau, usable[usable.len() - 1].tau);

    let min_index = usable
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.dev.total_cmp(&b.1.dev))
        .map_or(0, |(i, _)| i);
    let pm = usable[min_index];
    let sigma_min = TermValue {
        value: pm.dev,
        lo: pm.dev_lo,
        hi: pm.dev_hi,
        tau: Some(pm.tau),
    };
    let interior = min_index > 0 && min_index + 1 < usable.len();

    let terms = Term::ALL
        .iter()
        .map(|&term| {
            let est = if term == Term::BiasInstability {
                if interior {
                    let f = flicker_floor();
                    TermEstimate::Value(TermValue {
                        value: pm.dev / f,
                        lo: pm.dev_lo / f,
                        hi: pm.dev_hi / f,
                        tau: Some(pm.tau),
                    })
                } else if min_index + 1 == usable.len() {
                    TermEstimate::NotIdentifiable(format!(
                        "not identifiable: the ADEV still falls at the longest τ ({tau_max:.4} s); needs a longer recording"
                    ))
                } else {
                    TermEstimate::NotIdentifiable(format!(
                        "not identifiable: the ADEV rises from the shortest τ ({tau_min:.4} s) on"
                    ))
                }
            } else {
                let target = term.slope();
                // Falling terms show before the minimum, rising ones after
                // it: a noisy wiggle of the right slope on the wrong side is
                // not the term.
                let side = |i: usize| if term.slope() < 0.0 { i <= min_index } else { i >= min_index };
                let best = slopes
                    .iter()
                    .enumerate()
                    .filter(|(i, s)| s.is_finite() && side(*i))
                    .min_by(|a, b| (a.1 - target).abs().total_cmp(&(b.1 - target).abs()));
                match best {
                    Some((i, s)) if (s - target).abs() <= SLOPE_TOLERANCE => {
                        let p = usable[i];
                        let scale = (reading_tau(term) / p.tau).powf(target);
                        TermEstimate::Value(TermValue {
                            value: p.dev * scale,
                            lo: p.dev_lo * scale,
                            hi: p.dev_hi * scale,
                            tau: Some(p.tau),
                        })
                    }
                    _ => {
                        let need = if term.is_short_tau() {
                            format!("needs τ below {tau_min:.4} s (a higher sample rate)")
                        } else {
                            format!("needs τ beyond {tau_max:.4} s (a longer recording)")
                        };
                        TermEstimate::NotIdentifiable(format!(
                            "not identifiable: no part of the curve has slope {target:+}; {need}"
                        ))
                    }
                }
            };
            (term, est)
        })
        .collect();
    SlopeResult {
        terms,
        sigma_min: Some(sigma_min),
    }
}
