//! One estimator of an inertial sensor's noise model that chooses its own
//! terms: the theoretical Allan variance of a sum of candidate processes
//! ([`process`]) is fitted to the measured overlapping AVAR by weighted
//! nonlinear least squares ([`lm`]), every candidate sum is fitted, and an
//! information criterion decides which processes the data holds ([`select`]).
//!
//! The candidates: quantization Q, white noise N, bias instability B
//! (flicker), rate random walk K, rate ramp R, and up to two first-order
//! Gauss–Markov processes (σ, T). This is the approach of GMWM (Guerrier,
//! Skaloud, Stebler & Victoria-Feser, "Wavelet-variance-based estimation for
//! composite stochastic processes", JASA 108, 2013), on the Allan variance
//! (which is twice the Haar wavelet variance), in its two steps: a first
//! fit with the points taken as independent, then every candidate fitted
//! again with the efficient weights, the inverse of the covariance of the
//! points under the first fit's model ([`covariance`]: neighbouring octave
//! points share most of their data). The Bayesian information criterion
//! stands in for WVIC (both penalise a fit's χ² by its parameter count).
//!
//! Rules every result keeps (each has a test in `tests/noise_model.rs`):
//! - a term enters a model only where it carries at least [`SHOW_SHARE`]
//!   of the model's variance at [`MIN_POINTS`] points or more, holding
//!   [`MIN_TERM_EDF`] degrees of freedom between them;
//! - no kept term's own Allan variance exceeds, at any point with
//!   [`MIN_EDF`] degrees of freedom, the upper end of the measured
//!   variance's [`CEILING_CONFIDENCE`] interval (the [`ceiling`]) with the
//!   point weighed as the fit weighs it;
//! - a term the criterion leaves out, or one no point can show, is given as
//!   an upper bound, never as a value: the smallest ceiling along its own
//!   line, each point's ceiling taken with the point's own EDF, the one its
//!   printed interval has, so that no bound stands above a printed
//!   deviation's 99 % end; so is every term when no candidate fits (p below
//!   [`FIT_P_VALUE`]), and [`NoiseModel::defeat`] says where the best
//!   candidate parts from the curve.

pub mod ceiling;
pub mod covariance;
pub mod lm;
pub mod lowpass;
pub mod periodic;
pub mod process;
pub mod range;
mod select;

use statrs::distribution::{ContinuousCDF, Normal, StudentsT};

use crate::Point;
use crate::noise_terms::{PerTerm, Term, TermEstimate, TermValue};
use ceiling::Ceiling;
use lm::{Component, Data, model_avar};
use nalgebra::DMatrix;
pub use select::Candidate;

/// Largest EDF a point is weighted with: a 1 % standard deviation of σ².
/// No sensor is exact power laws down to τ0 (its anti-alias filter, the
/// sampling itself, a flicker spectrum that ends somewhere); trusting the
/// short-τ points of a long record to 0.1 % would let a model error of that
/// size decide the fit. The cap sets the fit's weights only: the intervals
/// take each point's spread from its own EDF (`select::Best::spreads`).
pub const MAX_FIT_EDF: f64 = 20_000.0;

/// Share of the model's variance a process must carry at a point to count
/// as shown there.
pub const SHOW_SHARE: f64 = 0.5;

/// Fewest points at which a process must show.
pub const MIN_POINTS: usize = 2;

/// Fewest degrees of freedom, summed over the points where it shows, that
/// a process must rest on: with 10, σ² is known to about ±45 %.
pub const MIN_TERM_EDF: f64 = 10.0;

/// Fewest degrees of freedom of a point for its ceiling to bound a term.
pub const MIN_EDF: f64 = 10.0;

/// Confidence (two-sided) of the measured interval whose upper end no term
/// may exceed.
pub const CEILING_CONFIDENCE: f64 = 0.99;

/// A fit whose χ² has a p-value below this is no description of the curve.
pub const FIT_P_VALUE: f64 = 0.01;

