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
//! One estimator gives the terms: the noise model of
//! [`crate::noise_model`], fitted to the octave curve, which chooses its own
//! terms and gives each a value with its interval or an upper bound
//! ([`NoiseTerms::choose`]). Beside it, by name and for comparison only:
//! the curve's minimum σ_min and where it lies, which the thesis tables
//! quote ([`slope_method`], the IEEE 952 slope reading that also finds
//! the minimum), and the thesis's own reading ([`thesis_reading`]).
//!
//! Units: the terms are in the unit of the rate data and seconds: N in
//! unit/√Hz = unit·√s, B in unit, K in unit/√s, Q in unit·s, R in unit/s.

mod slope;
mod thesis;

pub use slope::{MIN_EDF, Minimum, SlopeResult, slope_method};
pub use thesis::{ThesisReading, thesis_reading};

use crate::analysis::analyze_series_grids;
use crate::noise_model::{NoiseModel, estimate};
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

/// A curve's noise terms: the selected model, and beside it the curve's
/// minimum and the thesis's reading.
#[derive(Debug, Clone, PartialEq)]
pub struct NoiseTerms {
    /// The IEEE 952 slope reading of the dense curve: kept for σ_min, where
    /// the minimum lies, and the thesis's reading; its term values are no
    /// output's.
    pub slope: SlopeResult,
    /// The selected noise model: the terms every output reads.
    pub model: NoiseModel,
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

/// What to show for a term.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Chosen {
    /// The selected model's value.
    Model(TermValue),
    /// Not in the model (or no model fits): its upper bound.
    Bound(f64),
    /// Nothing can be said.
    Nothing,
}

impl Chosen {
    /// The value: the estimate, or the bound.
    pub fn value(&self) -> Option<f64> {
        match self {
            Chosen::Model(v) => Some(v.value),
            Chosen::Bound(b) => Some(*b),
            Chosen::Nothing => None,
        }
    }
}

/// A term's [`Chosen`] estimate and why it is not a value, when it is not.
#[derive(Debug, Clone, PartialEq)]
pub struct Choice {
    /// The estimate.
    pub chosen: Chosen,
    /// Why the term is only bounded, or unknown.
    pub note: Option<String>,
}

impl Choice {
    /// The value shown: the estimate, or the bound.
    pub fn value(&self) -> Option<f64> {
        self.chosen.value()
    }
}

impl NoiseTerms {
    /// The one answer for `term`: the model's value where the selected
    /// model holds it and fits the curve; else its upper bound.
    pub fn choose(&self, term: Term) -> Choice {
        match self.model.get(term) {
            TermEstimate::Value(v) => Choice {
                chosen: Chosen::Model(*v),
                note: None,
            },
            TermEstimate::NotIdentifiable(why) => Choice {
                chosen: self.model.bound(term).map_or(Chosen::Nothing, Chosen::Bound),
                note: Some(why.clone()),
            },
        }
    }
}

/// The overlapping ADEV of rate samples `y` at octave taus, and the noise
/// terms read from it by [`identify`] (σ_min on the `many` grid, the model
/// on the octave points, intervals at `confidence`). The samples
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
/// the model on `sparse` (octave taus, nearly independent points) with
/// intervals at `confidence`; σ_min and the thesis's reading on `dense`
/// (a fine tau grid such as `many`, so the minimum is read where it is).
pub fn identify(dense: &[Point], sparse: &[Point], confidence: f64) -> NoiseTerms {
    NoiseTerms {
        slope: slope_method(dense),
        model: estimate(sparse, confidence),
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
