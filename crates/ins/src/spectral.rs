//! The position error of one channel from a noise given by its power
//! spectral density, for the bias instability, which has no closed form.
//!
//! The position at t after alignment is linear in the sensor error u(s):
//!
//! ```text
//! x(t) = ∫₀ᵗ h(t − s)·u(s) ds − H(t)·ū,   H(t) = ∫₀ᵗ h,   ū = the window's mean of u
//! ```
//!
//! with h the impulse response of [`crate::schuler`] (or of the flat Earth,
//! g·τ²/2 from a gyro and τ from the specific force), and ū the mean over
//! the alignment window T_a that levelling (for the specific force) or the
//! gyro's bias estimate (for the rate) takes out. For u = e^{iΩs} this is
//! G(Ω)·e^{iΩt} with
//!
//! ```text
//! G(Ω) = ∫₀ᵗ h(τ)·e^{−iΩτ} dτ − H(t)·e^{−iΩt}·(1 − e^{−iΩT_a})/(iΩT_a),
//! ```
//!
//! so a stationary error of one-sided PSD S(f) gives Var x(t) = ∫₀^∞ S(f)·
//! |G(2πf)|² df (the output variance of a linear system, Papoulis,
//! *Probability, Random Variables and Stochastic Processes*). The bias
//! instability's PSD is B²/(2π·f) two-sided (IEEE Std 952-1997, Annex C,
//! whose Allan variance of it, 2·ln 2·B²/π, gives the 0.664·B floor),
//! B²/(π·f) one-sided. Because
//! the window's mean is taken out, |G|² falls as f² at low frequency and
//! the integral converges with no cut-off: it is the variance of an ideal
//! 1/f bias wandering over every time scale, and so a bound on a real one
//! whose PSD flattens (below B²/(π·f)) outside the band where its Allan
//! deviation is flat. The older bound, a constant bias of size B, is not
//! one: the bias walks away from the window's mean logarithmically with
//! the time since alignment, and passes B after 10 (specific force) to 16
//! (gyro) window lengths; at 60 window lengths it is 1.15 times B.

use std::f64::consts::PI;

use crate::schuler;

/// A complex number, just what G needs.
#[derive(Debug, Clone, Copy, PartialEq)]
struct C {
    re: f64,
    im: f64,
}

impl C {
    const fn new(re: f64, im: f64) -> C {
        C { re, im }
    }
    fn cis(phase: f64) -> C {
        let (s, c) = phase.sin_cos();
        C::new(c, s)
    }
    fn add(self, o: C) -> C {
        C::new(self.re + o.re, self.im + o.im)
    }
    fn sub(self, o: C) -> C {
        C::new(self.re - o.re, self.im - o.im)
    }
    fn mul(self, o: C) -> C {
        C::new(self.re * o.re - self.im * o.im, self.re * o.im + self.im * o.re)
    }
    fn scale(self, k: f64) -> C {
        C::new(self.re * k, self.im * k)
    }
    fn inv(self) -> C {
        let d = self.re * self.re + self.im * self.im;
        C::new(self.re / d, -self.im / d)
    }
    fn norm_sqr(self) -> f64 {
        self.re * self.re + self.im * self.im
    }
}

fn sinc(z: f64) -> f64 {
    if z.abs() < 1e-4 {
        1.0 - z * z / 6.0
    } else {
        z.sin() / z
    }
}

/// ∫₀ᵗ e^{iaτ} dτ = t·e^{iat/2}·sinc(at/2), exact and stable at a = 0.
fn e_integral(a: f64, t: f64) -> C {
    C::cis(a * t / 2.0).scale(t * sinc(a * t / 2.0))
}

