//! Model selection: every candidate sum of processes is fitted, those that
//! break a rule of [`super`] are set aside, and the lowest information
//! criterion χ² + p·ln n among the rest is the model (Schwarz 1978; the
//! role WVIC plays in GMWM, Guerrier et al. 2013 §4).

use nalgebra::DMatrix;
use rayon::prelude::*;
use statrs::distribution::{ChiSquared, ContinuousCDF};

use super::ceiling::{self, Ceiling};
use super::lm::{self, Component, Data, TcRange, model_avar};
use super::{Defeat, MAX_FIT_EDF, MIN_POINTS, MIN_TERM_EDF, Quality, SHOW_SHARE, data_of};
use crate::Point;
use crate::noise_terms::Term;

/// A candidate model that kept every rule, with its criterion.
#[derive(Debug, Clone, PartialEq)]
pub struct Candidate {
    /// Its processes ("N + K").
    pub label: String,
    /// χ² + p·ln n.
    pub criterion: f64,
    /// χ² of its fit.
    pub chi2: f64,
    /// p, its number of parameters.
    pub parameters: usize,
}

/// The standard deviations of a fit's log-parameters.
pub(super) struct Spreads {
    /// One per parameter.
    pub sd: Vec<f64>,
    /// The correlations between the parameters (the identity where they
    /// are unknown): what a quantity read from two of them, such as the
    /// white noise 2σ²T of a filter-shaped Gauss–Markov term, needs.
    pub corr: DMatrix<f64>,
    /// Whether they were scaled up by the fit's measured misfit: their
    /// scale then rests on the residuals, an estimate on the fit's degrees
    /// of freedom, and not on the points' known covariance alone.
    pub rescaled: bool,
}

/// The selected model's fit.
pub(super) struct Best {
    pub components: Vec<Component>,
    pub theta: Vec<f64>,
    pub label: String,
    pub quality: Quality,
    pub resid: Vec<f64>,
    jac: DMatrix<f64>,
    /// The lower Cholesky factor of the points' correlation matrix, where
    /// the fit weighed the points with their correlations.
    whiten: Option<DMatrix<f64>>,
    /// Each point's standard deviation of ln σ̂² under its own EDF over the
    /// one the fit weighed it with (below 1 where [`MAX_FIT_EDF`] capped
    /// it).
    capped: Vec<f64>,
}

impl Best {
    /// Standard deviation of each log-parameter.
    ///
    /// Weighed with the points' correlations: the covariance of a weighted
    /// least-squares estimate whose weights W are not the inverse of the
    /// residuals' covariance Σ, (JᵀWJ)⁻¹ JᵀWΣWJ (JᵀWJ)⁻¹ (the "sandwich" of
    /// a fit with working weights: Liang & Zeger, "Longitudinal data
    /// analysis using generalized linear models", Biometrika 73, 1986). The fit
    /// weighs each point with its EDF capped at [`MAX_FIT_EDF`], a variance
    /// larger than the model's own; taking that larger variance as the
    /// points' true one, as (JᵀWJ)⁻¹ alone does, widens the intervals of the
    /// terms read at short τ (N, Q) beyond the estimates' actual scatter.
    /// Σ is the model's covariance of the points (uncapped EDFs, their
    /// correlations), scaled up by the fit's measured misfit where the
    /// model misses the points by more than Σ allows: χ² over its
    /// expectation under Σ, tr((I − H)·M) in the whitened frame (H the hat
    /// matrix, M the whitened Σ), which is χ²/dof when nothing is capped.
    ///
    /// Where the points were weighed as independent: from (JᵀJ)⁻¹, scaled
    /// up by χ²/dof, and never below what the single most telling point
    /// gives alone (1/max |J_ik|): neighbouring octave points share most of
    /// their data, so their errors are positively correlated and the
    /// independent-points covariance is too optimistic; the single-point
    /// spread is its fully correlated limit.
    pub fn spreads(&self) -> Spreads {
        let p = self.jac.ncols();
        let Some(cov) = (self.jac.transpose() * &self.jac).try_inverse() else {
            return Spreads {
                sd: vec![f64::INFINITY; p],
                corr: DMatrix::identity(p, p),
                rescaled: false,
            };
        };
        if let Some(l) = &self.whiten {
            return self.sandwich(l, &cov);
        }
        let inflate = self.quality.chi2_reduced.max(1.0);
        let sd = (0..p)
            .map(|k| {
                let single = self
                    .jac
                    .column(k)
                    .iter()
                    .map(|j| 1.0 / j.abs())
                    .fold(f64::INFINITY, f64::min);
                let joint = (cov[(k, k)].max(0.0) * inflate).sqrt();
                joint.max(single)
            })
            .collect();
        Spreads {
            sd,
            corr: correlation(&cov),
            rescaled: inflate > 1.0,
        }
    }

