//! The IEEE Std 952-1997 (Annex C) noise terms of an inertial sensor, read
//! from its Allan deviation:
//!
//! | term | σ²(τ) | slope of σ | read off (slope method) |
//! | --- | --- | --- | --- |
//! | quantization Q | 3Q²/τ² | −1 | σ(√3 s) on the −1 line |
//! | white noise N (ARW/VRW) | N²/τ | −1/2 | σ(1 s) on the −1/2 line |
//! | bias instability B | (2 ln2/π)·B² | 0 | σ_min / 0.664 |
//! | rate random walk K | K²τ/3 | +1/2 | σ(3 s) on the +1/2 line |
//! | rate ramp R | R²τ²/2 | +1 | σ(√2 s) on the +1 line |
//!
//! Two estimators, side by side: the slope method of IEEE 952 read only
//! where a term's slope holds over a stretch of τ ([`slope_method`]), and a
//! weighted, non-negative least-squares fit of the whole model that leaves
//! out what no power law describes ([`fit_model`]). Each value has an
//! interval; a term the data cannot show is reported as not identifiable,
//! with the reason and an upper bound ([`upper_bound`]), never as a
//! number. [`NoiseTerms::choose`] says which estimate holds. The thesis's
//! own reading (slope nearest −1/2, first positive slope) is kept beside
//! them by name ([`thesis_reading`]), for comparison only.
//!
//! Units: the terms are in the unit of the rate data and seconds: N in
//! unit/√Hz = unit·√s, B in unit, K in unit/√s, Q in unit·s, R in unit/s.

mod fit;
mod slope;
mod thesis;

pub use fit::{FitResult, fit_model};
pub use slope::{MIN_EDF, Minimum, SlopeResult, slope_method};
pub use thesis::{ThesisReading, thesis_reading};

use crate::analysis::analyze_series_grids;
use crate::{AllanError, DataType, Options, PhaseSeries, Point, TauSpec};

/// √(2 ln 2 / π) = 0.664…: the Allan deviation floor of flicker noise of
/// bias instability B is 0.664·B (IEEE 952 Annex C).
pub fn flicker_floor() -> f64 {
    (2.0 * std::f64::consts::LN_2 / std::f64::consts::PI).sqrt()
}

/// The largest value `term` can have on this curve: its share of σ² can
/// nowhere exceed σ², so at every τ with at least `min_edf` degrees of
/// freedom the term is below the upper end of σ's interval read along its
/// own line; the smallest of these is the bound (at the confidence of the
/// points' intervals). `None` without such a point.
pub fn upper_bound(term: Term, points: &[Point], min_edf: f64) -> Option<f64> {
    points
        .iter()
        .filter(|p| p.edf >= min_edf && p.dev_hi.is_finite() && p.dev_hi > 0.0 && p.tau > 0.0)
        .map(|p| (p.dev_hi * p.dev_hi / term.variance_basis(p.tau)).sqrt())
        .filter(|v| v.is_finite())
        .min_by(f64::total_cmp)
}

/// One of the five terms.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Term {
    /// Quantization noise Q.
    Quantization,
    /// White rate noise N: angle random walk (gyro), velocity random walk (accel).
    WhiteNoise,
    /// Bias instability B (flicker).
    BiasInstability,
    /// Rate random walk K.
    RateRandomWalk,
    /// Rate ramp R.
    RateRamp,
}

impl Term {
    /// All five, from short to long τ.
    pub const ALL: [Term; 5] = [
        Term::Quantization,
        Term::WhiteNoise,
        Term::BiasInstability,
        Term::RateRandomWalk,
        Term::RateRamp,
    ];

    /// Q, N, B, K or R.
    pub fn symbol(self) -> &'static str {
        match self {
            Term::Quantization => "Q",
            Term::WhiteNoise => "N",
            Term::BiasInstability => "B",
            Term::RateRandomWalk => "K",
            Term::RateRamp => "R",
        }
    }

    /// Snake-case name for JSON.
    pub fn name(self) -> &'static str {
        match self {
            Term::Quantization => "quantization",
            Term::WhiteNoise => "white_noise",
            Term::BiasInstability => "bias_instability",
            Term::RateRandomWalk => "rate_random_walk",
            Term::RateRamp => "rate_ramp",
        }
    }

    /// Slope of σ(τ) on log-log axes where this term dominates.
    pub fn slope(self) -> f64 {
        match self {
            Term::Quantization => -1.0,
            Term::WhiteNoise => -0.5,
            Term::BiasInstability => 0.0,
            Term::RateRandomWalk => 0.5,
            Term::RateRamp => 1.0,
        }
    }

    /// σ²(τ) contributed by a term of value 1: the model's basis function.
    pub fn variance_basis(self, tau: f64) -> f64 {
        match self {
            Term::Quantization => 3.0 / (tau * tau),
            Term::WhiteNoise => 1.0 / tau,
            Term::BiasInstability => flicker_floor().powi(2),
            Term::RateRandomWalk => tau / 3.0,
            Term::RateRamp => tau * tau / 2.0,
        }
    }

    /// Whether the term shows at short τ (it needs faster sampling to be
    /// seen) rather than at long τ (it needs a longer recording).
    pub fn is_short_tau(self) -> bool {
        matches!(self, Term::Quantization | Term::WhiteNoise)
    }
}

