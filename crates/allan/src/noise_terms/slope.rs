//! The slope method of IEEE Std 952 Annex C, made to hold on real curves:
//! a term is read only where the log-log slope of σ(τ) stays at the term's
//! slope over a stretch of τ (a factor of [`STRETCH_FACTOR`]), on the side
//! of the minimum where that term can dominate, and its line is read at
//! the term's τ (1 s for N, 3 s for K, √3 s for Q, √2 s for R) from every
//! point of the stretch. A single point whose local slope happens to match
//! — a tone's ripple at the first τ, the flank of a periodic bump, a noisy
//! point near the end of the curve — is not a term.
//!
//! Bias instability is the minimum σ_min over 0.664, taken only among
//! points with at least [`MIN_EDF`] degrees of freedom and only when the
//! curve rises past it by more than the minimum's own scatter; a curve
//! still falling at its longest supported τ has no minimum within the
//! record, and B is then only bounded from above.

use super::{
    PerTerm, Term, TermEstimate, TermValue, ThesisReading, flicker_floor, thesis_reading, upper_bound,
};
use crate::Point;

/// Largest distance between the curve's slope and a term's slope for the
/// term to be read there.
pub const SLOPE_TOLERANCE: f64 = 0.12;

/// Shortest stretch of τ (as a ratio of its ends) over which the slope must
/// hold for a term to be read.
pub const STRETCH_FACTOR: f64 = 3.0;

/// Fewest degrees of freedom of a point for σ_min to be taken there: with
/// 10, σ is known to about ±22 % (one standard deviation, 1/√(2·edf)); past
/// it the last points of a curve, with 3 to 6, would decide the minimum.
pub const MIN_EDF: f64 = 10.0;

/// Where the curve's minimum is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Minimum {
    /// Inside the record: the curve rises past it beyond its scatter.
    Found,
    /// The curve still falls (or stays flat within its scatter) at the
    /// longest τ with enough degrees of freedom.
    StillFalling,
    /// The curve rises from the shortest τ on.
    RisesFromStart,
    /// Too few points.
    Unknown,
}

/// The slope method's result.
#[derive(Debug, Clone, PartialEq)]
pub struct SlopeResult {
    /// Every term's estimate.
    pub terms: PerTerm<TermEstimate>,
    /// The ADEV minimum σ_min with its interval and τ, among the points
    /// with at least [`MIN_EDF`] degrees of freedom: what the thesis tables
    /// quote as bias instability "at τ s".
    pub sigma_min: Option<TermValue>,
    /// Whether σ_min is a minimum of the curve.
    pub minimum: Minimum,
    /// The stretch of τ (first, last) each identified term was read over.
    pub stretches: Vec<(Term, f64, f64)>,
    /// Upper bounds of the terms the method could not read: no term's share
    /// of σ² can exceed the upper end of σ's interval at any τ.
    pub bounds: Vec<(Term, f64)>,
    /// N and B as the thesis's own script reads them, for comparison.
    pub thesis: ThesisReading,
}

impl SlopeResult {
    /// The estimate of one term.
    pub fn get(&self, term: Term) -> &TermEstimate {
        self.terms.get(term)
    }