    /// The sandwich of [`Best::spreads`], given L (the points' correlation
    /// R = LLᵀ) and (JᵀWJ)⁻¹ = (JᵀJ)⁻¹ of the whitened Jacobian J.
    fn sandwich(&self, l: &DMatrix<f64>, bread: &DMatrix<f64>) -> Spreads {
        let n = self.jac.nrows();
        let p = self.jac.ncols();
        // Σ = S D R D S and W = (S R S)⁻¹ with S the fit's standard
        // deviations and D = diag(capped): whitened by L⁻¹S⁻¹, Σ becomes
        // M = (L⁻¹DL)(L⁻¹DL)ᵀ.
        let dl = DMatrix::from_fn(n, n, |i, j| self.capped[i] * l[(i, j)]);
        let Some(root) = l.clone().solve_lower_triangular(&dl) else {
            return Spreads {
                sd: vec![f64::INFINITY; p],
                corr: DMatrix::identity(p, p),
                rescaled: false,
            };
        };
        let m = &root * root.transpose();
        let meat = self.jac.transpose() * &m * &self.jac;
        let cov = bread * meat * bread;
        let hat = &self.jac * bread * self.jac.transpose();
        let expected = (DMatrix::identity(n, n) - hat).component_mul(&m).sum();
        let inflate = if expected > 0.0 {
            (self.quality.chi2 / expected).max(1.0)
        } else {
            self.quality.chi2_reduced.max(1.0)
        };
        Spreads {
            sd: (0..p).map(|k| (cov[(k, k)].max(0.0) * inflate).sqrt()).collect(),
            corr: correlation(&cov),
            rescaled: inflate > 1.0,
        }
    }
}

/// The correlation matrix of a covariance (zero where a variance is not
/// positive).
fn correlation(cov: &DMatrix<f64>) -> DMatrix<f64> {
    let p = cov.nrows();
    DMatrix::from_fn(p, p, |i, j| {
        let d = (cov[(i, i)] * cov[(j, j)]).sqrt();
        if i == j {
            1.0
        } else if d > 0.0 && d.is_finite() {
            (cov[(i, j)] / d).clamp(-1.0, 1.0)
        } else {
            0.0
        }
    })
}

pub(super) struct Selection {
    pub best: Option<Best>,
    pub ranked: Vec<Candidate>,
    pub evidence: Vec<(String, f64)>,
    /// Among the candidates a ceiling rules out, where the one of lowest
    /// criterion breaks it.
    pub defeated: Option<Defeat>,
}

impl Best {
    /// `pts` with each point's EDF taken from the model: each process's own
    /// EDF (Greenhall's, of the overlapping ADEV, for the power-law α it
    /// shows there), combined by its share w_k of the variance as
    /// 1/√ν = Σ w_k/√ν_k. That is the standard deviation of a sum whose
    /// parts' errors are fully correlated, an upper bound (Minkowski) on
    /// that of the sum. The points' own noise identification reads one α
    /// from the data at each point and is thrown by mixtures: quantization
    /// lingering over white noise gives a white-phase α and an EDF in the
    /// tens of thousands to a point whose white-noise part has a few
    /// hundred.
    pub fn reweigh(&self, pts: &[Point]) -> Vec<Point> {
        pts.iter()
            .map(|p| {
                let n_phase = p.n + 2 * p.m;
                let total = model_avar(&self.components, &self.theta, p.tau);
                let mut at = 0;
                let mut inv_sqrt = 0.0;
                for c in &self.components {
                    let own = &self.theta[at..at + c.arity()];
                    at += c.arity();
                    let share = c.avar(own, p.tau) / total;
                    let nu = crate::edf::edf_for(crate::Stat::Oadev, c.alpha(own, p.tau), p.m, n_phase)
                        .unwrap_or(p.edf);
                    inv_sqrt += share / nu.sqrt();
                }
                let edf = 1.0 / (inv_sqrt * inv_sqrt);
                Point {
                    edf: if edf.is_finite() && edf > 0.0 { edf } else { p.edf },
                    ..*p
                }
            })
            .collect()
    }
}

