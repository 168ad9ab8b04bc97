//! The τ range a model is fitted over. A family of power laws and
//! Gauss–Markov processes rarely describes a real sensor's curve from τ0
//! to the record's end: the sensor's filter pulls the shortest τ down, a
//! temperature drift or a tone bends the longest up. Vetoing the whole
//! model there turns a white noise known to a few per cent over two
//! decades into a bound because of one point. So where no candidate
//! describes the whole curve, the end the best candidate parts from is
//! dropped, one point at a time, until a candidate keeps the rules and
//! describes the points left, or [`MIN_POINTS`] remain. The range is
//! printed, and so is how far the curve lies from the model beyond it
//! ([`Miss`]). The greedy path finds a wide range, not always the widest:
//! each step drops the end where the fit breaks, never a point inside.

use super::lm::{Component, model_avar};
use crate::Point;

/// Fewest points a range is narrowed to.
pub const MIN_POINTS: usize = 6;

/// A model whose χ² exceeds what the points' noise allows still describes
/// them where its deviation lies within this share of every point's: a misfit the χ² scale then widens the
/// intervals by (`select::Best::spreads`). Real sensors' curves carry
/// 10^5 degrees of freedom at short τ, a 0.3 % interval that no
/// idealised process meets.
pub const TOLERANCE: f64 = 0.05;

/// Where the curve beyond the fit range lies, against the model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Miss {
    /// τ of the point, s.
    pub tau: f64,
    /// The measured deviation over the model's there.
    pub ratio: f64,
}

/// The τ range a model was fitted over.
#[derive(Debug, Clone, PartialEq)]
pub struct FitRange {
    /// Its shortest τ, s.
    pub lo: f64,
    /// Its longest τ, s.
    pub hi: f64,
    /// Whether it is the whole curve.
    pub whole: bool,
    /// Each measured point beyond it, against the model.
    pub misses: Vec<Miss>,
    /// Points inside it left out of the fit as a feature no candidate
    /// process has (a bump, a tone), against the model.
    pub features: Vec<Miss>,
}

impl FitRange {
    /// The miss farthest from 1 below the range and above it.
    pub fn worst(&self) -> (Option<Miss>, Option<Miss>) {
        let far = |side: &dyn Fn(&Miss) -> bool| {
            self.misses
                .iter()
                .filter(|m| side(m))
                .max_by(|a, b| a.ratio.ln().abs().total_cmp(&b.ratio.ln().abs()))
                .copied()
        };
        (far(&|m| m.tau < self.lo), far(&|m| m.tau > self.hi))
    }

    /// One sentence: the range, and where the curve beyond it parts from
    /// the model most.
    pub fn describe(&self) -> String {
        let mut s = format!(
            "fitted over τ = {}–{} s",
            super::tau_text(self.lo),
            super::tau_text(self.hi)
        );
        if self.whole {
            s.push_str(", the whole curve");
        }
        for f in &self.features {
            s.push_str(&format!(
                "; left out inside it at τ = {} s, measured/model = {:.3}{}",
                super::tau_text(f.tau),
                f.ratio,
                if f.ratio > 1.0 {
                    format!(
                        " (a bump: a periodic disturbance of period near {} s shows at half its period)",
                        super::tau_text(2.0 * f.tau)
                    )
                } else {
                    String::new()
                }
            ));
        }
        let (below, above) = self.worst();
        for (m, side) in [(below, "below"), (above, "above")] {
            if let Some(m) = m {
                s.push_str(&format!(
                    "; {side} it the family misses the curve most at τ = {} s (measured/model = {:.3})",
                    super::tau_text(m.tau),
                    m.ratio
                ));
            }
        }
        s
    }
}

/// Whether the model's deviation is within [`TOLERANCE`] of every
/// point's. A point's own interval is no such licence: a model that misses
/// every point by two of its standard deviations lies inside each 95 %
/// interval and describes none of them.
pub fn within_tolerance(comps: &[Component], theta: &[f64], pts: &[Point]) -> bool {
    within_tolerance_beside(comps, theta, pts, |_| 0.0)
}

/// [`within_tolerance`] for points that had the Allan variance `beside(τ)`
/// of a process outside the family (a periodic disturbance) taken off:
/// the model with it against the points with it.
pub fn within_tolerance_beside(
    comps: &[Component],
    theta: &[f64],
    pts: &[Point],
    beside: impl Fn(f64) -> f64,
) -> bool {
    pts.iter().all(|p| {
        let b = beside(p.tau);
        let m = (model_avar(comps, theta, p.tau) + b).sqrt();
        (m / (p.dev * p.dev + b).sqrt() - 1.0).abs() <= TOLERANCE
    })
}

/// A parting point this close to an end of the range is the family's
/// miss at that end, and a narrower range is tried; one farther in is a
/// feature inside the range (a bump, a tone) and is left out instead, up
/// to [`MAX_SKIPPED`] of the range's points.
const END: usize = 3;

