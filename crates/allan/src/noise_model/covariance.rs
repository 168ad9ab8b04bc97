//! The covariance of the overlapping Allan variance estimates at different
//! τ under a model: GMWM's efficient weighting (Guerrier et al., JASA 2013,
//! §3), computed rather than bootstrapped. The gmwm package estimates it by
//! simulating the first-stage fit many times (`cov_bootstrapper`,
//! src/bootstrappers.cpp); for Gaussian processes it has a closed form, which
//! is deterministic and costs milliseconds.
//!
//! With the phase x (the integral of the rate) sampled every τ0, the
//! estimate at m is σ̂²(m) = Σ_k d_m(k)² / (2τ²·n_m), d_m(k) = x_{k+2m} −
//! 2x_{k+m} + x_k. For Gaussian x (Isserlis):
//!
//!   Cov(σ̂²_i, σ̂²_j) = Σ_h c(h)·C_ij(h)² / (2τ_i²τ_j²·n_i·n_j),
//!
//! C_ij(h) = Cov(d_i(k), d_j(k + h)), c(h) the number of (k, k + h) pairs
//! in range. Each d is a combination of x with weights (1, −2, 1) that
//! annihilates polynomials of degree one, so C_ij(h) = Σ_a Σ_b w_a w_b
//! K(h + b − a) with K the phase's generalised covariance (Matheron's
//! intrinsic random functions), one per process:
//! - quantization (white phase of standard deviation Q): Q²·[s = 0];
//! - white rate N: −N²|s|/2 (x a Brownian motion);
//! - flicker rate B: B²s²·ln|s|/(2π) (gives the plateau 2 ln 2·B²/π);
//! - random-walk rate K: K²|s|³/12;
//! - Gauss–Markov (σ, T): −σ²T·(|s| − T(1 − e^{−|s|/T}));
//! - a rate ramp R is a trend, not a random process: its second difference
//!   is Rτ² at every k, which adds 2Rτ²·ē to σ̂²·2τ², ē the mean of the
//!   noise's second differences; so Cov gains R²·Cov(ē_i, ē_j), the same
//!   lag sum over C_ij(h) instead of its square.
//!
//! Each reproduces its AVAR of [`super::process`] at h = 0, i = j (tested).

use nalgebra::DMatrix;
use rayon::prelude::*;

use super::lm::Component;
use crate::noise_terms::Term;

/// One estimate of the curve: its averaging factor, sample interval and
/// number of terms.
#[derive(Debug, Clone, Copy)]
pub struct Estimate {
    /// Averaging factor m (τ = m·τ0).
    pub m: usize,
    /// Sample interval τ0, s.
    pub tau0: f64,
    /// Number of terms n of its sum.
    pub n: usize,
}

/// The phase's generalised covariance of one process at lag `s` seconds,
/// for its size² `size2` and (a Gauss–Markov term's) correlation time `t`,
/// the exponentials of the fit's log form.
fn gcov(c: Component, size2: f64, t: f64, s: f64, tau0: f64) -> f64 {
    let a = s.abs();
    match c {
        Component::Power(Term::Quantization) => {
            if a < 0.5 * tau0 {
                size2
            } else {
                0.0
            }
        }
        Component::Power(Term::WhiteNoise) => -0.5 * size2 * a,
        Component::Power(Term::BiasInstability) => {
            if a == 0.0 {
                0.0
            } else {
                size2 * a * a * a.ln() / (2.0 * std::f64::consts::PI)
            }
        }
        Component::Power(Term::RateRandomWalk) => size2 * a * a * a / 12.0,
        Component::Power(Term::RateRamp) => 0.0,
        Component::GaussMarkov => {
            // 1 − e^{−a/T} loses its digits for a ≪ T: exp_m1 keeps them.
            -size2 * t * (a + t * (-a / t).exp_m1())
        }
    }
}

/// Whether a process's C_ij(h) vanishes once every lag has one sign.
fn finite_support(c: Component) -> bool {
    !matches!(
        c,
        Component::Power(Term::BiasInstability) | Component::GaussMarkov
    )
}

const WEIGHTS: [f64; 3] = [1.0, -2.0, 1.0];

/// Each component's generalised covariance at the whole lags 0..`len`
/// samples (it is even in the lag), one row after another: computed once
/// per matrix and read by every pair of estimates.
struct Lattice {
    len: usize,
    g: Vec<f64>,
}