/// The symbol of each component: Q, N, B, K, R; GM1, GM2 in order.
pub(super) fn labels(comps: &[Component]) -> Vec<String> {
    let gms = comps.iter().filter(|c| **c == Component::GaussMarkov).count();
    let mut k = 0;
    comps
        .iter()
        .map(|c| match c {
            Component::Power(t) => t.symbol().to_string(),
            Component::GaussMarkov if gms == 1 => "GM".to_string(),
            Component::GaussMarkov => {
                k += 1;
                format!("GM{k}")
            }
        })
        .collect()
}

fn candidates() -> Vec<Vec<Component>> {
    let mut out = Vec::new();
    for gm in 0..=2 {
        for mask in 0u32..32 {
            if mask == 0 && gm == 0 {
                continue;
            }
            let mut comps: Vec<Component> = Term::ALL
                .iter()
                .enumerate()
                .filter(|(k, _)| mask & (1 << k) != 0)
                .map(|(_, t)| Component::Power(*t))
                .collect();
            comps.extend(std::iter::repeat_n(Component::GaussMarkov, gm));
            out.push(comps);
        }
    }
    out
}

/// Starting points: each term as large as the curve allows, shared among
/// the processes; Gauss–Markov peaks (at τ ≈ 1.89 T) placed at a fifth,
/// half and four fifths of the curve's span of ln τ.
fn starts(comps: &[Component], data: &Data) -> Vec<Vec<f64>> {
    let n = data.len();
    let share = (comps.len() as f64).ln();
    let y: Vec<f64> = (0..n).map(|i| data.z[i]).collect();
    let (lt0, lt1) = (data.tau[0].ln(), data.tau[n - 1].ln());
    let peaks: Vec<f64> = [0.2, 0.5, 0.8]
        .iter()
        .map(|f| lt0 + f * (lt1 - lt0) - 1.89f64.ln())
        .collect();
    let gm_count = comps.iter().filter(|c| **c == Component::GaussMarkov).count();
    let combos: Vec<Vec<f64>> = match gm_count {
        0 => vec![vec![]],
        1 => peaks.iter().map(|&p| vec![p]).collect(),
        _ => vec![
            vec![peaks[0], peaks[1]],
            vec![peaks[0], peaks[2]],
            vec![peaks[1], peaks[2]],
        ],
    };
    combos
        .into_iter()
        .map(|tcs| {
            let mut gm = tcs.into_iter();
            let mut theta = Vec::new();
            for c in comps {
                match c {
                    Component::Power(t) => {
                        let top = (0..n)
                            .map(|i| y[i] - lm::power_basis(*t, data.tau[i]).ln())
                            .fold(f64::INFINITY, f64::min);
                        theta.push(top - share);
                    }
                    Component::GaussMarkov => {
                        let ln_t = gm.next().unwrap_or(lt0);
                        let at = (0..n)
                            .min_by(|&a, &b| {
                                (data.tau[a].ln() - ln_t - 1.89f64.ln())
                                    .abs()
                                    .total_cmp(&(data.tau[b].ln() - ln_t - 1.89f64.ln()).abs())
                            })
                            .unwrap_or(0);
                        theta.push(y[at] - 0.381f64.ln() - share);
                        theta.push(ln_t);
                    }
                }
            }
            theta
        })
        .collect()
}

/// Why a fitted candidate is set aside.
enum Breach {
    /// A process shows at too few points, or on too few degrees of freedom.
    Unshown,
    /// The process at this index exceeds the measured ceiling, most at
    /// this point.
    Above(usize, Ceiling),
}