/// ∫₀ᵗ τ^k·e^{zτ} dτ for k = 1, 2 and z = −iΩ: the series below |zt| = 2
/// (the closed form cancels there), the closed form above.
fn moment(k: i32, omega: f64, t: f64) -> C {
    let z = C::new(0.0, -omega);
    let zt = omega * t;
    if zt.abs() < 2.0 {
        // t^{k+1}·Σ (zt)ⁿ / (n!·(n + k + 1))
        let mut sum = C::new(0.0, 0.0);
        let mut term = C::new(1.0, 0.0);
        let zt = C::new(0.0, -zt);
        for n in 0..40 {
            sum = sum.add(term.scale(1.0 / f64::from(n + k + 1)));
            term = term.mul(zt).scale(1.0 / f64::from(n + 1));
        }
        sum.scale(t.powi(k + 1))
    } else {
        let (ezt, iz) = (C::cis(-omega * t), z.inv());
        let iz2 = iz.mul(iz);
        match k {
            1 => ezt.mul(iz.scale(t).sub(iz2)).add(iz2),
            _ => {
                let iz3 = iz2.mul(iz);
                ezt.mul(iz.scale(t * t).sub(iz2.scale(2.0 * t)).add(iz3.scale(2.0)))
                    .sub(iz3.scale(2.0))
            }
        }
    }
}

/// Which sensor drives the channel, and whether the Schuler loop closes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kernel {
    /// A rate error, through the tilt: g·τ²/2 on a flat Earth, else
    /// (g/ω_s²)·(1 − cos ω_s·τ).
    Gyro {
        /// g, m/s².
        gravity: f64,
        /// The Schuler frequency ω_s, rad/s; `None` on a flat Earth.
        schuler_rate: Option<f64>,
    },
    /// A specific-force error: τ on a flat Earth, else sin(ω_s·τ)/ω_s.
    Accel {
        /// The Schuler frequency ω_s, rad/s; `None` on a flat Earth.
        schuler_rate: Option<f64>,
    },
}

impl Kernel {
    /// ∫₀ᵗ h(τ)·e^{−iΩτ} dτ and H(t).
    fn responses(self, omega: f64, t: f64) -> (C, f64) {
        match self {
            Kernel::Gyro {
                gravity,
                schuler_rate: None,
            } => (
                moment(2, omega, t).scale(gravity / 2.0),
                gravity * t.powi(3) / 6.0,
            ),
            Kernel::Accel { schuler_rate: None } => (moment(1, omega, t), t * t / 2.0),
            Kernel::Gyro {
                gravity,
                schuler_rate: Some(w),
            } => {
                let r = gravity / (w * w);
                let cos = e_integral(w - omega, t).add(e_integral(-w - omega, t)).scale(0.5);
                let nav = e_integral(-omega, t).sub(cos).scale(r);
                (nav, gravity * t.powi(3) / 6.0 * schuler::constant_gyro(w * t))
            }
            Kernel::Accel {
                schuler_rate: Some(w),
            } => {
                // (E(ω − Ω) − E(−ω − Ω)) / (2iω)
                let d = e_integral(w - omega, t).sub(e_integral(-w - omega, t));
                let nav = d.mul(C::new(0.0, -1.0 / (2.0 * w)));
                (nav, t * t / 2.0 * schuler::constant_accel(w * t))
            }
        }
    }
}

/// |G(2πf)|² of `kernel` at `t` s after an alignment of `align_s` s whose
/// mean is taken out (`remove_mean`) or not.
pub fn gain(kernel: Kernel, t: f64, align_s: f64, remove_mean: bool, f: f64) -> f64 {
    let omega = 2.0 * PI * f;
    let (nav, h) = kernel.responses(omega, t);
    if !remove_mean {
        return nav.norm_sqr();
    }
    let mean = C::cis(-omega * (t + align_s / 2.0)).scale(h * sinc(omega * align_s / 2.0));
    nav.sub(mean).norm_sqr()
}

