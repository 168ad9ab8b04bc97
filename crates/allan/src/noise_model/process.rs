//! The theoretical Allan variance of each candidate process, as a function
//! of τ, for a process of unit size (the fit multiplies by the size²).
//!
//! Sources, each checked against the limits of the others:
//! - IEEE Std 952-1997 Annex C: quantization 3Q²/τ², white noise N²/τ,
//!   rate random walk K²τ/3, rate ramp R²τ²/2, and the flicker floor
//!   (2 ln 2/π)B² that it gives for τ well above the flicker's lower cutoff.
//! - First-order Gauss–Markov x' = −x/T + w with stationary variance σ²:
//!   AVAR(τ) = (2σ²T/τ)·[1 − (T/2τ)(3 − 4e^{−τ/T} + e^{−2τ/T})]
//!   (El-Sheimy, Hou & Niu, IEEE TIM 57(1), 2008, with q_c² = 2σ²/T),
//!   checked here against a direct integration of its autocovariance.
//!   It tends to N²/τ with N² = 2σ²T for τ ≫ T and to K²τ/3 with
//!   K² = 2σ²/T for τ ≪ T (tested below).

/// √(2 ln 2 / π)² = 0.4413…: the Allan variance floor of flicker noise of
/// bias instability 1 (IEEE 952 Annex C).
pub const FLICKER_FLOOR_VAR: f64 = 2.0 * std::f64::consts::LN_2 / std::f64::consts::PI;

/// AVAR of quantization noise Q = 1 at τ.
pub fn quantization(tau: f64) -> f64 {
    3.0 / (tau * tau)
}

/// AVAR of white rate noise N = 1 at τ.
pub fn white(tau: f64) -> f64 {
    1.0 / tau
}

/// AVAR of flicker noise of bias instability B = 1 (its plateau).
pub fn flicker(_tau: f64) -> f64 {
    FLICKER_FLOOR_VAR
}

/// AVAR of a rate random walk K = 1 at τ.
pub fn random_walk(tau: f64) -> f64 {
    tau / 3.0
}

/// AVAR of a rate ramp R = 1 at τ.
pub fn ramp(tau: f64) -> f64 {
    tau * tau / 2.0
}

/// AVAR at τ of a first-order Gauss–Markov process of unit variance and
/// correlation time `tc`.
pub fn gauss_markov(tau: f64, tc: f64) -> f64 {
    let x = tau / tc;
    if x < 1e-2 {
        // The bracket cancels to x²/3 − x³/4 + 7x⁴/60 − x⁵/24 + …: the series keeps the
        // digits that the closed form loses to cancellation.
        return 2.0 * x / 3.0 * (1.0 - x * (0.75 - x * (0.35 - x / 8.0)));
    }
    let bracket = 1.0 - (3.0 - 4.0 * (-x).exp() + (-2.0 * x).exp()) / (2.0 * x);
    2.0 / x * bracket
}

/// ∂/∂(ln T) of [`gauss_markov`]: −x·dg/dx at x = τ/T.
pub fn gauss_markov_dln_tc(tau: f64, tc: f64) -> f64 {
    let x = tau / tc;
    let dg = if x < 1e-2 {
        2.0 / 3.0 - x * (1.0 - x * (0.7 - x / 3.0))
    } else {
        let (e1, e2) = ((-x).exp(), (-2.0 * x).exp());
        -2.0 / (x * x) + 2.0 * (3.0 - 4.0 * e1 + e2) / (x * x * x) - (4.0 * e1 - 2.0 * e2) / (x * x)
    };
    -x * dg
}