/// Whether every process of a fitted model shows ([`SHOW_SHARE`] of the
/// variance at [`MIN_POINTS`] points holding [`MIN_TERM_EDF`]) and stays
/// under the measured curve's ceiling ([`ceiling`]); if not, the first rule
/// it breaks.
fn admissible(
    comps: &[Component],
    theta: &[f64],
    pts: &[Point],
    ceilings: &[Ceiling],
    min_points: usize,
) -> Result<(), Breach> {
    let mut at = 0;
    let mut above: Option<(f64, usize, Ceiling)> = None;
    let mut unshown = false;
    for (k, c) in comps.iter().enumerate() {
        let own = &theta[at..at + c.arity()];
        at += c.arity();
        let (mut count, mut edf) = (0usize, 0.0);
        for p in pts {
            let v = c.avar(own, p.tau);
            if v >= SHOW_SHARE * model_avar(comps, theta, p.tau) {
                count += 1;
                edf += p.edf;
            }
        }
        unshown |= count < min_points || edf < MIN_TERM_EDF;
        if let Some(worst) = ceiling::worst_breach(ceilings, |tau| c.avar(own, tau)) {
            let factor = c.avar(own, worst.tau) / worst.avar;
            if above.is_none_or(|(f, _, _)| factor > f) {
                above = Some((factor, k, *worst));
            }
        }
    }
    match (above, unshown) {
        (Some((_, k, worst)), _) => Err(Breach::Above(k, worst)),
        (None, true) => Err(Breach::Unshown),
        (None, false) => Ok(()),
    }
}

/// The defeat of a candidate a ceiling rules out: the process and the
/// point, with the measured deviation over the process's own there.
fn above_defeat(comps: &[Component], theta: &[f64], process: usize, at: &Ceiling) -> Defeat {
    let start: usize = comps[..process].iter().map(|c| c.arity()).sum();
    let c = comps[process];
    let own = c.avar(&theta[start..start + c.arity()], at.tau);
    Defeat {
        candidate: labels(comps).join(" + "),
        process: labels(comps).into_iter().nth(process),
        tau: at.tau,
        ratio: at.dev / own.sqrt(),
        sigmas: None,
    }
}

/// Steps of the first round.
const ROUGH_ITERATIONS: usize = 25;
/// Admissible candidates taken to convergence, in the order of their
/// first-round criterion.
const REFINED: usize = 24;
/// Steps at most to convergence.
const FULL_ITERATIONS: usize = 400;
/// Candidates refined at once (on all cores).
const REFINE_CHUNK: usize = 8;
/// A process carrying less than this share of the model's variance at every
/// point has left the candidate's fit: far below [`SHOW_SHARE`], which it
/// would have to regain at [`MIN_POINTS`] points to be kept.
const SHED: f64 = 1e-6;

struct Scored {
    comps: Vec<Component>,
    fit: lm::Fitted,
    criterion: f64,
}