/// Nodes and weights of 8-point Gauss–Legendre on [−1, 1] (Abramowitz &
/// Stegun, Table 25.4).
const GL8: [(f64, f64); 4] = [
    (0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (0.796_666_477_413_626_7, 0.222_381_034_453_374_5),
    (0.960_289_856_497_536_2, 0.101_228_536_290_376_3),
];

/// The most pieces of the linear stretch.
const MAX_PIECES: f64 = 200_000.0;

fn gauss(a: f64, b: f64, f: &impl Fn(f64) -> f64) -> f64 {
    let (m, h) = ((a + b) / 2.0, (b - a) / 2.0);
    h * GL8
        .iter()
        .map(|&(x, w)| w * (f(m - h * x) + f(m + h * x)))
        .sum::<f64>()
}

/// ∫₀^∞ S(f)·|G(2πf)|² df for a one-sided PSD `psd`: on ln f below
/// 1/(t + T_a), where |G|² is smooth; on f, an oscillation of |G|² per
/// piece, up to 20/min(t, T_a); on ln f again above, where |G|² has
/// fallen as 1/f² and its oscillations are averaged.
pub fn variance(kernel: Kernel, t: f64, align_s: f64, remove_mean: bool, psd: impl Fn(f64) -> f64) -> f64 {
    let span = t + if remove_mean { align_s } else { 0.0 };
    let short = if remove_mean { t.min(align_s) } else { t };
    let on_log = |u: f64| {
        let f = u.exp();
        psd(f) * gain(kernel, t, align_s, remove_mean, f) * f
    };
    let on_lin = |f: f64| psd(f) * gain(kernel, t, align_s, remove_mean, f);
    let (f1, f2) = (1.0 / span, 20.0 / short);
    let mut sum = 0.0;
    let log_pieces = |lo: f64, hi: f64| -> f64 {
        let n = ((hi - lo) / 0.05).ceil().max(1.0) as usize;
        let w = (hi - lo) / n as f64;
        (0..n)
            .map(|i| gauss(lo + i as f64 * w, lo + (i + 1) as f64 * w, &on_log))
            .sum()
    };
    sum += log_pieces((1e-5 * f1).ln(), f1.ln());
    // One piece per oscillation; a very short window under a long horizon
    // (hundreds of thousands of oscillations) gets wider pieces, over which
    // the oscillating part, already small at those frequencies, averages.
    let n = ((f2 - f1) * span).ceil().clamp(1.0, MAX_PIECES) as usize;
    let w = (f2 - f1) / n as f64;
    sum += (0..n)
        .map(|i| gauss(f1 + i as f64 * w, f1 + (i + 1) as f64 * w, &on_lin))
        .sum::<f64>();
    sum += log_pieces(f2.ln(), (f2 * 1e4).ln());
    sum
}

/// The position variance from a bias instability `b` (unit of the sensor):
/// its one-sided PSD b²/(π·f) over every frequency.
pub fn bias_instability_variance(kernel: Kernel, b: f64, t: f64, align_s: f64) -> f64 {
    if b == 0.0 {
        return 0.0;
    }
    variance(kernel, t, align_s, true, |f| b * b / (PI * f))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_moments_series_and_closed_form_agree() {
        for k in [1, 2] {
            let t = 3.0;
            let below = moment(k, 2.0 / t - 1e-13, t);
            let above = moment(k, 2.0 / t + 1e-13, t);
            assert!((below.sub(above)).norm_sqr().sqrt() < 1e-11 * above.norm_sqr().sqrt());
        }
        // ∫₀ᵗ τ dτ and ∫₀ᵗ τ² dτ at Ω = 0.
        assert!((moment(1, 0.0, 3.0).re - 4.5).abs() < 1e-12);
        assert!((moment(2, 0.0, 3.0).re - 9.0).abs() < 1e-12);
    }

    #[test]
    fn at_zero_frequency_the_mean_removal_cancels_a_constant() {
        for kernel in [
            Kernel::Gyro {
                gravity: 9.8,
                schuler_rate: None,
            },
            Kernel::Accel {
                schuler_rate: Some(1.24e-3),
            },
        ] {
            assert!(gain(kernel, 600.0, 10.0, true, 1e-12) < 1e-6 * gain(kernel, 600.0, 10.0, false, 1e-12));
        }
    }
}