    /// The upper bound of a term the method could not read.
    pub fn bound(&self, term: Term) -> Option<f64> {
        self.bounds.iter().find(|(t, _)| *t == term).map(|(_, b)| *b)
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

/// Log-log slope at each point: the least-squares slope of ln σ against
/// ln τ over the points within a factor 2 either side, so that one noisy
/// point does not make a slope.
fn local_slopes(points: &[Point]) -> Vec<f64> {
    let lt: Vec<f64> = points.iter().map(|p| p.tau.ln()).collect();
    let ls: Vec<f64> = points.iter().map(|p| p.dev.ln()).collect();
    let half = 2f64.ln() + 1e-9;
    (0..points.len())
        .map(|i| {
            let idx: Vec<usize> = (0..points.len())
                .filter(|&j| (lt[j] - lt[i]).abs() <= half)
                .collect();
            if idx.len() < 2 {
                return f64::NAN;
            }
            let n = idx.len() as f64;
            let mx = idx.iter().map(|&j| lt[j]).sum::<f64>() / n;
            let my = idx.iter().map(|&j| ls[j]).sum::<f64>() / n;
            let sxy: f64 = idx.iter().map(|&j| (lt[j] - mx) * (ls[j] - my)).sum();
            let sxx: f64 = idx.iter().map(|&j| (lt[j] - mx).powi(2)).sum();
            if sxx > 0.0 { sxy / sxx } else { f64::NAN }
        })
        .collect()
}

/// Runs (first, last index) of consecutive points within `range` whose
/// slope is within [`SLOPE_TOLERANCE`] of `target` and that span at least
/// [`STRETCH_FACTOR`] in τ.
fn stretches(
    points: &[Point],
    slopes: &[f64],
    target: f64,
    range: std::ops::RangeInclusive<usize>,
) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start: Option<usize> = None;
    let end = *range.end();
    for i in range.clone() {
        let holds = (slopes[i] - target).abs() <= SLOPE_TOLERANCE;
        match (holds, start) {
            (true, None) => start = Some(i),
            (false, Some(s)) => {
                out.push((s, i - 1));
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start {
        out.push((s, end));
    }
    out.retain(|&(a, b)| points[b].tau / points[a].tau >= STRETCH_FACTOR * (1.0 - 1e-9));
    out
}

/// A term's line read over the stretches where its slope holds. Every
/// other term only adds to σ², so a point's reading along the line is the
/// term plus the others' share: points whose whole interval lies above the
/// lowest upper bound of any point are lifted by the others and are not
/// read. Among the rest, the reading is the best-supported point's (most
/// degrees of freedom), with its interval.
fn read_stretches(points: &[Point], runs: &[(usize, usize)], term: Term) -> (TermValue, (usize, usize)) {
    let s = term.slope();
    let at = |p: &Point, v: f64| v * (reading_tau(term) / p.tau).powf(s);
    let members = || runs.iter().flat_map(|&(a, b)| (a..=b).map(move |i| (i, (a, b))));
    let envelope = members()
        .map(|(i, _)| at(&points[i], points[i].dev_hi))
        .fold(f64::INFINITY, f64::min);
    let (i, run) = members()
        .filter(|&(i, _)| at(&points[i], points[i].dev_lo) <= envelope)
        .max_by(|a, b| points[a.0].edf.total_cmp(&points[b.0].edf).then(b.0.cmp(&a.0)))
        .unwrap_or((runs[0].0, runs[0]));
    let p = points[i];
    (
        TermValue {
            value: at(&p, p.dev),
            lo: at(&p, p.dev_lo),
            hi: at(&p, p.dev_hi),
            tau: Some(p.tau),
        },
        run,
    )
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
            terms: PerTerm::from_fn(|_| TermEstimate::NotIdentifiable(why.clone())),
            sigma_min: None,
            minimum: Minimum::Unknown,
            stretches: Vec::new(),
            bounds: Vec::new(),
            thesis: thesis_reading(points),
        };
    }
    let slopes = local_slopes(&usable);
    let last = usable.len() - 1;
    let (tau_min, tau_max) = (usable[0].tau, usable[last].tau);

    // σ_min among the supported points; the whole curve when none is.
    let supported: Vec<usize> = (0..usable.len()).filter(|&i| usable[i].edf >= MIN_EDF).collect();
    let candidates = if supported.is_empty() {
        (0..usable.len()).collect()
    } else {
        supported.clone()
    };
    let min_index = candidates
        .iter()
        .copied()
        .min_by(|&a, &b| usable[a].dev.total_cmp(&usable[b].dev))
        .unwrap_or(0);
    let last_supported = candidates.last().copied().unwrap_or(last);
    let pm = usable[min_index];
    let rises_after = candidates
        .iter()
        .any(|&j| j > min_index && usable[j].dev_lo > pm.dev_hi.max(pm.dev));
    let minimum = if min_index == candidates[0] && min_index < last_supported && rises_after {
        Minimum::RisesFromStart
    } else if rises_after {
        Minimum::Found
    } else {
        Minimum::StillFalling
    };
    let sigma_min = TermValue {
        value: pm.dev,
        lo: pm.dev_lo,
        hi: pm.dev_hi,
        tau: Some(pm.tau),
    };
    let supported_tau = usable[last_supported].tau;

    let mut found_stretches = Vec::new();
    let terms = PerTerm::from_fn(|term| {
        if term == Term::BiasInstability {
            match minimum {
                Minimum::Found => {
                    let f = flicker_floor();
                    TermEstimate::Value(TermValue {
                        value: pm.dev / f,
                        lo: pm.dev_lo / f,
                        hi: pm.dev_hi / f,
                        tau: Some(pm.tau),
                    })
                }
                Minimum::StillFalling => TermEstimate::NotIdentifiable(format!(
                    "not identifiable: no minimum within the record (the ADEV still falls at τ = \
                         {supported_tau:.4} s, the longest with ≥ {MIN_EDF} degrees of freedom); needs a \
                         longer recording"
                )),
                Minimum::RisesFromStart => TermEstimate::NotIdentifiable(format!(
                    "not identifiable: the ADEV rises from the shortest τ ({tau_min:.4} s) on"
                )),
                Minimum::Unknown => TermEstimate::NotIdentifiable(
                    "not identifiable: too few points on the ADEV curve".to_string(),
                ),
            }
        } else {
            let target = term.slope();
            // Falling terms show before the minimum, rising ones after
            // it; with no minimum found, the falling terms may be read
            // anywhere and the rising ones nowhere.
            let range = match (term.slope() < 0.0, minimum) {
                (true, Minimum::Found) => 0..=min_index,
                (true, _) => 0..=last,
                (false, Minimum::Found | Minimum::RisesFromStart) => min_index..=last,
                (false, _) => last + 1..=last,
            };
            let mut runs = if range.is_empty() {
                Vec::new()
            } else {
                stretches(&usable, &slopes, target, range)
            };
            let mut rejected = None;
            if term == Term::Quantization {
                // Quantization dominates from the shortest τ: its −1
                // line starts in the first octave, with the curve
                // falling from τ0 on. A −1 stretch after a rise is the
                // flank of a bump; one that does not reach τ0's octave
                // is a tone's or a filter's ripple.
                let before = runs.len();
                runs.retain(|&(a, _)| {
                    usable[a].tau <= 2.0 * tau_min * (1.0 + 1e-9) && (0..a).all(|j| slopes[j] < -0.5)
                });
                if runs.len() < before {
                    rejected = Some(
                        "not identifiable: the only slope −1 on the curve does not start at the shortest τ \
                             (a bump, a tone or a filter, not quantization)",
                    );
                }
            }
            match (!runs.is_empty()).then(|| read_stretches(&usable, &runs, term)) {
                Some((value, run)) => {
                    found_stretches.push((term, usable[run.0].tau, usable[run.1].tau));
                    TermEstimate::Value(value)
                }
                None => {
                    let need = if term.is_short_tau() {
                        format!("needs τ below {tau_min:.4} s (a higher sample rate)")
                    } else {
                        format!("needs τ beyond {tau_max:.4} s (a longer recording)")
                    };
                    TermEstimate::NotIdentifiable(rejected.map_or_else(
                        || {
                            format!(
                                "not identifiable: no stretch of the curve (a factor {STRETCH_FACTOR} in τ) \
                                     holds slope {target:+}; {need}"
                            )
                        },
                        str::to_string,
                    ))
                }
            }
        }
    });
    let bounds = terms
        .iter()
        .filter(|(_, e)| e.value().is_none())
        .filter_map(|(t, _)| upper_bound(t, &usable, MIN_EDF).map(|b| (t, b)))
        .collect();
    SlopeResult {
        terms,
        sigma_min: Some(sigma_min),
        minimum,
        stretches: found_stretches,
        bounds,
        thesis: thesis_reading(&usable),
    }
}