/// Fits every candidate to `pts`, correlated as `corr` says (independent
/// without it), and selects, each kept process held under the measured
/// ceiling times `slack` (1: the ceiling itself).
pub(super) fn select(pts: &[Point], corr: Option<&DMatrix<f64>>, slack: f64) -> Selection {
    let n = pts.len();
    let none = || Selection {
        best: None,
        ranked: Vec::new(),
        evidence: Vec::new(),
        defeated: None,
    };
    if n < 2 {
        return none();
    }
    let data = match corr {
        Some(c) => match data_of(pts).correlated(c) {
            Some(d) => d,
            None => return none(),
        },
        None => data_of(pts),
    };
    let capped: Vec<f64> = pts
        .iter()
        .zip(&data.s)
        .map(|(p, s)| (lm::trigamma(p.edf / 2.0).sqrt() / s).min(1.0))
        .collect();
    // A kept process is held under the points as this fit weighs them: the
    // model's own account of each point's spread (or, before a model, the
    // most cautious power-law one), which the points' one-α-at-a-time
    // noise identification can overstate many times in a mixture (see
    // `Best::reweigh`). The bounds of the processes left out are set
    // against the curve as measured and printed (`super::build`).
    let weighed: Vec<Point> = pts
        .iter()
        .map(|p| Point {
            edf: p.edf.min(MAX_FIT_EDF),
            ..*p
        })
        .collect();
    let ceilings: Vec<Ceiling> = ceiling::ceilings(&weighed)
        .into_iter()
        .map(|c| Ceiling {
            avar: c.avar * slack,
            ..c
        })
        .collect();
    // Past the strict ceiling, a process must show over two octaves (three
    // points), not two: two points at the short end are as much the shape
    // of a filter or of a tone near the sampling rate as a process.
    let min_points = if slack > 1.0 { MIN_POINTS + 1 } else { MIN_POINTS };
    let tc = TcRange {
        lo: data.tau[0].ln(),
        hi: data.tau[n - 1].ln(),
    };
    let penalty = (n as f64).ln();
    let score = |comps: Vec<Component>, fit: lm::Fitted| Scored {
        criterion: fit.chi2 + fit.theta.len() as f64 * penalty,
        comps,
        fit,
    };
    // Every candidate from every start, briefly; then the most promising
    // ones to convergence. A candidate that has not settled in the first
    // round is shrinking a process towards nothing and is no better than
    // the smaller candidate without it, which is fitted too.
    let mut rough: Vec<Scored> = candidates()
        .into_par_iter()
        .filter(|comps| comps.iter().map(|c| c.arity()).sum::<usize>() < n)
        .filter_map(|comps| {
            let fit = starts(&comps, &data)
                .into_iter()
                .filter_map(|s| lm::fit(&data, &comps, s, tc, ROUGH_ITERATIONS))
                .min_by(|a, b| a.chi2.total_cmp(&b.chi2))?;
            Some(score(comps, fit))
        })
        .collect();
    rough.sort_by(|a, b| a.criterion.total_cmp(&b.criterion));
    // Refined in order of the first round's criterion, a few at a time on
    // all cores, until REFINED keep the rules: the same candidates, in the
    // same order, as one at a time. A candidate one of whose processes
    // shrinks below SHED of the variance at every point is set aside as
    // unshown: that process can no longer show, and the smaller candidate
    // without it holds the same fit. Where then no candidate keeps the
    // rules, the set-aside ones are refined to convergence after all: the
    // defeat printed is that of the candidate of lowest criterion that the
    // ceiling rules out, which may be one of them.
    let refine = |s: &Scored, shed: f64| {
        lm::fit_shedding(&data, &s.comps, s.fit.theta.clone(), tc, FULL_ITERATIONS, shed)
    };
    let mut fits: Vec<Option<lm::Fitted>> = Vec::with_capacity(rough.len());
    let (mut scored, mut defeated) = (Vec::new(), None);
    let rules = Rules {
        pts,
        ceilings: &ceilings,
        min_points,
        penalty,
    };
    for chunk in rough.chunks(REFINE_CHUNK) {
        let from = fits.len();
        fits.extend(chunk.par_iter().map(|s| refine(s, SHED)).collect::<Vec<_>>());
        rules.keep(&rough, &fits, from, &mut scored, &mut defeated);
        if scored.len() == REFINED {
            break;
        }
    }
    if scored.is_empty() {
        let shed: Vec<usize> = (0..fits.len())
            .filter(|&k| fits[k].as_ref().is_some_and(|f| f.shed))
            .collect();
        if !shed.is_empty() {
            let again: Vec<Option<lm::Fitted>> = shed.par_iter().map(|&k| refine(&rough[k], 0.0)).collect();
            for (k, f) in shed.into_iter().zip(again) {
                fits[k] = f;
            }
            defeated = None;
            rules.keep(&rough, &fits, 0, &mut scored, &mut defeated);
        }
    }
    let defeated = defeated.map(|(_, d)| d);
    let mut scored: Vec<Scored> = scored
        .into_iter()
        .filter_map(|k| Some(score(rough[k].comps.clone(), fits[k].clone()?)))
        .collect();
    scored.sort_by(|a, b| a.criterion.total_cmp(&b.criterion));
    let Some(top) = scored.first() else {
        return Selection { defeated, ..none() };
    };
    let label_of = |comps: &[Component]| labels(comps).join(" + ");
    let ranked = scored
        .iter()
        .take(6)
        .map(|s| Candidate {
            label: label_of(&s.comps),
            criterion: s.criterion,
            chi2: s.fit.chi2,
            parameters: s.fit.theta.len(),
        })
        .collect();
    let gms = |c: &[Component]| c.iter().filter(|x| **x == Component::GaussMarkov).count();
    let evidence = top
        .comps
        .iter()
        .zip(labels(&top.comps))
        .map(|(c, l)| {
            let without = scored
                .iter()
                .filter(|s| match c {
                    Component::Power(t) => !s.comps.contains(&Component::Power(*t)),
                    Component::GaussMarkov => gms(&s.comps) < gms(&top.comps),
                })
                .map(|s| s.criterion)
                .fold(f64::INFINITY, f64::min);
            (l, without - top.criterion)
        })
        .collect();
    let p = top.fit.theta.len();
    let dof = n - p;
    let chi2 = top.fit.chi2;
    let p_value = ChiSquared::new(dof as f64).map_or(f64::NAN, |d| d.sf(chi2));
    let best = Best {
        components: top.comps.clone(),
        theta: top.fit.theta.clone(),
        label: label_of(&top.comps),
        quality: Quality {
            chi2,
            dof,
            chi2_reduced: chi2 / dof as f64,
            p_value,
            criterion: top.criterion,
        },
        resid: top.fit.resid.clone(),
        jac: top.fit.jac.clone(),
        whiten: data.whiten.clone(),
        capped,
    };
    Selection {
        best: Some(best),
        ranked,
        evidence,
        defeated,
    }
}

