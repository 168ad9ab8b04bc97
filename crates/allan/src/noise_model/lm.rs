//! Weighted nonlinear least squares of a sum of processes to a measured
//! Allan variance, in log-parameters (every size and correlation time stays
//! positive), by Levenberg–Marquardt.
//!
//! The residual of point i is taken on ln σ̂²: an Allan variance estimate
//! with ν equivalent degrees of freedom is σ²·χ²_ν/ν, whose logarithm has
//! mean ln σ² + ψ(ν/2) − ln(ν/2) and variance ψ₁(ν/2) exactly (ψ, ψ₁: the
//! digamma and trigamma functions). The weights are thus the points' own
//! degrees of freedom, independent of the model, and the bias of ln σ̂²
//! at few degrees of freedom (−0.33 at ν = 3) is removed rather than fitted.
//! Where the correlations of the points are known, the standardised
//! residuals are whitened by the Cholesky factor of their correlation
//! matrix: the efficient weighting of GMWM (Guerrier et al., JASA 2013, §3).

use nalgebra::DMatrix;
use statrs::function::gamma::digamma;

use super::process;
use crate::noise_terms::Term;

/// One process of a candidate model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Component {
    /// One of the five IEEE 952 terms: one parameter, ln(size²).
    Power(Term),
    /// A first-order Gauss–Markov process: ln σ², ln T.
    GaussMarkov,
}

impl Component {
    /// Number of parameters.
    pub fn arity(self) -> usize {
        match self {
            Component::Power(_) => 1,
            Component::GaussMarkov => 2,
        }
    }

    /// The power-law exponent α of the rate noise's spectrum (S_y ∝ f^α)
    /// that the process shows at τ: quantization is white phase (+2), N
    /// white rate (0), B flicker rate (−1), K and R random-walk rate (−2,
    /// the steepest the EDF tables hold); a Gauss–Markov process looks like
    /// a random walk below its correlation time and white noise above it.
    pub fn alpha(self, p: &[f64], tau: f64) -> i32 {
        match self {
            Component::Power(Term::Quantization) => 2,
            Component::Power(Term::WhiteNoise) => 0,
            Component::Power(Term::BiasInstability) => -1,
            Component::Power(_) => -2,
            Component::GaussMarkov if tau < p[1].exp() => -2,
            Component::GaussMarkov => 0,
        }
    }

    /// AVAR at τ for parameters `p` (in log form).
    pub fn avar(self, p: &[f64], tau: f64) -> f64 {
        match self {
            Component::Power(t) => p[0].exp() * power_basis(t, tau),
            Component::GaussMarkov => p[0].exp() * process::gauss_markov(tau, p[1].exp()),
        }
    }
}

/// The AVAR of a term of size 1.
pub fn power_basis(term: Term, tau: f64) -> f64 {
    match term {
        Term::Quantization => process::quantization(tau),
        Term::WhiteNoise => process::white(tau),
        Term::BiasInstability => process::flicker(tau),
        Term::RateRandomWalk => process::random_walk(tau),
        Term::RateRamp => process::ramp(tau),
    }
}

/// The points, ready to fit.
#[derive(Debug, Clone)]
pub struct Data {
    /// τ, s.
    pub tau: Vec<f64>,
    /// ln σ̂² with its χ² bias removed.
    pub z: Vec<f64>,
    /// Standard deviation of ln σ̂².
    pub s: Vec<f64>,
    /// The lower Cholesky factor L of the correlation matrix of the
    /// points' ln σ̂², where it is known: the residuals standardised by `s`
    /// are whitened by L⁻¹ before they are squared (generalised least
    /// squares, GMWM's efficient weighting). Without it the points count as
    /// independent.
    pub whiten: Option<DMatrix<f64>>,
}

/// Trigamma ψ₁(x) for x > 0: the recurrence ψ₁(x) = ψ₁(x+1) + 1/x² up to
/// x ≥ 10, then the asymptotic series (Abramowitz & Stegun 6.4.12), whose
/// first omitted term is below 1e-12 there.
pub fn trigamma(mut x: f64) -> f64 {
    let mut acc = 0.0;
    while x < 10.0 {
        acc += 1.0 / (x * x);
        x += 1.0;
    }
    let x2 = 1.0 / (x * x);
    acc + 1.0 / x + x2 / 2.0 + x2 / x * (1.0 / 6.0 - x2 * (1.0 / 30.0 - x2 * (1.0 / 42.0 - x2 / 30.0)))
}