/// The model, ready to evaluate C_ij(h).
struct Model<'a> {
    comps: &'a [Component],
    theta: &'a [f64],
    tau0: f64,
    /// Each component's size² and (a Gauss–Markov term's) correlation
    /// time, the exponentials of its parameters: taken once for every lag
    /// of every pair.
    sizes: Vec<(f64, f64)>,
}

impl<'a> Model<'a> {
    fn new(comps: &'a [Component], theta: &'a [f64], tau0: f64) -> Self {
        let mut at = 0;
        let sizes = comps
            .iter()
            .map(|&c| {
                let p = &theta[at..at + c.arity()];
                at += c.arity();
                let t = if c == Component::GaussMarkov {
                    p[1].exp()
                } else {
                    0.0
                };
                (p[0].exp(), t)
            })
            .collect();
        Model {
            comps,
            theta,
            tau0,
            sizes,
        }
    }
}

impl Model<'_> {
    /// C_ij(h) for factors `mi`, `mj` at a (real) lag of `h` samples.
    fn cross(&self, mi: f64, mj: f64, h: f64) -> f64 {
        let (lo, hi) = (-2.0 * mj, 2.0 * mi);
        let inside = h > lo && h < hi;
        let mut total = 0.0;
        for (&c, &(size2, t)) in self.comps.iter().zip(&self.sizes) {
            if !inside && finite_support(c) {
                continue;
            }
            let mut v = 0.0;
            for (ka, wa) in WEIGHTS.iter().enumerate() {
                for (kb, wb) in WEIGHTS.iter().enumerate() {
                    let s = (h + kb as f64 * mj - ka as f64 * mi) * self.tau0;
                    v += wa * wb * gcov(c, size2, t, s, self.tau0);
                }
            }
            total += v;
        }
        total
    }

    /// Each component's generalised covariance at every whole lag of
    /// samples from 0 to `len` − 1: the values [`Model::cross`] takes at
    /// whole lags h (|s| of each), each computed once instead of once for
    /// each of the nine (a, b) pairs, each h that reaches it and each pair
    /// of estimates.
    fn lattice(&self, len: usize) -> Lattice {
        let mut g = Vec::with_capacity(len * self.comps.len());
        for (&c, &(size2, t)) in self.comps.iter().zip(&self.sizes) {
            g.par_extend(
                (0..len)
                    .into_par_iter()
                    .map(|k| gcov(c, size2, t, k as f64 * self.tau0, self.tau0)),
            );
        }
        Lattice { len, g }
    }

    /// [`Model::cross`] at a whole lag `h`, from `lattice`: the same value
    /// bit for bit (the lag of each of the nine terms is a whole number of
    /// samples, exact in f64 either way, and the terms are added in the same
    /// order, and a lag's sign changes no bit of k·τ0's magnitude).
    fn cross_at(&self, lattice: &Lattice, mi: i64, mj: i64, h: i64) -> f64 {
        let (lo, hi) = (-2.0 * mj as f64, 2.0 * mi as f64);
        let inside = (h as f64) > lo && (h as f64) < hi;
        let mut total = 0.0;
        for (k, &c) in self.comps.iter().enumerate() {
            if !inside && finite_support(c) {
                continue;
            }
            let row = &lattice.g[k * lattice.len..(k + 1) * lattice.len];
            let mut v = 0.0;
            for (ka, wa) in WEIGHTS.iter().enumerate() {
                for (kb, wb) in WEIGHTS.iter().enumerate() {
                    let s = h + kb as i64 * mj - ka as i64 * mi;
                    v += wa * wb * row[s.unsigned_abs() as usize];
                }
            }
            total += v;
        }
        total
    }

    /// R² of the model's rate ramp, 0 without one.
    fn ramp_size2(&self) -> f64 {
        let mut at = 0;
        for &c in self.comps {
            if c == Component::Power(Term::RateRamp) {
                return self.theta[at].exp();
            }
            at += c.arity();
        }
        0.0
    }

    /// The width, in lags, of the first panel at either end of a piece
    /// between breakpoints: a sample where flicker's s²·ln|s| bends there,
    /// half the shortest correlation time for the exponentials of a
    /// Gauss–Markov term; none (one panel per piece) for the polynomials of
    /// the other processes.
    fn grading(&self) -> f64 {
        let mut at = 0;
        let mut w = f64::INFINITY;
        for &c in self.comps {
            match c {
                Component::Power(Term::BiasInstability) => w = 1.0,
                Component::GaussMarkov => w = w.min((self.theta[at + 1].exp() / self.tau0 / 2.0).max(1.0)),
                _ => {}
            }
            at += c.arity();
        }
        w
    }
}