/// A term's value with its interval, and the τ it was read at.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TermValue {
    /// The estimate.
    pub value: f64,
    /// Lower bound.
    pub lo: f64,
    /// Upper bound.
    pub hi: f64,
    /// τ of the point it was read from (slope method), s.
    pub tau: Option<f64>,
}

/// A term, or why there is none.
#[derive(Debug, Clone, PartialEq)]
pub enum TermEstimate {
    /// Identified.
    Value(TermValue),
    /// The data cannot show it; the reason says what would.
    NotIdentifiable(String),
}

impl TermEstimate {
    /// The value, if identified.
    pub fn value(&self) -> Option<&TermValue> {
        match self {
            TermEstimate::Value(v) => Some(v),
            TermEstimate::NotIdentifiable(_) => None,
        }
    }
}

/// Both estimators and where they disagree.
#[derive(Debug, Clone, PartialEq)]
pub struct NoiseTerms {
    /// The slope method.
    pub slope: SlopeResult,
    /// The model fit.
    pub fit: FitResult,
    /// Terms both identified whose intervals do not overlap, with a sentence.
    pub disagreements: Vec<(Term, String)>,
}

/// One value per noise term, each in a field of its own: a term's
/// estimate is had by naming the term, never by its position in a list.
#[derive(Debug, Clone, PartialEq)]
pub struct PerTerm<T> {
    /// Q.
    pub quantization: T,
    /// N.
    pub white_noise: T,
    /// B.
    pub bias_instability: T,
    /// K.
    pub rate_random_walk: T,
    /// R.
    pub rate_ramp: T,
}

impl<T> PerTerm<T> {
    /// `f` of each term, called in [`Term::ALL`] order.
    pub fn from_fn(mut f: impl FnMut(Term) -> T) -> Self {
        PerTerm {
            quantization: f(Term::Quantization),
            white_noise: f(Term::WhiteNoise),
            bias_instability: f(Term::BiasInstability),
            rate_random_walk: f(Term::RateRandomWalk),
            rate_ramp: f(Term::RateRamp),
        }
    }

    /// The value of `term`.
    pub fn get(&self, term: Term) -> &T {
        match term {
            Term::Quantization => &self.quantization,
            Term::WhiteNoise => &self.white_noise,
            Term::BiasInstability => &self.bias_instability,
            Term::RateRandomWalk => &self.rate_random_walk,
            Term::RateRamp => &self.rate_ramp,
        }
    }

    /// Each term with its value, in [`Term::ALL`] order.
    pub fn iter(&self) -> impl Iterator<Item = (Term, &T)> {
        Term::ALL.into_iter().map(move |t| (t, self.get(t)))
    }
}

/// What to show for a term: the estimate that holds, and how it was had.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Chosen {
    /// The fit's value.
    Fit(TermValue),
    /// The slope method's value (the fit could not separate the term).
    Slope(TermValue),
    /// Neither method could read it: its upper bound.
    Bound(f64),
    /// Nothing can be said.
    Nothing,
}

impl Chosen {
    /// The value: the estimate, or the bound.
    pub fn value(&self) -> Option<f64> {
        match self {
            Chosen::Fit(v) | Chosen::Slope(v) => Some(v.value),
            Chosen::Bound(b) => Some(*b),
            Chosen::Nothing => None,
        }
    }
}

/// A term's [`Chosen`] estimate and what a reader must know about it.
#[derive(Debug, Clone, PartialEq)]
pub struct Choice {
    /// The estimate.
    pub chosen: Chosen,
    /// The two methods disagree beyond their intervals (the fit is shown).
    pub disagree: bool,
    /// Why the estimate is not the fit's, when it is not.
    pub note: Option<&'static str>,
}

impl Choice {
    /// The value shown: the estimate, or the bound.
    pub fn value(&self) -> Option<f64> {
        self.chosen.value()
    }
}