impl Data {
    /// From (τ, σ̂², ν) triples.
    pub fn new(points: impl IntoIterator<Item = (f64, f64, f64)>) -> Data {
        let mut d = Data {
            tau: Vec::new(),
            z: Vec::new(),
            s: Vec::new(),
            whiten: None,
        };
        for (tau, var, nu) in points {
            let h = nu / 2.0;
            d.tau.push(tau);
            d.z.push(var.ln() - (digamma(h) - h.ln()));
            d.s.push(trigamma(h).sqrt());
        }
        d
    }

    /// The same points, correlated as `corr` says; `None` if `corr` is not
    /// a positive definite matrix of the points' size.
    pub fn correlated(mut self, corr: &DMatrix<f64>) -> Option<Data> {
        if corr.nrows() != self.len() || corr.ncols() != self.len() || corr.iter().any(|v| !v.is_finite()) {
            return None;
        }
        self.whiten = Some(corr.clone().cholesky()?.l());
        Some(self)
    }

    /// Solves L·x = v in place (forward substitution), for the `stride`-th
    /// elements of `v` starting at `offset`: a column of a row-major matrix.
    fn whiten_in_place(&self, v: &mut [f64], offset: usize, stride: usize) {
        let Some(l) = &self.whiten else { return };
        for i in 0..self.len() {
            let mut acc = v[offset + i * stride];
            for k in 0..i {
                acc -= l[(i, k)] * v[offset + k * stride];
            }
            v[offset + i * stride] = acc / l[(i, i)];
        }
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.tau.len()
    }

    /// Whether there is no point.
    pub fn is_empty(&self) -> bool {
        self.tau.is_empty()
    }
}

/// The model's AVAR at τ: the sum of its components.
pub fn model_avar(comps: &[Component], theta: &[f64], tau: f64) -> f64 {
    let mut at = 0;
    comps
        .iter()
        .map(|c| {
            let v = c.avar(&theta[at..at + c.arity()], tau);
            at += c.arity();
            v
        })
        .sum()
}

/// A fitted candidate.
#[derive(Debug, Clone)]
pub struct Fitted {
    /// The parameters, in log form.
    pub theta: Vec<f64>,
    /// Σ rᵢ² of the whitened residuals, the χ² of the fit.
    pub chi2: f64,
    /// Jacobian of the whitened residuals at the solution (n × p).
    pub jac: DMatrix<f64>,
    /// Each point's residual at the solution over its own standard
    /// deviation (not whitened: a point's own miss).
    pub resid: Vec<f64>,
    /// Whether the fit stopped because a process had shrunk below the
    /// share [`fit_shedding`] was given at every point: the fit is then the
    /// smaller model's without it, not converged.
    pub shed: bool,
}

/// Range of ln T: a correlation time far outside the τ of the curve is a
/// white noise or a random walk, which the simpler models already hold.
#[derive(Debug, Clone, Copy)]
pub struct TcRange {
    /// Lower end of ln T.
    pub lo: f64,
    /// Upper end of ln T.
    pub hi: f64,
}

fn clamp(comps: &[Component], theta: &mut [f64], tc: TcRange) {
    let mut at = 0;
    for c in comps {
        theta[at] = theta[at].clamp(-1400.0, 1400.0);
        if *c == Component::GaussMarkov {
            theta[at + 1] = theta[at + 1].clamp(tc.lo, tc.hi);
        }
        at += c.arity();
    }
}

/// One evaluation of a model on the points: everything a Levenberg–Marquardt
/// step reads from it, so that a trial, once accepted, gives the Jacobian and
/// the points' own misses without being evaluated again.
struct Evaluation {
    /// Each point's residual over its standard deviation (not whitened).
    own: Vec<f64>,
    /// The same, whitened.
    r: Vec<f64>,
    /// Row-major n × p: each parameter's ∂(model AVAR)/∂(parameter) at
    /// each point (for a size, its process's AVAR; for ln T, σ²·∂g/∂ln T).
    parts: Vec<f64>,
    /// The model's AVAR at each point.
    m: Vec<f64>,
}

impl Evaluation {
    fn new(n: usize, p: usize) -> Evaluation {
        Evaluation {
            own: vec![0.0; n],
            r: vec![0.0; n],
            parts: vec![0.0; n * p],
            m: vec![0.0; n],
        }
    }

    /// χ² of the whitened residuals.
    fn chi2(&self) -> f64 {
        self.r.iter().map(|v| v * v).sum()
    }