/// Lags up to this many are summed one by one; beyond, the sum is an
/// integral (Euler–Maclaurin, with the half-sample shift of the midpoint
/// rule), whose error is of the order of one lag's term in many thousands.
const DIRECT: i64 = 4096;

/// Gauss–Legendre nodes and weights on [−1, 1], 8 points: exact for the
/// degree-7 polynomials that c(h)·C(h)² is for white noise and random walks
/// between breakpoints.
const GL_X: [f64; 4] = [
    0.183_434_642_495_649_8,
    0.525_532_409_916_329,
    0.796_666_477_413_626_7,
    0.960_289_856_497_536_3,
];
const GL_W: [f64; 4] = [
    0.362_683_783_378_362,
    0.313_706_645_877_887_3,
    0.222_381_034_453_374_5,
    0.101_228_536_290_376_3,
];

fn gauss_legendre(a: f64, b: f64, f: &dyn Fn(f64) -> f64) -> f64 {
    let (mid, half) = ((a + b) / 2.0, (b - a) / 2.0);
    half * GL_X
        .iter()
        .zip(GL_W)
        .map(|(x, w)| w * (f(mid - half * x) + f(mid + half * x)))
        .sum::<f64>()
}

/// ∫ f over [a, b] in panels that start `w0` wide at each end and double
/// towards the middle: the processes bend near the breakpoints and are
/// smooth in between.
fn graded(a: f64, b: f64, w0: f64, f: &dyn Fn(f64) -> f64) -> f64 {
    let mut cuts = vec![a, b, (a + b) / 2.0];
    let mut w = w0;
    while w < (b - a) / 2.0 {
        cuts.push(a + w);
        cuts.push(b - w);
        w *= 2.0;
    }
    cuts.sort_by(f64::total_cmp);
    cuts.dedup();
    cuts.windows(2).map(|p| gauss_legendre(p[0], p[1], f)).sum()
}

/// The breakpoints of C_ij for two estimates: the lags at which two of the
/// nine phase samples coincide, and the ends of the range of lags with
/// pairs; sorted, each once.
fn cuts(ei: &Estimate, ej: &Estimate) -> Vec<i64> {
    let (ni, nj) = (ei.n as i64, ej.n as i64);
    let (first, last) = (-(nj - 1), ni);
    let mut cuts: Vec<i64> = Vec::with_capacity(11);
    for a in 0..3 {
        for b in 0..3 {
            cuts.push(a * ei.m as i64 - b * ej.m as i64);
        }
    }
    cuts.push(first);
    cuts.push(last);
    cuts.iter_mut().for_each(|c| *c = (*c).clamp(first, last));
    cuts.sort_unstable();
    cuts.dedup();
    cuts
}

/// The largest |lag| of samples at which [`covariance`] reads a process's
/// generalised covariance one lag at a time (pieces of up to [`DIRECT`]
/// lags), plus one; 0 where it reads none so.
fn reach(ei: &Estimate, ej: &Estimate) -> usize {
    let (mi, mj) = (ei.m as i64, ej.m as i64);
    cuts(ei, ej)
        .windows(2)
        .filter(|p| p[1] > p[0] && p[1] - p[0] <= DIRECT)
        .map(|p| ((p[0] - 2 * mi).abs()).max((p[1] - 1 + 2 * mj).abs()) as usize + 1)
        .max()
        .unwrap_or(0)
}

