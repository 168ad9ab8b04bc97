//! Flicker (1/f) rate noise from a bank of first-order Gauss–Markov
//! processes with correlation times spaced evenly in log τ.
//!
//! A Gauss–Markov process of variance σ² and correlation time T has the
//! one-sided PSD 4σ²T/(1 + (2πfT)²). Summed over times spaced Δ = ln r
//! apart in ln T, the bank approaches ∫ 4σ²T/(1+(2πfT)²) dlnT / Δ =
//! σ²/(Δ·f): a 1/f spectrum between 1/(2πT_max) and 1/(2πT_min). IEEE 952
//! gives bias instability B the two-sided rate PSD B²/(2π f), one-sided
//! B²/(π f), so each process gets σ² = B²Δ/π, and the Allan deviation is
//! flat at 0.664·B over the τ the bank covers.
//!
//! Streaming: each process keeps one number. The slow ones are updated
//! only every few samples (a 32nd of their correlation time), exactly
//! (φ = e^(−stride·τ0/T)), and held in between, so that a bank reaching
//! days of correlation costs a few normal draws per sample.

use rand::Rng;
use rand_distr::{Distribution, StandardNormal};

/// Correlation times per decade: the ripple of the summed spectrum stays
/// well inside the ±10 % the Allan deviation may wander.
pub const POLES_PER_DECADE: f64 = 3.0;

#[derive(Debug, Clone)]
struct Pole {
    value: f64,
    phi: f64,
    kick: f64,
    stride: u32,
    /// Samples until the next update.
    countdown: u32,
}

/// A unit flicker source (B = 1): multiply by B.
#[derive(Debug, Clone)]
pub struct FlickerBank {
    poles: Vec<Pole>,
    sum: f64,
}

impl FlickerBank {
    /// A bank whose Allan deviation is flat for τ in `[tau_lo, tau_hi]` (s),
    /// at sample interval `tau0`.
    pub fn new(tau0: f64, tau_lo: f64, tau_hi: f64, rng: &mut impl Rng) -> FlickerBank {
        // The Allan deviation at τ weighs the spectrum over about a decade
        // on either side of 1/τ: the poles reach well beyond the flat range.
        let t_min = (0.1 * tau_lo).max(0.5 * tau0);
        let t_max = (20.0 * tau_hi).max(t_min);
        let ratio = 10f64.powf(1.0 / POLES_PER_DECADE);
        let count = ((t_max / t_min).ln() / ratio.ln()).ceil() as usize + 1;
        let sigma = (ratio.ln() / std::f64::consts::PI).sqrt();
        let poles = (0..count)
            .map(|i| {
                let t = t_min * ratio.powi(i as i32);
                let stride = ((t / tau0 / 32.0).floor().min(f64::from(u32::MAX)) as u32).max(1);
                let phi = (-(stride as f64) * tau0 / t).exp();
                let w: f64 = StandardNormal.sample(rng);
                let value = sigma * w;
                Pole {
                    value,
                    phi,
                    kick: sigma * (1.0 - phi * phi).sqrt(),
                    stride,
                    countdown: stride,
                }
            })
            .collect::<Vec<_>>();
        let sum = poles.iter().map(|p| p.value).sum();
        FlickerBank { poles, sum }
    }

    /// The next sample.
    pub fn next(&mut self, rng: &mut impl Rng) -> f64 {
        for p in &mut self.poles {
            p.countdown -= 1;
            if p.countdown == 0 {
                p.countdown = p.stride;
                let w: f64 = StandardNormal.sample(rng);
                let new = p.phi * p.value + p.kick * w;
                self.sum += new - p.value;
                p.value = new;
            }
        }
        self.sum
    }
}