    /// Whether some process carries less than `share` of the model's
    /// variance at every point.
    fn sheds(&self, comps: &[Component], p: usize, share: f64) -> bool {
        let mut at = 0;
        comps.iter().any(|c| {
            let k = at;
            at += c.arity();
            (0..self.m.len()).all(|i| self.parts[i * p + k] < share * self.m[i])
        })
    }

    /// The whitened Jacobian of the residuals (row-major n × p) into `jac`.
    fn jacobian(&self, data: &Data, p: usize, jac: &mut [f64]) {
        for i in 0..data.len() {
            for k in 0..p {
                jac[i * p + k] = -self.parts[i * p + k] / (self.m[i] * data.s[i]);
            }
        }
        for k in 0..p {
            data.whiten_in_place(jac, k, p);
        }
    }
}

/// Each point's AVAR of every power-law term of unit size, in
/// [`Term::ALL`]'s order: the same values [`power_basis`] gives, computed
/// once per fit rather than once per evaluation.
fn bases(data: &Data) -> Vec<[f64; 5]> {
    data.tau
        .iter()
        .map(|&tau| Term::ALL.map(|t| power_basis(t, tau)))
        .collect()
}

/// `x.exp()`, taken as the 0 it rounds to below −750 without calling
/// `exp` (whose underflow path is slow): the same value bit for bit.
fn exp_or_zero(x: f64) -> f64 {
    if x < -750.0 { 0.0 } else { x.exp() }
}

/// Evaluates the model at `theta` into `ev`, in one pass over the points;
/// `false` where the model is not finite. Each parameter's exponential and
/// each Gauss–Markov term's closed form are computed once per point (the
/// values `Component::avar` and [`process::gauss_markov`] give, bit for
/// bit), with the derivative in ln T beside it.
fn evaluate_into(
    data: &Data,
    bases: &[[f64; 5]],
    comps: &[Component],
    theta: &[f64],
    ev: &mut Evaluation,
) -> bool {
    let p = theta.len();
    let mut scale = [0.0f64; 16];
    for (s, t) in scale.iter_mut().zip(theta) {
        *s = exp_or_zero(*t);
    }
    for (i, basis) in bases.iter().enumerate() {
        let tau = data.tau[i];
        let parts = &mut ev.parts[i * p..(i + 1) * p];
        let mut at = 0;
        let mut m = 0.0;
        for c in comps {
            let v = match c {
                Component::Power(t) => scale[at] * basis[term_index(*t)],
                Component::GaussMarkov => {
                    let (g, dg) = process::gauss_markov_and_dln_tc(tau, scale[at + 1]);
                    parts[at + 1] = scale[at] * dg;
                    scale[at] * g
                }
            };
            parts[at] = v;
            m += v;
            at += c.arity();
        }
        let ri = (data.z[i] - m.ln()) / data.s[i];
        if !ri.is_finite() {
            return false;
        }
        ev.m[i] = m;
        ev.own[i] = ri;
        ev.r[i] = ri;
    }
    data.whiten_in_place(&mut ev.r, 0, 1);
    true
}

/// The index of a term in [`Term::ALL`].
fn term_index(t: Term) -> usize {
    Term::ALL.iter().position(|x| *x == t).unwrap_or(0)
}

/// Solves the symmetric positive definite system a·x = b (p × p,
/// row-major) by Cholesky; `None` if it is not positive definite.
fn solve_spd(a: &[f64], b: &[f64], p: usize) -> Option<Vec<f64>> {
    let mut l = vec![0.0; p * p];
    for i in 0..p {
        for j in 0..=i {
            let mut s = a[i * p + j];
            for k in 0..j {
                s -= l[i * p + k] * l[j * p + k];
            }
            if i == j {
                if s.is_nan() || s <= 0.0 {
                    return None;
                }
                l[i * p + i] = s.sqrt();
            } else {
                l[i * p + j] = s / l[j * p + j];
            }
        }
    }
    let mut y = vec![0.0; p];
    for i in 0..p {
        let s: f64 = (0..i).map(|k| l[i * p + k] * y[k]).sum();
        y[i] = (b[i] - s) / l[i * p + i];
    }
    let mut x = vec![0.0; p];
    for i in (0..p).rev() {
        let s: f64 = (i + 1..p).map(|k| l[k * p + i] * x[k]).sum();
        x[i] = (y[i] - s) / l[i * p + i];
    }
    Some(x)
}

/// Relative gain in χ² below which the fit has settled: far below the χ²
/// differences (units) the criterion compares.
const TOLERANCE: f64 = 1e-7;

