//! Theo1 (NIST SP 1065 §5.2.15, eq. 30; Howe & Peppler 2003).
//!
//! Theo1(m, τ0, N) = 1/(0.75·(N−m)·(mτ0)²) Σ_{i=1}^{N−m} Σ_{δ=0}^{m/2−1}
//! [(x_i − x_{i−δ+m/2}) + (x_{i+m} − x_{i+δ+m/2})]² / (m/2 − δ),
//! for even m. It estimates the Allan variance at τ = 0.75·m·τ0
//! ([`theo1_tau`]). Not bias-corrected, as Stable32 1.60 and AllanTools
//! print it.
//!
//! Cost: O(N·m/2) per τ: Theo1 is meant for short series, where it reaches
//! the longest τ.

use super::Estimate;

/// The τ Theo1 reports at averaging factor m: 0.75·m·τ0.
pub fn theo1_tau(m: usize, tau0: f64) -> f64 {
    0.75 * m as f64 * tau0
}

/// Theo1 deviation at even averaging factor m (2 ≤ m ≤ N − 1).
pub fn theo1(phase: &[f64], m: usize, tau0: f64) -> Option<Estimate> {
    let n = phase.len();
    if m < 2 || m % 2 == 1 || m >= n || tau0.is_nan() || tau0 <= 0.0 {
        return None;
    }
    let h = m / 2;
    let mut total = 0.0;
    for i in 0..n - m {
        let a = phase[i] + phase[i + m];
        let mut s = 0.0;
        for d in 0..h {
            let v = a - phase[i + h - d] - phase[i + h + d];
            s += v * v / (h - d) as f64;
        }
        total += s;
    }
    let tau = m as f64 * tau0;
    let dev = (total / (0.75 * (n - m) as f64 * tau * tau)).sqrt();
    dev.is_finite().then_some(Estimate { dev, n: (n - m) * h })
}