/// What a refined candidate must keep.
struct Rules<'a> {
    pts: &'a [Point],
    ceilings: &'a [Ceiling],
    min_points: usize,
    penalty: f64,
}

impl Rules<'_> {
    /// Goes on from `fits[from]`, in the first round's order, adding to
    /// `kept` the index of each refined candidate that keeps the rules, up
    /// to [`REFINED`] of them, and holding in `defeated` the one of lowest
    /// criterion (the first of equals) that the ceiling rules out. A fit
    /// that failed or shed a process is neither.
    fn keep(
        &self,
        rough: &[Scored],
        fits: &[Option<lm::Fitted>],
        from: usize,
        kept: &mut Vec<usize>,
        defeated: &mut Option<(f64, Defeat)>,
    ) {
        for (k, (s, fit)) in rough.iter().zip(fits).enumerate().skip(from) {
            if kept.len() == REFINED {
                return;
            }
            let Some(fit) = fit.as_ref().filter(|f| !f.shed) else {
                continue;
            };
            match admissible(&s.comps, &fit.theta, self.pts, self.ceilings, self.min_points) {
                Ok(()) => kept.push(k),
                Err(Breach::Above(process, at)) => {
                    let criterion = fit.chi2 + fit.theta.len() as f64 * self.penalty;
                    if defeated.as_ref().is_none_or(|(c, _)| criterion < *c) {
                        *defeated = Some((criterion, above_defeat(&s.comps, &fit.theta, process, &at)));
                    }
                }
                Err(Breach::Unshown) => {}
            }
        }
    }
}

/// A point is left out when the model misses it by more than this many of
/// its standard deviations…
const OUTLIER_SIGMAS: f64 = 5.0;
/// …and by more than this many times the median miss (so that a model
/// that fits nothing well is not whittled down to the points it fits).
const OUTLIER_MEDIAN: f64 = 3.0;

