//! The ceiling of the measured curve: at each point, the upper end of the
//! measured Allan variance's [`CEILING_CONFIDENCE`] interval, by the same
//! χ² interval ([`crate::confidence::chi2_interval`]) that gives the
//! intervals every output prints. No kept term may exceed it, and a left-out
//! term's bound is the smallest ceiling along its line.
//!
//! The bounds take each point with its own EDF, the one its printed
//! interval has: a ceiling set under a smaller EDF (the most cautious
//! power-law one, or the model's) lies above the printed interval's upper
//! end, and a bound from it stood up to 10 % above the deviation it came
//! from on real recordings. A kept term is held under the points as the fit
//! weighs them (`select`): the points' own noise identification reads one α
//! at a time and can overstate a point's EDF many times in a mixture, which
//! would rule out true processes.

use super::{CEILING_CONFIDENCE, MIN_EDF};
use crate::Point;
use crate::confidence::chi2_interval;

/// One point's ceiling on the Allan variance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ceiling {
    /// τ of the point, s.
    pub tau: f64,
    /// The measured deviation there.
    pub dev: f64,
    /// The upper end of the measured variance's interval.
    pub avar: f64,
}

/// The upper end of the measured deviation's [`CEILING_CONFIDENCE`]
/// interval at `p`, with `p`'s own EDF.
pub fn upper_dev(p: &Point) -> f64 {
    chi2_interval(p.dev, p.edf, CEILING_CONFIDENCE).1
}

/// The ceilings of the measured points that bound a term: those with at
/// least [`MIN_EDF`] degrees of freedom, or every point when none has that
/// many (a record too short for any still bounds its terms).
pub fn ceilings(measured: &[Point]) -> Vec<Ceiling> {
    let supported = measured.iter().any(|p| p.edf >= MIN_EDF);
    measured
        .iter()
        .filter(|p| !supported || p.edf >= MIN_EDF)
        .map(|p| Ceiling {
            tau: p.tau,
            dev: p.dev,
            avar: upper_dev(p).powi(2),
        })
        .filter(|c| c.avar.is_finite())
        .collect()
}

/// The smallest ceiling along the line of a process whose Allan variance
/// at τ is `basis(τ)` times its size²: the largest size (σ-like, the
/// square root) that stays under every ceiling.
pub fn bound(ceilings: &[Ceiling], basis: impl Fn(f64) -> f64) -> Option<f64> {
    ceilings
        .iter()
        .map(|c| (c.avar / basis(c.tau)).sqrt())
        .filter(|v| v.is_finite())
        .min_by(f64::total_cmp)
}

/// The ceiling a process whose Allan variance at τ is `avar(τ)` exceeds
/// by the largest factor, if it exceeds any.
pub fn worst_breach(ceilings: &[Ceiling], avar: impl Fn(f64) -> f64) -> Option<&Ceiling> {
    ceilings
        .iter()
        .map(|c| (avar(c.tau) / c.avar, c))
        .filter(|(r, _)| *r > 1.0)
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, c)| c)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(tau: f64, dev: f64, edf: f64) -> Point {
        let (lo, hi) = chi2_interval(dev, edf, 0.95);
        Point {
            tau,
            m: 1,
            n: 100,
            dev,
            dev_lo: lo,
            dev_hi: hi,
            edf,
            alpha: 0,
            noise_id: crate::NoiseIdMethod::Assumed,
        }
    }

    /// The ceiling is the printed interval's upper end at the ceiling's
    /// confidence: the same EDF, the same quantile, bit for bit.
    #[test]
    fn the_ceiling_is_the_printed_interval_at_its_confidence() {
        for edf in [2.5, 10.0, 37.0, 1e3, 5e5] {
            let p = point(1.0, 2e-3, edf);
            assert_eq!(upper_dev(&p), chi2_interval(2e-3, edf, CEILING_CONFIDENCE).1);
            assert!(
                upper_dev(&p) > p.dev_hi,
                "99 % end inside the 95 % one at EDF {edf}"
            );
        }
    }

    /// A bound is no larger than any supported point allows, and equals
    /// the tightest one.
    #[test]
    fn a_bound_is_the_tightest_ceiling_along_the_line() {
        let pts = [
            point(1.0, 1.0, 100.0),
            point(2.0, 0.6, 50.0),
            point(4.0, 0.5, 3.0),
        ];
        let c = ceilings(&pts);
        assert_eq!(c.len(), 2, "the 3-EDF point bounds nothing beside supported ones");
        let white = |tau: f64| 1.0 / tau;
        let b = bound(&c, white).unwrap();
        assert!(worst_breach(&c, |tau| b * b * white(tau) * (1.0 - 1e-12)).is_none());
        let over = worst_breach(&c, |tau| b * b * white(tau) * (1.0 + 1e-9));
        assert_eq!(
            over.map(|o| o.tau),
            Some(2.0),
            "the tightest point is the one broken"
        );
        let at_2 = upper_dev(&pts[1]) * 2f64.sqrt();
        assert!((b / at_2 - 1.0).abs() < 1e-12, "{b} vs {at_2}");
    }

    /// A record whose every point is short of [`MIN_EDF`] is bounded by all
    /// of them.
    #[test]
    fn without_supported_points_every_point_bounds() {
        let pts = [point(1.0, 1.0, 3.0), point(2.0, 0.7, 1.5)];
        assert_eq!(ceilings(&pts).len(), 2);
    }
}
