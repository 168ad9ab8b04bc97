//! The sensor's filter. White noise of density N through a first-order
//! low-pass of time constant Tc is a first-order Gauss–Markov process with
//! correlation time Tc and σ² = N²/(2Tc): its Allan variance is N²/τ
//! beyond a few Tc and falls below that line at the shortest τ. A MEMS
//! sensor's digital low-pass (the MPU-9250's DLPF, a flight stack's
//! software filter) puts Tc at about the sampling interval, where no
//! record can tell a Gauss–Markov process from filtered white noise. The
//! fit then finds a "GM" with T near τ0 and no N; that GM is the white
//! noise, and is reported as N with the filter named, never as a GM.

use nalgebra::DMatrix;

use super::lm::Component;
use super::select::{Spreads, labels};
use crate::noise_terms::{Term, TermValue};

/// A Gauss–Markov term whose T is below this many times the shortest τ
/// the model was fitted to is the sensor's filter: at every τ of the curve but the first
/// two octaves it is white noise to within 40 % of its variance
/// (1 − 3T/2τ), which no record separates from a filter.
pub const FACTOR: f64 = 4.0;

/// The first-order low-pass filter the white noise passes through.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LowPass {
    /// Its time constant Tc, s, with its interval.
    pub tau_c: TermValue,
    /// Its −3 dB frequency 1/(2π·Tc), Hz.
    pub cutoff_hz: f64,
}

/// The index (among `comps`) of the Gauss–Markov term that is the filter
/// on the white noise, if any: the one of shortest T, where T is below
/// [`FACTOR`] times `tau_first`.
pub(super) fn find(comps: &[Component], theta: &[f64], tau_first: f64) -> Option<usize> {
    let mut at = 0;
    let mut shortest: Option<(usize, f64)> = None;
    for (k, c) in comps.iter().enumerate() {
        if *c == Component::GaussMarkov {
            let t = theta[at + 1].exp();
            if shortest.is_none_or(|(_, s)| t < s) {
                shortest = Some((k, t));
            }
        }
        at += c.arity();
    }
    shortest
        .filter(|&(_, t)| tau_first > 0.0 && t < FACTOR * tau_first)
        .map(|(k, _)| k)
}

/// N² = N_w² + 2σ²T: the white noise before the filter, the filtered
/// Gauss–Markov term `gm`'s and any unfiltered white term's together, with
/// its interval from the parameters' covariance (`spreads`) at the
/// quantile `z`, by the delta method on ln N².
pub(super) fn white_noise(
    comps: &[Component],
    theta: &[f64],
    gm: usize,
    spreads: &Spreads,
    z: f64,
) -> TermValue {
    let p = theta.len();
    let mut parts = Vec::new();
    let mut at = 0;
    for (k, c) in comps.iter().enumerate() {
        match c {
            Component::Power(Term::WhiteNoise) => parts.push((theta[at].exp(), vec![at])),
            Component::GaussMarkov if k == gm => {
                parts.push((2.0 * (theta[at] + theta[at + 1]).exp(), vec![at, at + 1]));
            }
            _ => {}
        }
        at += c.arity();
    }
    let total: f64 = parts.iter().map(|(v, _)| v).sum();
    // The gradient of ln N² in the log-parameters.
    let mut g = DMatrix::<f64>::zeros(p, 1);
    for (v, idx) in &parts {
        for &i in idx {
            g[(i, 0)] += v / total;
        }
    }
    let cov = DMatrix::from_fn(p, p, |i, j| spreads.corr[(i, j)] * spreads.sd[i] * spreads.sd[j]);
    let var: f64 = (g.transpose() * cov * &g)[(0, 0)];
    let var = var.max(0.0);
    let sd = var.sqrt();
    let ln = total.ln();
    TermValue {
        value: (ln / 2.0).exp(),
        lo: ((ln - z * sd) / 2.0).exp(),
        hi: ((ln + z * sd) / 2.0).exp(),
        tau: None,
    }
}

/// The model's label, the filter's Gauss–Markov term shown as the N it is.
pub(super) fn label(comps: &[Component], filter: Option<usize>) -> String {
    let Some(f) = filter else {
        return labels(comps).join(" + ");
    };
    let mut shown: Vec<Component> = comps
        .iter()
        .enumerate()
        .filter(|&(k, c)| k != f && *c != Component::Power(Term::WhiteNoise))
        .map(|(_, c)| *c)
        .collect();
    let at = shown
        .iter()
        .position(|c| !matches!(c, Component::Power(Term::Quantization)))
        .unwrap_or(shown.len());
    shown.insert(at, Component::Power(Term::WhiteNoise));
    labels(&shown).join(" + ")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spreads(sd: Vec<f64>, corr: DMatrix<f64>) -> Spreads {
        Spreads {
            sd,
            corr,
            rescaled: false,
        }
    }

    #[test]
    fn the_filter_is_the_gauss_markov_term_at_the_sampling_interval() {
        let comps = [Component::Power(Term::BiasInstability), Component::GaussMarkov];
        let theta = [0.0, 1.0, 0.027f64.ln()];
        assert_eq!(find(&comps, &theta, 0.02), Some(1));
        // T = 100 s on a curve from 0.1 s is a process of its own.
        let theta = [0.0, 1.0, 100f64.ln()];
        assert_eq!(find(&comps, &theta, 0.1), None);
        assert_eq!(label(&comps, Some(1)), "N + B");
        let with_q = [Component::Power(Term::Quantization), Component::GaussMarkov];
        assert_eq!(label(&with_q, Some(1)), "Q + N");
    }

    #[test]
    fn white_noise_of_a_filtered_gauss_markov_term_is_two_sigma2_t() {
        let comps = [Component::GaussMarkov];
        let (s2, t) = (4e-6f64, 0.025f64);
        let theta = [s2.ln(), t.ln()];
        // ln σ² and ln T perfectly anticorrelated with equal spreads: N² is
        // known exactly.
        let corr = DMatrix::from_row_slice(2, 2, &[1.0, -1.0, -1.0, 1.0]);
        let n = white_noise(&comps, &theta, 0, &spreads(vec![0.3, 0.3], corr), 1.96);
        assert!((n.value / (2.0 * s2 * t).sqrt() - 1.0).abs() < 1e-12);
        assert!((n.hi / n.value - 1.0).abs() < 1e-9 && (n.lo / n.value - 1.0).abs() < 1e-9);
        // Independent: var ln N² = 0.09 + 0.09.
        let n = white_noise(
            &comps,
            &theta,
            0,
            &spreads(vec![0.3, 0.3], DMatrix::identity(2, 2)),
            1.96,
        );
        let want = (1.96 * 0.18f64.sqrt() / 2.0).exp();
        assert!((n.hi / n.value / want - 1.0).abs() < 1e-12);
    }

    #[test]
    fn an_unfiltered_white_term_adds_to_the_filtered_one() {
        let comps = [Component::Power(Term::WhiteNoise), Component::GaussMarkov];
        let theta = [1e-6f64.ln(), 1e-4f64.ln(), 0.01f64.ln()];
        let n = white_noise(
            &comps,
            &theta,
            1,
            &spreads(vec![0.0; 3], DMatrix::identity(3, 3)),
            1.96,
        );
        assert!((n.value * n.value / (1e-6 + 2.0 * 1e-4 * 0.01) - 1.0).abs() < 1e-12);
    }
}