/// The index of the worst-missed point, if it is an outlier.
pub(super) fn outlier(resid: &[f64]) -> Option<usize> {
    let mut order: Vec<f64> = resid.iter().map(|r| r.abs()).collect();
    order.sort_unstable_by(f64::total_cmp);
    let median = order.get(order.len() / 2).copied().unwrap_or(0.0);
    resid
        .iter()
        .enumerate()
        .filter(|(_, r)| r.abs() > OUTLIER_SIGMAS && r.abs() > OUTLIER_MEDIAN * median)
        .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
        .map(|(i, _)| i)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fit's [`Best`] with the given whitened Jacobian, correlation
    /// factor, capped ratios and χ².
    fn best(jac: DMatrix<f64>, l: DMatrix<f64>, capped: Vec<f64>, chi2: f64) -> Best {
        let (n, p) = (jac.nrows(), jac.ncols());
        let dof = n - p;
        Best {
            components: Vec::new(),
            theta: vec![0.0; p],
            label: String::new(),
            quality: Quality {
                chi2,
                dof,
                chi2_reduced: chi2 / dof as f64,
                p_value: 0.5,
                criterion: 0.0,
            },
            resid: vec![0.0; n],
            jac,
            whiten: Some(l),
            capped,
        }
    }

    /// A straight line on six points whose errors are AR(1)-correlated
    /// (ρ = 0.6): the Cholesky factor of their correlation, the design
    /// matrix and the points' true standard deviations.
    fn line() -> (DMatrix<f64>, DMatrix<f64>, Vec<f64>) {
        let n = 6;
        let corr = DMatrix::from_fn(n, n, |i, j| 0.6f64.powi((i as i32 - j as i32).abs()));
        let l = corr.cholesky().expect("positive definite").l();
        let x = DMatrix::from_fn(n, 2, |i, k| if k == 0 { 1.0 } else { i as f64 });
        (l, x, vec![0.01, 0.01, 0.02, 0.05, 0.1, 0.2])
    }

    /// The whitened Jacobian L⁻¹·S⁻¹·X of the fit that weighs the points
    /// with standard deviations `s`.
    fn whitened(l: &DMatrix<f64>, x: &DMatrix<f64>, s: &[f64]) -> DMatrix<f64> {
        let scaled = DMatrix::from_fn(x.nrows(), x.ncols(), |i, k| x[(i, k)] / s[i]);
        l.clone().solve_lower_triangular(&scaled).expect("invertible")
    }

    #[test]
    fn nothing_capped_is_the_gls_covariance_scaled_by_chi2_per_dof() {
        let (l, x, s) = line();
        let j = whitened(&l, &x, &s);
        let gls = (j.transpose() * &j).try_inverse().expect("invertible");
        let b = best(j, l, vec![1.0; 6], 8.0);
        let spreads = b.spreads();
        assert!(spreads.rescaled);
        for (k, sd) in spreads.sd.iter().enumerate() {
            // χ²/dof = 2.
            let expected = (gls[(k, k)] * 2.0).sqrt();
            assert!((sd / expected - 1.0).abs() < 1e-9, "{sd} vs {expected}");
        }
    }

    #[test]
    fn capped_weights_give_the_estimates_own_scatter() {
        let (l, x, s) = line();
        // The fit weighs every point as if its σ were at least 0.03, as
        // the EDF cap does at the points known best.
        let s_fit: Vec<f64> = s.iter().map(|v| v.max(0.03)).collect();
        let j = whitened(&l, &x, &s_fit);
        let capped: Vec<f64> = s.iter().zip(&s_fit).map(|(a, b)| a / b).collect();
        let b = best(j.clone(), l.clone(), capped, 0.0);
        let spreads = b.spreads();
        assert!(!spreads.rescaled);
        let spreads = spreads.sd;
        // The weighted estimate θ̂ = (JᵀJ)⁻¹Jᵀ·L⁻¹S_fit⁻¹·e over draws of
        // e with the points' true covariance S·LLᵀ·S.
        let gain = (j.transpose() * &j).try_inverse().expect("invertible") * j.transpose();
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut uniform = || {
            state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        };
        let draws = 40_000;
        let mut sums = [0.0f64; 2];
        for _ in 0..draws {
            let z = DMatrix::from_fn(6, 1, |_, _| {
                let (u, v) = (uniform().max(1e-300), uniform());
                (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
            });
            let e = &l * z;
            let white = l
                .clone()
                .solve_lower_triangular(&DMatrix::from_fn(6, 1, |i, _| e[(i, 0)] * s[i] / s_fit[i]))
                .expect("invertible");
            let theta = &gain * white;
            for k in 0..2 {
                sums[k] += theta[(k, 0)] * theta[(k, 0)];
            }
        }
        let naive = (j.transpose() * &j).try_inverse().expect("invertible");
        for k in 0..2 {
            let scatter = (sums[k] / draws as f64).sqrt();
            // The sampling error of a standard deviation over 40 000 draws
            // is 0.35 %.
            assert!(
                (spreads[k] / scatter - 1.0).abs() < 0.02,
                "{k}: {} vs {scatter}",
                spreads[k]
            );
            // The capped weights' own covariance overstates it.
            assert!(naive[(k, k)].sqrt() > 1.2 * scatter, "{k}");
        }
    }
}