impl NoiseTerms {
    /// The estimate of `term` that holds: the fit's, unless the fit cannot
    /// separate it; then the slope method's; then the term's upper bound.
    /// A rate random walk the fit found beside no bias instability is not
    /// taken as measured: flicker noise the fit could not resolve lifts the
    /// long-τ end of the curve the way a random walk does, so its K may be
    /// mostly B (the slope method's K, or the bound, is used instead).
    pub fn choose(&self, term: Term) -> Choice {
        let disagree = self.disagreements.iter().any(|(t, _)| *t == term);
        let slope = self.slope.get(term).value().copied();
        let fallback = |note| Choice {
            chosen: match (slope, self.slope.bound(term)) {
                (Some(v), _) => Chosen::Slope(v),
                (None, Some(b)) => Chosen::Bound(b),
                (None, None) => Chosen::Nothing,
            },
            disagree: false,
            note: Some(note),
        };
        match self.fit.get(term).value() {
            Some(_)
                if term == Term::RateRandomWalk && self.fit.get(Term::BiasInstability).value().is_none() =>
            {
                fallback(
                    "the fit's K stands beside no bias instability and may hold one it could not resolve",
                )
            }
            Some(v) => Choice {
                chosen: Chosen::Fit(*v),
                disagree,
                note: None,
            },
            None => fallback("the fit cannot separate this term"),
        }
    }
}

/// The overlapping ADEV of rate samples `y` at octave taus, and the noise
/// terms read from it by [`identify`] (the slope method on the `many` grid,
/// the fit on the octave points, intervals at `confidence`). The samples
/// are turned into phase once for both grids.
pub fn analyze_terms(
    y: &[f64],
    rate_hz: f64,
    confidence: f64,
) -> Result<(Vec<Point>, NoiseTerms), AllanError> {
    analyze_terms_vec(crate::phase::copy_with_room(y), rate_hz, confidence)
}

/// [`analyze_terms`], taking the samples by value so that they become the
/// phase in place: a long recording is not copied. Both grids are computed
/// in one pass over their union of averaging factors
/// ([`analyze_series_grids`]), each curve exactly as its grid alone gives it.
pub fn analyze_terms_vec(
    y: Vec<f64>,
    rate_hz: f64,
    confidence: f64,
) -> Result<(Vec<Point>, NoiseTerms), AllanError> {
    let series = PhaseSeries::from_vec(y, DataType::Freq, rate_hz)?;
    let opts = Options {
        rate_hz,
        confidence,
        ..Options::default()
    };
    let mut curves = analyze_series_grids(&series, &opts, &[TauSpec::Octave, TauSpec::Many])?.into_iter();
    let (Some(sparse), Some(dense)) = (curves.next(), curves.next()) else {
        unreachable!("analyze_series_grids returns one curve per grid")
    };
    let terms = identify(&dense, &sparse, confidence);
    Ok((sparse, terms))
}

/// Identifies the noise terms from an overlapping ADEV curve of rate data:
/// the slope method on `dense` (a fine tau grid such as `many`, so the
/// minimum and the slopes are read where they are), the fit on `sparse`
/// (octave taus, nearly independent points), with fit intervals at
/// `confidence`.
pub fn identify(dense: &[Point], sparse: &[Point], confidence: f64) -> NoiseTerms {
    let slope = slope_method(dense);
    let fit = fit_model(sparse, confidence);
    let mut disagreements = Vec::new();
    for term in Term::ALL {
        if let (Some(a), Some(b)) = (slope.get(term).value(), fit.get(term).value())
            && (a.hi < b.lo || b.hi < a.lo)
        {
            let why = if term == Term::BiasInstability {
                "σ_min also holds the white noise and random walk around the minimum, which the fit separates"
            } else {
                "another term overlaps where the slope was read"
            };
            disagreements.push((
                term,
                format!(
                    "{}: slope method {:.4e} [{:.4e}, {:.4e}] and fit {:.4e} [{:.4e}, {:.4e}] disagree \
                     beyond their intervals ({why})",
                    term.symbol(),
                    a.value,
                    a.lo,
                    a.hi,
                    b.value,
                    b.lo,
                    b.hi
                ),
            ));
        }
    }
    NoiseTerms {
        slope,
        fit,
        disagreements,
    }
}

#[cfg(test)]
mod per_term_tests {
    use super::*;

    #[test]
    fn each_term_has_its_own_field() {
        let per = PerTerm::from_fn(|t| t);
        for t in Term::ALL {
            assert_eq!(*per.get(t), t);
        }
        assert_eq!(per.iter().map(|(t, _)| t).collect::<Vec<_>>(), Term::ALL);
    }
}