/// Share of a range's points that may be left out inside it.
const MAX_SKIPPED: f64 = 0.25;

/// The fit of a range: where it starts and ends in `pts`, the indices
/// inside it left out, and the fit.
pub(super) struct Found {
    pub start: usize,
    pub end: usize,
    pub skipped: Vec<usize>,
    /// The factor on the measured ceiling that held the kept processes.
    pub slack: f64,
    pub attempt: super::Attempt,
}

/// The range of `pts` and its fit: the whole curve where `fit` describes
/// it, else the greedy narrowing of the module's text, a parting point
/// inside the range left out rather than narrowing it; the whole curve's
/// fit where no narrower range is described either.
pub(super) fn search(pts: &[Point], fit: impl Fn(&[Point], f64) -> super::Attempt) -> Found {
    let n = pts.len();
    let whole = |attempt, slack| Found {
        start: 0,
        end: n,
        skipped: Vec::new(),
        slack,
        attempt,
    };
    let strict = fit(pts, 1.0);
    if strict.describes() || n <= MIN_POINTS {
        return whole(strict, 1.0);
    }
    let slack = slack();
    let attempt = fit(pts, slack);
    if attempt.describes() {
        return whole(attempt, slack);
    }
    // Widest first; of equal width, the one that keeps the longer τ (the
    // short end is where a sensor's filter shapes the curve).
    for width in (MIN_POINTS..n).rev() {
        for lo in (0..=n - width).rev() {
            let hi = lo + width;
            if lo > MAX_SHORT_CUT || n - hi > MAX_LONG_CUT {
                continue;
            }
            if let Some(found) = with_features(pts, lo, hi, slack, &fit) {
                return found;
            }
        }
    }
    whole(strict, 1.0)
}

/// The factor on the measured ceiling past the strict rules: a kept
/// process may stand above it by the share a model that describes the
/// curve may miss it by.
pub(super) fn slack() -> f64 {
    (1.0 + TOLERANCE).powi(2)
}

/// Most points cut from the short end: 4 octaves (τ0 to 16τ0), past which
/// no sampling or anti-alias filter shapes the curve.
const MAX_SHORT_CUT: usize = 4;
/// Most points cut from the long end.
const MAX_LONG_CUT: usize = 8;

/// The fit of `pts[lo..hi]`, leaving out a parting point inside it (not
/// within [`END`] of either end) while the fit does not describe the
/// points and [`MAX_SKIPPED`] allows; `None` where none describes them.
fn with_features(
    pts: &[Point],
    lo: usize,
    hi: usize,
    slack: f64,
    fit: &impl Fn(&[Point], f64) -> super::Attempt,
) -> Option<Found> {
    let mut skipped: Vec<usize> = Vec::new();
    loop {
        let kept: Vec<usize> = (lo..hi).filter(|i| !skipped.contains(i)).collect();
        let window: Vec<Point> = kept.iter().map(|&i| pts[i]).collect();
        let attempt = fit(&window, slack);
        if attempt.describes() {
            skipped.sort_unstable();
            return Some(Found {
                start: lo,
                end: hi,
                skipped,
                slack,
                attempt,
            });
        }
        let t = attempt.parting_tau()?;
        let k = (0..kept.len()).min_by(|&a, &b| {
            (pts[kept[a]].tau / t)
                .ln()
                .abs()
                .total_cmp(&(pts[kept[b]].tau / t).ln().abs())
        })?;
        let room = ((MAX_SKIPPED * (hi - lo) as f64) as usize) > skipped.len();
        // Only a point the model misses as an outlier (many of its standard
        // deviations, and many times the median miss) is a feature: a curve
        // that no candidate follows anywhere is not whittled down to the
        // points one does.
        let outlier = attempt.outlier_at().is_some_and(|o| o == k);
        if k < END || k + END >= kept.len() || !room || !outlier {
            return None;
        }
        skipped.push(kept[k]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_worst_miss_on_each_side() {
        let r = FitRange {
            lo: 0.1,
            hi: 100.0,
            whole: false,
            features: Vec::new(),
            misses: vec![
                Miss {
                    tau: 0.01,
                    ratio: 0.9,
                },
                Miss {
                    tau: 0.05,
                    ratio: 0.98,
                },
                Miss {
                    tau: 200.0,
                    ratio: 1.5,
                },
                Miss {
                    tau: 400.0,
                    ratio: 0.4,
                },
            ],
        };
        let (b, a) = r.worst();
        assert_eq!(b.map(|m| m.tau), Some(0.01));
        assert_eq!(a.map(|m| m.tau), Some(400.0), "0.4 is farther from 1 than 1.5");
        let text = r.describe();
        assert!(text.starts_with("fitted over τ = 0.1–100 s"), "{text}");
        assert!(text.contains("below it") && text.contains("0.900"), "{text}");
    }
}