/// Cov(σ̂²_i, σ̂²_j) under the model, its whole lags read from `lattice`
/// (which must reach [`reach`] of the pair; `None` only where that is 0).
fn covariance(model: &Model, lattice: Option<&Lattice>, ei: &Estimate, ej: &Estimate) -> f64 {
    let (mi, mj) = (ei.m as f64, ej.m as f64);
    let (ni, nj) = (ei.n as i64, ej.n as i64);
    let count = |h: f64| -> f64 {
        let lo = (-h).max(0.0);
        let hi = (ni as f64).min(nj as f64 - h);
        (hi - lo).max(0.0)
    };
    let f = |h: f64| {
        let c = model.cross(mi, mj, h);
        count(h) * c * c
    };
    let w0 = model.grading();
    let cuts = cuts(ei, ej);
    let direct = |p: &[i64]| p[1] > p[0] && p[1] - p[0] <= DIRECT;
    let (mi_i, mj_i) = (ei.m as i64, ej.m as i64);
    let lag_sum = |whole: &dyn Fn(&Lattice, i64) -> f64, g: &dyn Fn(f64) -> f64| -> f64 {
        cuts.windows(2)
            .map(|p| match lattice {
                Some(lat) if direct(p) => (p[0]..p[1]).map(|h| whole(lat, h)).sum(),
                _ if p[1] <= p[0] => 0.0,
                _ => graded(p[0] as f64 - 0.5, p[1] as f64 - 0.5, w0, g),
            })
            .sum()
    };
    let f_whole = |lat: &Lattice, h: i64| {
        let c = model.cross_at(lat, mi_i, mj_i, h);
        count(h as f64) * c * c
    };
    let (ti, tj) = (mi * ei.tau0, mj * ej.tau0);
    let mut cov = lag_sum(&f_whole, &f) / (2.0 * ti * ti * tj * tj * ni as f64 * nj as f64);
    let ramp2 = model.ramp_size2();
    if ramp2 > 0.0 {
        // The ramp's second difference Rτ² is the same at every k: it
        // multiplies the mean of the noise's, σ̂² = (R²τ⁴ + 2Rτ²ē + mean e²)/2τ².
        let mean_cov = lag_sum(
            &|lat: &Lattice, h: i64| count(h as f64) * model.cross_at(lat, mi_i, mj_i, h),
            &|h: f64| count(h) * model.cross(mi, mj, h),
        ) / (ni as f64 * nj as f64);
        cov += ramp2 * mean_cov;
    }
    cov
}