/// [`gauss_markov`] and [`gauss_markov_dln_tc`] together, their
/// exponentials computed once: the same values, bit for bit.
pub fn gauss_markov_and_dln_tc(tau: f64, tc: f64) -> (f64, f64) {
    let x = tau / tc;
    if x < 1e-2 {
        return (gauss_markov(tau, tc), gauss_markov_dln_tc(tau, tc));
    }
    let (e1, e2) = ((-x).exp(), (-2.0 * x).exp());
    let bracket = 1.0 - (3.0 - 4.0 * e1 + e2) / (2.0 * x);
    let dg = -2.0 / (x * x) + 2.0 * (3.0 - 4.0 * e1 + e2) / (x * x * x) - (4.0 * e1 - 2.0 * e2) / (x * x);
    (2.0 / x * bracket, -x * dg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_markov_tends_to_white_noise_and_random_walk() {
        let tc = 50.0;
        // τ ≫ T: N² = 2σ²T.
        let tau = 1e5;
        assert!((gauss_markov(tau, tc) / (2.0 * tc * white(tau)) - 1.0).abs() < 2e-3);
        // τ ≪ T: K² = 2σ²/T.
        let tau = 1e-3;
        assert!((gauss_markov(tau, tc) / (2.0 / tc * random_walk(tau)) - 1.0).abs() < 1e-4);
    }

    #[test]
    fn gauss_markov_derivative_matches_differences() {
        for (tau, tc) in [(0.5e-2, 1.0), (0.3, 1.0), (2.0, 1.0), (40.0, 1.0)] {
            let h: f64 = 1e-6;
            let num = (gauss_markov(tau, tc * h.exp()) - gauss_markov(tau, tc * (-h).exp())) / (2.0 * h);
            let ana = gauss_markov_dln_tc(tau, tc);
            assert!(
                (num - ana).abs() < 1e-6 * ana.abs().max(1e-3),
                "{tau}: {num} {ana}"
            );
        }
    }

    #[test]
    fn gauss_markov_and_its_derivative_together_are_each_alone() {
        for (tau, tc) in [(0.5e-2, 1.0), (0.3, 1.0), (2.0, 1.0), (40.0, 1.0), (7.0, 3e-3)] {
            let (g, dg) = gauss_markov_and_dln_tc(tau, tc);
            assert_eq!(g.to_bits(), gauss_markov(tau, tc).to_bits(), "{tau}");
            assert_eq!(dg.to_bits(), gauss_markov_dln_tc(tau, tc).to_bits(), "{tau}");
        }
    }

    #[test]
    fn gauss_markov_series_meets_closed_form() {
        // Just below the switch, where the closed form still holds 8 digits
        // and the series omits terms of order x⁴.
        let x: f64 = 0.99e-2;
        let closed = 2.0 / x * (1.0 - (3.0 - 4.0 * (-x).exp() + (-2.0 * x).exp()) / (2.0 * x));
        assert!((gauss_markov(x, 1.0) / closed - 1.0).abs() < 1e-7);
    }

    #[test]
    fn gauss_markov_matches_its_autocovariance() {
        // AVAR = Var(ȳ) − Cov(ȳ₁, ȳ₂) for the autocovariance R(v) = e^{−v/T}:
        // Var(ȳ) = (2/τ²)∫₀^τ (τ−v)R(v)dv, Cov = (1/τ²)∫₀^{2τ} min(v, 2τ−v)R(v)dv,
        // integrated by the trapezoid rule, independently of the closed form.
        let tc = 3.0;
        for tau in [0.3, 3.0, 5.67, 30.0] {
            let steps = 200_000;
            let integrate = |f: &dyn Fn(f64) -> f64, upper: f64| {
                let h = upper / steps as f64;
                (0..=steps)
                    .map(|i| {
                        let w = if i == 0 || i == steps { 0.5 } else { 1.0 };
                        w * f(i as f64 * h)
                    })
                    .sum::<f64>()
                    * h
            };
            let r = |v: f64| (-v / tc).exp();
            let var = 2.0 / (tau * tau) * integrate(&|v| (tau - v) * r(v), tau);
            let cov = integrate(&|v| v.min(2.0 * tau - v) * r(v), 2.0 * tau) / (tau * tau);
            let want = var - cov;
            assert!((gauss_markov(tau, tc) / want - 1.0).abs() < 1e-6, "{tau}");
        }
    }
}