/// A first-order Gauss–Markov term.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GaussMarkovTerm {
    /// Its standard deviation σ, in the unit of the rate data.
    pub sigma: TermValue,
    /// Its correlation time T, s.
    pub tau_c: TermValue,
}

/// How well the selected model fits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quality {
    /// χ² of the fit (on ln σ̂², weighted by each point's EDF).
    pub chi2: f64,
    /// Points minus parameters.
    pub dof: usize,
    /// χ²/dof.
    pub chi2_reduced: f64,
    /// P(χ²_dof ≥ χ²).
    pub p_value: f64,
    /// The information criterion: χ² + (parameters)·ln(points).
    pub criterion: f64,
}

/// Where the best candidate parts from the measured curve, when no
/// candidate fits it.
#[derive(Debug, Clone, PartialEq)]
pub struct Defeat {
    /// The candidate ("N + K"): the selected model where one was selected
    /// and does not fit (p below [`FIT_P_VALUE`]); where none keeps the
    /// rules, the one of lowest criterion that the ceiling rules out.
    pub candidate: String,
    /// The process whose own line exceeds the measured ceiling at `tau`
    /// ("K"); `None` where it is the candidate's whole curve that misses
    /// the point.
    pub process: Option<String>,
    /// τ of that point, s.
    pub tau: f64,
    /// The measured deviation over the candidate's curve there (over the
    /// process's own line where `process` is given): below 1 where the
    /// candidate stands above the curve.
    pub ratio: f64,
    /// The miss in the point's own standard deviations of ln σ̂², as the
    /// fit weighs it (a misfit only).
    pub sigmas: Option<f64>,
}

impl Defeat {
    /// One sentence saying where the candidate parts from the curve.
    pub fn describe(&self) -> String {
        match (&self.process, self.sigmas) {
            (Some(p), _) => format!(
                "the best candidate, {}, has {p} above the measured deviation's {:.0} % upper end at τ = {} s \
                 (measured/{p} = {:.3})",
                self.candidate,
                100.0 * CEILING_CONFIDENCE,
                tau_text(self.tau),
                self.ratio
            ),
            (None, s) => format!(
                "{} misses the curve most at τ = {} s (measured/model = {:.3}{})",
                self.candidate,
                tau_text(self.tau),
                self.ratio,
                s.map(|s| format!(", {s:.1} standard deviations"))
                    .unwrap_or_default()
            ),
        }
    }
}