/// The covariance matrix of the estimates σ̂² at `points` under the model
/// `comps` with parameters `theta` (the fit's log form). Every estimate
/// must share τ0 and be taken over the same record.
pub fn matrix(comps: &[Component], theta: &[f64], points: &[Estimate]) -> DMatrix<f64> {
    let n = points.len();
    let tau0 = points.first().map_or(1.0, |p| p.tau0);
    let model = Model::new(comps, theta, tau0);
    let pairs: Vec<(usize, usize)> = (0..n).flat_map(|i| (i..n).map(move |j| (i, j))).collect();
    let len = pairs
        .iter()
        .map(|&(i, j)| reach(&points[i], &points[j]))
        .max()
        .unwrap_or(0);
    let lattice = (len > 0).then(|| model.lattice(len));
    let values: Vec<f64> = pairs
        .par_iter()
        .map(|&(i, j)| covariance(&model, lattice.as_ref(), &points[i], &points[j]))
        .collect();
    let mut out = DMatrix::zeros(n, n);
    for (&(i, j), v) in pairs.iter().zip(values) {
        out[(i, j)] = v;
        out[(j, i)] = v;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::super::lm::{Component, model_avar};
    use super::*;

    fn est(m: usize, n_phase: usize) -> Estimate {
        Estimate {
            m,
            tau0: 0.1,
            n: n_phase - 2 * m,
        }
    }

    #[test]
    fn each_process_gives_its_allan_variance() {
        // C_ii(0)/(2τ²) is the AVAR, for every process of the candidates.
        let cases: Vec<(Component, Vec<f64>)> = vec![
            (Component::Power(Term::Quantization), vec![(4e-8f64).ln()]),
            (Component::Power(Term::WhiteNoise), vec![(2.3e-8f64).ln()]),
            (Component::Power(Term::BiasInstability), vec![(6e-9f64).ln()]),
            (Component::Power(Term::RateRandomWalk), vec![(4e-12f64).ln()]),
            (Component::GaussMarkov, vec![(1e-8f64).ln(), (3.0f64).ln()]),
        ];
        for (c, p) in cases {
            let comps = [c];
            let model = Model::new(&comps, &p, 0.1);
            for m in [1usize, 3, 16, 500] {
                let tau = m as f64 * 0.1;
                let want = model_avar(&comps, &p, tau);
                let got = model.cross(m as f64, m as f64, 0.0) / (2.0 * tau * tau);
                assert!((got / want - 1.0).abs() < 1e-6, "{c:?} m={m}: {got} vs {want}");
            }
        }
    }

    #[test]
    fn white_noise_variance_matches_greenhall_edf() {
        // ν = 2·AVAR²/Var(σ̂²) against Greenhall's EDF of the overlapping
        // ADEV for white rate noise (crate::edf, checked against NIST SP
        // 1065's tables in tests/sp1065_tables.rs). Greenhall's algorithm
        // is a continuous-time approximation, within 0.1 % from m = 64 on;
        // below, the exact discrete value is SP 1065's white-FM formula
        // (eq. 53 of NIST SP 1065), ν = (3(N−1)/2m − 2(N−2)/N)·4m²/(4m²+5).
        let comps = [Component::Power(Term::WhiteNoise)];
        let theta = [(1e-6f64).ln()];
        let n_phase = 100_001;
        for m in [64usize, 2048, 16_384, 25_000] {
            let e = est(m, n_phase);
            let v = matrix(&comps, &theta, &[e])[(0, 0)];
            let avar = model_avar(&comps, &theta, m as f64 * 0.1);
            let nu = 2.0 * avar * avar / v;
            let greenhall = crate::edf::edf_for(crate::Stat::Oadev, 0, m, n_phase).unwrap();
            assert!((nu / greenhall - 1.0).abs() < 1e-3, "m={m}: {nu} vs {greenhall}");
        }
        for m in [1usize, 2, 4, 16] {
            let v = matrix(&comps, &theta, &[est(m, n_phase)])[(0, 0)];
            let avar = model_avar(&comps, &theta, m as f64 * 0.1);
            let nu = 2.0 * avar * avar / v;
            let (big_n, m2) = (n_phase as f64, (m * m) as f64);
            let sp1065 = (3.0 * (big_n - 1.0) / (2.0 * m as f64) - 2.0 * (big_n - 2.0) / big_n) * 4.0 * m2
                / (4.0 * m2 + 5.0);
            assert!((nu / sp1065 - 1.0).abs() < 1e-4, "m={m}: {nu} vs {sp1065}");
        }
    }

    #[test]
    fn random_walk_variance_matches_greenhall_edf() {
        let comps = [Component::Power(Term::RateRandomWalk)];
        let theta = [(1e-10f64).ln()];
        let n_phase = 100_001;
        for m in [8usize, 512, 8192, 25_000] {
            let e = est(m, n_phase);
            let v = matrix(&comps, &theta, &[e])[(0, 0)];
            let avar = model_avar(&comps, &theta, m as f64 * 0.1);
            let nu = 2.0 * avar * avar / v;
            let greenhall = crate::edf::edf_for(crate::Stat::Oadev, -2, m, n_phase).unwrap();
            assert!((nu / greenhall - 1.0).abs() < 5e-3, "m={m}: {nu} vs {greenhall}");
        }
    }

    #[test]
    fn flicker_variance_matches_greenhall_edf() {
        let comps = [Component::Power(Term::BiasInstability)];
        let theta = [(1e-8f64).ln()];
        let n_phase = 100_001;
        for m in [64usize, 4096, 25_000] {
            let e = est(m, n_phase);
            let v = matrix(&comps, &theta, &[e])[(0, 0)];
            let avar = model_avar(&comps, &theta, m as f64 * 0.1);
            let nu = 2.0 * avar * avar / v;
            let greenhall = crate::edf::edf_for(crate::Stat::Oadev, -1, m, n_phase).unwrap();
            assert!((nu / greenhall - 1.0).abs() < 3e-2, "m={m}: {nu} vs {greenhall}");
        }
    }

    /// The covariance of d_i(k) and d_j(k + h) for white rate noise of
    /// unit sample variance, from the samples themselves: d_m(k)/τ0 is the
    /// sum of y over [k+m, k+2m) minus that over [k, k+m).
    /// Returns Cov(σ̂²_i, σ̂²_j) and Cov(ē_i, ē_j).
    fn brute_white(mi: usize, mj: usize, n_phase: usize, tau0: f64) -> (f64, f64) {
        let weights = |m: usize, k: usize| -> Vec<f64> {
            let mut w = vec![0.0; n_phase];
            w[k..k + m].iter_mut().for_each(|v| *v = -tau0);
            w[k + m..k + 2 * m].iter_mut().for_each(|v| *v = tau0);
            w
        };
        let (ni, nj) = (n_phase - 2 * mi, n_phase - 2 * mj);
        let wi: Vec<Vec<f64>> = (0..ni).map(|k| weights(mi, k)).collect();
        let wj: Vec<Vec<f64>> = (0..nj).map(|k| weights(mj, k)).collect();
        let (mut sum, mut means) = (0.0, 0.0);
        for a in &wi {
            for b in &wj {
                let c: f64 = a.iter().zip(b).map(|(x, y)| x * y).sum();
                sum += 2.0 * c * c;
                means += c;
            }
        }
        let (ti, tj) = (mi as f64 * tau0, mj as f64 * tau0);
        let nn = ni as f64 * nj as f64;
        (sum / (4.0 * ti * ti * tj * tj * nn), means / nn)
    }

    #[test]
    fn a_ramp_adds_its_cross_term() {
        // R²·Cov(ē_i, ē_j) with ē's covariance written out from the sample
        // weights: white noise of unit sample variance under a ramp.
        let tau0: f64 = 0.5;
        let comps = [
            Component::Power(Term::WhiteNoise),
            Component::Power(Term::RateRamp),
        ];
        let r2 = 3e-3f64;
        let theta = [tau0.ln(), r2.ln()];
        let n_phase = 120;
        for (mi, mj) in [(1, 1), (2, 4), (5, 20)] {
            let e = |m: usize| Estimate {
                m,
                tau0,
                n: n_phase - 2 * m,
            };
            let got = matrix(&comps, &theta, &[e(mi), e(mj)])[(0, 1)];
            let (noise, means) = brute_white(mi, mj, n_phase, tau0);
            let want = noise + r2 * means;
            assert!((got / want - 1.0).abs() < 1e-9, "({mi}, {mj}): {got} vs {want}");
        }
    }

    #[test]
    fn cross_covariance_matches_the_samples() {
        // Isserlis over every pair of terms, written out from the sample
        // weights, against the lag sum; y has variance N²/τ0 = 1.
        let tau0: f64 = 0.5;
        let comps = [Component::Power(Term::WhiteNoise)];
        let theta = [tau0.ln()];
        let n_phase = 120;
        for (mi, mj) in [(1, 1), (1, 2), (2, 4), (3, 8), (5, 20)] {
            let e = |m: usize| Estimate {
                m,
                tau0,
                n: n_phase - 2 * m,
            };
            let got = matrix(&comps, &theta, &[e(mi), e(mj)])[(0, 1)];
            let want = brute_white(mi, mj, n_phase, tau0).0;
            assert!((got / want - 1.0).abs() < 1e-9, "({mi}, {mj}): {got} vs {want}");
        }
    }

    #[test]
    fn integral_meets_the_sum_over_lags() {
        // Above DIRECT lags per piece the sum is an integral: against the
        // plain sum over every lag, for each kind of lag dependence (finite
        // support, a power-law tail, an exponential one) and their sum.
        let all = [
            (Component::Power(Term::WhiteNoise), vec![(1e-8f64).ln()]),
            (Component::Power(Term::BiasInstability), vec![(1e-9f64).ln()]),
            (Component::Power(Term::RateRandomWalk), vec![(1e-12f64).ln()]),
            (Component::GaussMarkov, vec![(1e-9f64).ln(), (30.0f64).ln()]),
        ];
        let mut cases: Vec<(Vec<Component>, Vec<f64>)> =
            all.iter().map(|(c, p)| (vec![*c], p.clone())).collect();
        cases.push((
            all.iter().map(|x| x.0).collect(),
            all.iter().flat_map(|x| x.1.clone()).collect(),
        ));
        let n_phase = 60_000;
        for (mi, mj) in [(2500usize, 5000usize), (5000, 5000), (300, 9000)] {
            for (comps, theta) in &cases {
                let model = Model::new(comps, theta, 0.1);
                let (ei, ej) = (est(mi, n_phase), est(mj, n_phase));
                let lattice = model.lattice(reach(&ei, &ej));
                let got = covariance(&model, Some(&lattice), &ei, &ej);
                let (ni, nj) = (ei.n as i64, ej.n as i64);
                let plain: f64 = (-(nj - 1)..ni)
                    .map(|h| {
                        let c = model.cross(mi as f64, mj as f64, h as f64);
                        let count = (ni.min(nj - h) - (-h).max(0)).max(0) as f64;
                        count * c * c
                    })
                    .sum();
                let (ti, tj) = (mi as f64 * 0.1, mj as f64 * 0.1);
                let want = plain / (2.0 * ti * ti * tj * tj * ni as f64 * nj as f64);
                assert!(
                    (got / want - 1.0).abs() < 1e-4,
                    "{comps:?} ({mi}, {mj}): {got} vs {want}"
                );
            }
        }
    }
}