/// Levenberg–Marquardt from `theta`, for at most `iterations` steps; `None` if the model cannot be
/// evaluated on the points.
pub fn fit(
    data: &Data,
    comps: &[Component],
    theta: Vec<f64>,
    tc: TcRange,
    iterations: usize,
) -> Option<Fitted> {
    fit_shedding(data, comps, theta, tc, iterations, 0.0)
}

/// [`fit`], stopped as soon as one process carries less than `shed` of
/// the model's variance at every point ([`Fitted::shed`]): a process
/// shrinking towards nothing takes hundreds of ever smaller steps, each
/// worth less to χ², towards the fit of the smaller model without it.
pub fn fit_shedding(
    data: &Data,
    comps: &[Component],
    mut theta: Vec<f64>,
    tc: TcRange,
    iterations: usize,
    shed: f64,
) -> Option<Fitted> {
    let n = data.len();
    let p = theta.len();
    clamp(comps, &mut theta, tc);
    let bases = bases(data);
    let mut j = vec![0.0; n * p];
    let mut ev = Evaluation::new(n, p);
    if !evaluate_into(data, &bases, comps, &theta, &mut ev) {
        return None;
    }
    ev.jacobian(data, p, &mut j);
    let mut trial = Evaluation::new(n, p);
    let mut chi2: f64 = ev.chi2();
    let mut lambda = 1e-3;
    let (mut a, mut g) = (vec![0.0; p * p], vec![0.0; p]);
    let mut gone = false;
    for _ in 0..iterations {
        if shed > 0.0 && ev.sheds(comps, p, shed) {
            gone = true;
            break;
        }
        for k in 0..p {
            g[k] = -(0..n).map(|i| j[i * p + k] * ev.r[i]).sum::<f64>();
            for l in 0..=k {
                let v: f64 = (0..n).map(|i| j[i * p + k] * j[i * p + l]).sum();
                a[k * p + l] = v;
                a[l * p + k] = v;
            }
        }
        let mut improved = false;
        while lambda < 1e12 {
            let mut damped = a.clone();
            for k in 0..p {
                damped[k * p + k] += lambda * a[k * p + k].max(1e-12);
            }
            let Some(step) = solve_spd(&damped, &g, p) else {
                lambda *= 10.0;
                continue;
            };
            let mut next: Vec<f64> = theta.iter().zip(&step).map(|(t, d)| t + d).collect();
            clamp(comps, &mut next, tc);
            if evaluate_into(data, &bases, comps, &next, &mut trial) {
                let c2 = trial.chi2();
                if c2 < chi2 {
                    let gain = chi2 - c2;
                    theta = next;
                    chi2 = c2;
                    std::mem::swap(&mut ev, &mut trial);
                    ev.jacobian(data, p, &mut j);
                    lambda = (lambda / 3.0).max(1e-12);
                    improved = gain > TOLERANCE * (1.0 + chi2);
                    break;
                }
            }
            lambda *= 4.0;
        }
        if !improved {
            break;
        }
    }
    Some(Fitted {
        resid: ev.own,
        theta,
        chi2,
        jac: DMatrix::from_row_slice(n, p, &j),
        shed: gone,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trigamma_known_values() {
        // ψ₁(1) = π²/6, ψ₁(1/2) = π²/2 (Abramowitz & Stegun 6.4.2, 6.4.4).
        let pi2 = std::f64::consts::PI.powi(2);
        assert!((trigamma(1.0) - pi2 / 6.0).abs() < 1e-10);
        assert!((trigamma(0.5) - pi2 / 2.0).abs() < 1e-10);
    }

    #[test]
    fn recovers_exact_curve() {
        let taus: Vec<f64> = (0..14).map(|k| 0.01 * 2f64.powi(k)).collect();
        let comps = [
            Component::Power(Term::WhiteNoise),
            Component::Power(Term::RateRandomWalk),
            Component::GaussMarkov,
        ];
        let truth = [(1e-8f64).ln(), (4e-12f64).ln(), (1e-7f64).ln(), (5.0f64).ln()];
        // Exact AVAR at ν = ∞ has no bias to remove: fed through Data with a
        // huge ν, the fit returns the parameters it came from.
        let data = Data::new(taus.iter().map(|&t| (t, model_avar(&comps, &truth, t), 1e9)));
        let start = vec![(1e-7f64).ln(), (1e-11f64).ln(), (1e-6f64).ln(), (1.0f64).ln()];
        let f = fit(&data, &comps, start, TcRange { lo: -10.0, hi: 10.0 }, 500).unwrap();
        for (a, b) in f.theta.iter().zip(truth) {
            assert!((a - b).abs() < 1e-6, "{:?} vs {truth:?}", f.theta);
        }
    }
}