/// τ in seconds, its decimals to 0.1 ms, trailing zeros dropped; in
/// scientific notation below a millisecond.
fn tau_text(tau: f64) -> String {
    if tau < 1e-3 {
        return format!("{tau:.3e}");
    }
    let s = format!("{tau:.4}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// The selected noise model of one curve.
#[derive(Debug, Clone, PartialEq)]
pub struct NoiseModel {
    /// The five IEEE 952 terms: a value with its interval where the model
    /// holds the term, else why not.
    pub terms: PerTerm<TermEstimate>,
    /// Each term's upper bound (the smallest ceiling along its line), where
    /// the curve has a point to set one.
    pub bounds: PerTerm<Option<f64>>,
    /// Gauss–Markov terms of the model, by correlation time (never the
    /// sensor's filter: see `low_pass`).
    pub gauss_markov: Vec<GaussMarkovTerm>,
    /// The first-order low-pass filter the white noise passes through,
    /// where the curve shows one at its shortest τ ([`lowpass`]): N is
    /// then the white noise before the filter.
    pub low_pass: Option<lowpass::LowPass>,
    /// A periodic disturbance beside the noise processes, where the curve
    /// has a sinusoid's bump that the family alone does not describe
    /// ([`periodic`]): named, never a noise term. Its Allan variance is in
    /// [`NoiseModel::avar`] and [`NoiseModel::lines`].
    pub periodic: Option<periodic::Periodic>,
    /// The model, as its processes' symbols ("N + B + K"); "none" when no
    /// candidate was admissible.
    pub label: String,
    /// Whether the selected model describes the curve over `fit_range`:
    /// p ≥ [`FIT_P_VALUE`], or every point within [`range::TOLERANCE`] of
    /// the model (the misfit then widens the
    /// intervals). Its terms are values only then.
    pub fits: bool,
    /// Whether it fits within the points' own noise (p ≥ [`FIT_P_VALUE`]).
    pub within_noise: bool,
    /// The τ range the model was fitted over, and the curve beyond it
    /// against the model (`None` without a model).
    pub fit_range: Option<range::FitRange>,
    /// Its goodness of fit.
    pub quality: Option<Quality>,
    /// χ²/dof, as [`Quality::chi2_reduced`].
    pub chi2_reduced: Option<f64>,
    /// Points fitted.
    pub points: usize,
    /// Confidence of the intervals.
    pub confidence: f64,
    /// τ of points left out as no process of the candidates (a bump, a
    /// tone), only ever when the model did not fit with them.
    pub left_out: Vec<f64>,
    /// τ of the fitted points whose measured interval the model's curve
    /// leaves.
    pub outside: Vec<f64>,
    /// For each process of the model, how much worse the criterion is for
    /// the best admissible model without it: why it was kept.
    pub evidence: Vec<(String, f64)>,
    /// The best admissible candidates, best first.
    pub candidates: Vec<Candidate>,
    /// Where no candidate fits: where the best one parts from the curve.
    pub defeat: Option<Defeat>,
    components: Vec<Component>,
    theta: Vec<f64>,
}

impl NoiseModel {
    /// The estimate of one term.
    pub fn get(&self, term: Term) -> &TermEstimate {
        self.terms.get(term)
    }

    /// The upper bound of one term.
    pub fn bound(&self, term: Term) -> Option<f64> {
        *self.bounds.get(term)
    }

    /// The model's Allan variance at τ (zero without a model).
    pub fn avar(&self, tau: f64) -> f64 {
        if self.components.is_empty() {
            return 0.0;
        }
        model_avar(&self.components, &self.theta, tau) + self.periodic.map_or(0.0, |t| t.avar(tau))
    }

    /// Each process of the model with its symbol and its own Allan
    /// variance at τ: the lines a plot draws under the curve.
    pub fn lines(&self, tau: f64) -> Vec<(String, f64)> {
        let mut at = 0;
        let labels = select::labels(&self.components);
        let mut lines: Vec<(String, f64)> = self
            .components
            .iter()
            .zip(labels)
            .map(|(c, l)| {
                let v = c.avar(&self.theta[at..at + c.arity()], tau);
                at += c.arity();
                (l, v)
            })
            .collect();
        if let Some(t) = &self.periodic {
            lines.push(("periodic".to_string(), t.avar(tau)));
        }
        lines
    }
}

/// The selected noise model of an overlapping ADEV curve of rate data
/// (octave taus are best: nearly independent points), intervals at
/// `confidence`.
///
/// Where no candidate describes the whole curve, the curve is fitted over
/// a narrower τ range ([`range`]): the end the best candidate parts from
/// is dropped, one point at a time, until a candidate keeps the rules and
/// describes the points left; the range is printed and the curve's misses
/// beyond it are named ([`FitRange`]).
pub fn estimate(points: &[Point], confidence: f64) -> NoiseModel {
    let pts: Vec<Point> = points
        .iter()
        .copied()
        .filter(|p| p.dev.is_finite() && p.dev > 0.0 && p.edf.is_finite() && p.edf > 0.0 && p.tau > 0.0)
        .collect();
    // Every measured point bounds the terms the model leaves out, the
    // left-out points too: a point the model cannot describe is still a
    // deviation no bound may exceed.
    let ceilings = ceiling::ceilings(&pts);
    let found = search(&pts);
    build(&pts, found, &ceilings, confidence)
}

/// The fit of the whole curve where the family describes it; else, where
/// the curve has a bump, the family with a periodic disturbance beside it
/// over the range it describes ([`periodic::search`]); else the family's
/// range alone ([`range::search`]).
fn search(pts: &[Point]) -> range::Found {
    let whole = |attempt, slack| range::Found {
        start: 0,
        end: pts.len(),
        skipped: Vec::new(),
        slack,
        attempt,
    };
    let strict = fit_plain(pts, 1.0);
    if strict.describes() || pts.len() <= range::MIN_POINTS {
        return whole(strict, 1.0);
    }
    if let Some(found) = periodic::search(pts, &fit_plain) {
        return found;
    }
    range::search(pts, fit_window)
}

/// [`fit_plain`], and where that does not describe the window, the window
/// with a sinusoid of its own beside the family ([`periodic::on_window`]).
fn fit_window(points: &[Point], slack: f64) -> Attempt {
    let plain = fit_plain(points, slack);
    if plain.describes() {
        return plain;
    }
    periodic::on_window(points, slack, &fit_plain).unwrap_or(plain)
}

/// One fit of a run of points: the selection, the points as last
/// weighted, and the τ of points left out as no candidate process.
pub(crate) struct Attempt {
    used: Vec<Point>,
    sel: select::Selection,
    left_out: Vec<f64>,
    /// The periodic disturbance fitted beside the family, whose Allan
    /// variance `used` has had taken off ([`periodic`]).
    tone: Option<periodic::Periodic>,
}

impl Attempt {
    /// Whether the selected model describes the points it was fitted to:
    /// p at least [`FIT_P_VALUE`], or every point within
    /// [`range::TOLERANCE`] of the model.
    fn describes(&self) -> bool {
        let Some(best) = &self.sel.best else {
            return false;
        };
        let tone = |tau: f64| self.tone.map_or(0.0, |t| t.avar(tau));
        fits(best.quality.p_value)
            || range::within_tolerance_beside(&best.components, &best.theta, &self.used, tone)
    }

    /// The index of the point the selected model misses as an outlier
    /// (`select::outlier`), if any.
    fn outlier_at(&self) -> Option<usize> {
        self.sel.best.as_ref().and_then(|b| select::outlier(&b.resid))
    }

    /// τ where the best candidate parts from the points: where its worst
    /// process exceeds the ceiling, or where the selected model misses
    /// most.
    fn parting_tau(&self) -> Option<f64> {
        match &self.sel.best {
            Some(best) => misfit(best, &self.used).map(|d| d.tau),
            None => self.sel.defeated.as_ref().map(|d| d.tau),
        }
    }
}

/// Selects on `pts`, leaving out the worst-missed point (a bump, a tone)
/// while no candidate fits, up to a quarter of the points; the ceiling
/// times `slack` holds the kept processes.
fn fit_plain(points: &[Point], slack: f64) -> Attempt {
    let mut pts = points.to_vec();
    let mut left_out = Vec::new();
    let budget = pts.len() / 4;
    loop {
        let (used, sel) = select_reweighed(&pts, slack);
        if let Some(best) = &sel.best
            && !fits(best.quality.p_value)
            && left_out.len() < budget
            && pts.len() > 6
            && let Some(worst) = select::outlier(&best.resid)
        {
            left_out.push(pts[worst].tau);
            pts.remove(worst);
            continue;
        }
        left_out.sort_unstable_by(f64::total_cmp);
        return Attempt {
            used,
            sel,
            left_out,
            tone: None,
        };
    }
}

/// Passes of selection with the points weighed under the last model.
const MODEL_PASSES: usize = 2;

/// The power-law exponents α the EDF tables hold for the overlapping ADEV.
const ALPHAS: [i32; 5] = [2, 1, 0, -1, -2];

/// `pts` with each point's EDF the smallest any noise type gives it: before
/// there is a model, no point is trusted more than its least favourable
/// noise allows (the points' own noise identification, one point at a
/// time, can name white phase noise at the long τ of white rate noise and
/// give a point a hundred times its degrees of freedom).
fn cautious(pts: &[Point]) -> Vec<Point> {
    pts.iter()
        .map(|p| {
            let n_phase = p.n + 2 * p.m;
            let edf = ALPHAS
                .iter()
                .filter_map(|&a| crate::edf::edf_for(crate::Stat::Oadev, a, p.m, n_phase))
                .fold(p.edf, f64::min);
            Point { edf, ..*p }
        })
        .collect()
}

/// The points weighed under a fitted model: each point's EDF 2·AVAR²/Var
/// and the correlations between the points, both from the covariance of
/// the estimates under the model ([`covariance`]). `None` where that
/// covariance cannot weigh them (a model of trends alone, points of
/// different τ0).
fn efficient(best: &select::Best, pts: &[Point]) -> Option<(Vec<Point>, DMatrix<f64>)> {
    let tau0 = pts.first().map(|p| p.tau / p.m as f64)?;
    let estimates: Vec<covariance::Estimate> = pts
        .iter()
        .map(|p| covariance::Estimate { m: p.m, tau0, n: p.n })
        .collect();
    if pts
        .iter()
        .any(|p| p.m == 0 || ((p.tau / p.m as f64) / tau0 - 1.0).abs() > 1e-6)
    {
        return None;
    }
    let cov = covariance::matrix(&best.components, &best.theta, &estimates);
    let var: Vec<f64> = (0..pts.len()).map(|i| cov[(i, i)]).collect();
    if var.iter().any(|v| !(v.is_finite() && *v > 0.0)) {
        return None;
    }
    let corr = DMatrix::from_fn(pts.len(), pts.len(), |i, j| {
        cov[(i, j)] / (var[i] * var[j]).sqrt()
    });
    let used = pts
        .iter()
        .zip(&var)
        .map(|(p, v)| {
            let avar = model_avar(&best.components, &best.theta, p.tau);
            let edf = 2.0 * avar * avar / v;
            Point {
                edf: if edf.is_finite() && edf > 0.0 { edf } else { p.edf },
                ..*p
            }
        })
        .collect();
    Some((used, corr))
}

/// Selects on `pts` weighted with [`cautious`] EDFs as independent points,
/// then again with the points weighed under the selected model
/// ([`efficient`], or where it cannot, [`select::Best::reweigh`]'s EDFs
/// alone): the two-step GMWM, whose second step fits with the efficient
/// weights of the first step's model. Returns the points as last weighted
/// and the selection.
fn select_reweighed(pts: &[Point], slack: f64) -> (Vec<Point>, select::Selection) {
    let mut used = cautious(pts);
    let mut sel = select::select(&used, None, slack);
    for _ in 0..MODEL_PASSES {
        let Some(best) = &sel.best else { break };
        let next = match efficient(best, pts) {
            Some((next_used, corr)) => {
                let next = select::select(&next_used, Some(&corr), slack);
                (next_used, next)
            }
            None => {
                let next_used = best.reweigh(pts);
                let next = select::select(&next_used, None, slack);
                (next_used, next)
            }
        };
        // A weighting under which no candidate keeps the rules is no
        // better knowledge of the points than the one before it.
        if next.1.best.is_none() {
            break;
        }
        (used, sel) = next;
    }
    (used, sel)
}

fn fits(p: f64) -> bool {
    p >= FIT_P_VALUE
}

fn build(all: &[Point], found: range::Found, ceilings: &[Ceiling], confidence: f64) -> NoiseModel {
    let describes = found.attempt.describes();
    let range::Found {
        start,
        end,
        skipped,
        slack,
        attempt:
            Attempt {
                used: pts,
                sel,
                mut left_out,
                tone,
            },
    } = found;
    left_out.extend(skipped.iter().map(|&i| all[i].tau));
    left_out.sort_unstable_by(f64::total_cmp);
    let pts = &pts[..];
    let bounds = PerTerm::from_fn(|t| ceiling::bound(ceilings, |tau| lm::power_basis(t, tau)));
    // A kept term's interval is capped by the points it was fitted to: a
    // point beyond the range (the filter's dip) bounds no term in it.
    let in_range = ceiling::ceilings(&all[start..end]);
    let caps = PerTerm::from_fn(|t| {
        ceiling::bound(&in_range, |tau| lm::power_basis(t, tau)).map(|b| b * slack.sqrt())
    });
    let Some(best) = sel.best else {
        let why = if pts.len() < 2 {
            "not identifiable: fewer than 2 points on the curve".to_string()
        } else {
            format!(
                "no candidate model fits the curve: none keeps the rules (each term shown at \
                 {MIN_POINTS} points with {MIN_TERM_EDF} degrees of freedom, none above the measured ceiling){}",
                sel.defeated
                    .as_ref()
                    .map(|d| format!("; {}", d.describe()))
                    .unwrap_or_default()
            )
        };
        return NoiseModel {
            terms: PerTerm::from_fn(|_| TermEstimate::NotIdentifiable(why.clone())),
            bounds,
            gauss_markov: Vec::new(),
            low_pass: None,
            periodic: None,
            label: "none".to_string(),
            fits: false,
            within_noise: false,
            fit_range: None,
            quality: None,
            chi2_reduced: None,
            points: pts.len(),
            confidence,
            left_out,
            outside: Vec::new(),
            evidence: Vec::new(),
            candidates: sel.ranked,
            defeat: sel.defeated,
            components: Vec::new(),
            theta: Vec::new(),
        };
    };
    let q = best.quality;
    let within_noise = fits(q.p_value);
    let defeat = (!describes).then(|| misfit(&best, pts)).flatten();
    let spreads = best.spreads();
    // Student's t on the fit's degrees of freedom where the spreads rest on
    // the fit's own residual scatter (it exceeds what the points' covariance
    // allows, and sets their scale); the normal quantile where they rest on
    // the model's covariance of the points alone, a scale known rather
    // than estimated.
    let p_quantile = 0.5 + confidence / 2.0;
    let z = if spreads.rescaled {
        StudentsT::new(0.0, 1.0, q.dof as f64).map_or(f64::INFINITY, |d| d.inverse_cdf(p_quantile))
    } else {
        Normal::new(0.0, 1.0).map_or(f64::INFINITY, |d| d.inverse_cdf(p_quantile))
    };
    let interval = |at: usize, half: f64| -> (f64, f64, f64) {
        let th = best.theta[at];
        let sd = spreads.sd[at];
        (
            (th * half).exp(),
            ((th - z * sd) * half).exp(),
            ((th + z * sd) * half).exp(),
        )
    };
    // A Gauss–Markov process whose T lies at the sampling interval is the
    // sensor's filter on its white noise: it is reported as N and the
    // filter, never as a GM.
    let tau_first = pts.first().map_or(0.0, |p| p.tau);
    let filter = lowpass::find(&best.components, &best.theta, tau_first);
    let mut found: Vec<(Term, TermValue)> = Vec::new();
    let mut gauss_markov = Vec::new();
    let mut low_pass = None;
    let mut at = 0;
    for (k, c) in best.components.iter().enumerate() {
        match c {
            Component::Power(Term::WhiteNoise) if filter.is_some() => {}
            Component::Power(t) => {
                let (v, lo, hi) = interval(at, 0.5);
                let cap = caps.get(*t).unwrap_or(f64::INFINITY);
                found.push((
                    *t,
                    TermValue {
                        value: v,
                        lo,
                        hi: hi.min(cap.max(v)),
                        tau: None,
                    },
                ));
            }
            Component::GaussMarkov if filter == Some(k) => {
                let (t, tlo, thi) = interval(at + 1, 1.0);
                let n = lowpass::white_noise(&best.components, &best.theta, k, &spreads, z);
                // Capped along the filtered process's own curve.
                let cap = ceiling::bound(&in_range, |tau| process::gauss_markov(tau, t) / (2.0 * t))
                    .map_or(f64::INFINITY, |b| b * slack.sqrt());
                found.push((
                    Term::WhiteNoise,
                    TermValue {
                        hi: n.hi.min(cap.max(n.value)),
                        ..n
                    },
                ));
                low_pass = Some(lowpass::LowPass {
                    tau_c: TermValue {
                        value: t,
                        lo: tlo,
                        hi: thi,
                        tau: None,
                    },
                    cutoff_hz: 1.0 / (std::f64::consts::TAU * t),
                });
            }
            Component::GaussMarkov => {
                let (s, slo, shi) = interval(at, 0.5);
                let (t, tlo, thi) = interval(at + 1, 1.0);
                gauss_markov.push(GaussMarkovTerm {
                    sigma: TermValue {
                        value: s,
                        lo: slo,
                        hi: shi,
                        tau: None,
                    },
                    tau_c: TermValue {
                        value: t,
                        lo: tlo,
                        hi: thi,
                        tau: None,
                    },
                });
            }
        }
        at += c.arity();
    }
    gauss_markov.sort_by(|a, b| a.tau_c.value.total_cmp(&b.tau_c.value));
    let mut label = lowpass::label(&best.components, filter);
    if tone.is_some() {
        label.push_str(" + periodic");
    }
    // The reasons carry no number: the bound is in `bounds`, to be shown
    // in whatever unit the reader asked for.
    let terms = PerTerm::from_fn(|t| {
        if !describes {
            return TermEstimate::NotIdentifiable(format!(
                "no candidate model fits the curve (best {}: χ²/dof = {:.2}, p = {:.2e}){}",
                best.label,
                q.chi2_reduced,
                q.p_value,
                defeat
                    .as_ref()
                    .map(|d| format!("; {}", d.describe()))
                    .unwrap_or_default()
            ));
        }
        match found.iter().find(|(ft, _)| *ft == t) {
            Some((_, v)) => TermEstimate::Value(*v),
            None => TermEstimate::NotIdentifiable(format!(
                "not in the selected model ({label}): the information criterion keeps the curve without it"
            )),
        }
    });
    let outside = pts
        .iter()
        .filter(|p| {
            let m = model_avar(&best.components, &best.theta, p.tau).sqrt();
            m < p.dev_lo || m > p.dev_hi
        })
        .map(|p| p.tau)
        .collect();
    // The measured curve beyond the range against the whole model, the
    // periodic disturbance with the family.
    let miss = |p: &Point| range::Miss {
        tau: p.tau,
        ratio: p.dev
            / (model_avar(&best.components, &best.theta, p.tau) + tone.map_or(0.0, |t| t.avar(p.tau))).sqrt(),
    };
    let fit_range = (start < end).then(|| range::FitRange {
        lo: all[start].tau,
        hi: all[end - 1].tau,
        whole: start == 0 && end == all.len(),
        misses: all[..start].iter().chain(&all[end..]).map(miss).collect(),
        features: skipped.iter().map(|&i| miss(&all[i])).collect(),
    });
    NoiseModel {
        terms,
        bounds,
        gauss_markov: if describes { gauss_markov } else { Vec::new() },
        low_pass: if describes { low_pass } else { None },
        periodic: if describes { tone } else { None },
        label,
        fits: describes,
        within_noise,
        fit_range,
        quality: Some(q),
        chi2_reduced: Some(q.chi2_reduced),
        points: pts.len(),
        confidence,
        left_out,
        outside,
        evidence: sel.evidence,
        candidates: sel.ranked,
        defeat,
        components: best.components.clone(),
        theta: best.theta.clone(),
    }
}

/// Where a selected model that does not fit misses the curve most: the
/// point of largest standardised residual.
fn misfit(best: &select::Best, pts: &[Point]) -> Option<Defeat> {
    let (i, r) = best
        .resid
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))?;
    let p = pts.get(i)?;
    Some(Defeat {
        candidate: best.label.clone(),
        process: None,
        tau: p.tau,
        ratio: p.dev / model_avar(&best.components, &best.theta, p.tau).sqrt(),
        sigmas: Some(r.abs()),
    })
}

/// The data of the fit: each point's (τ, σ̂², ν) with ν capped at
/// [`MAX_FIT_EDF`].
fn data_of(pts: &[Point]) -> Data {
    Data::new(pts.iter().map(|p| (p.tau, p.dev * p.dev, p.edf.min(MAX_FIT_EDF))))
}
