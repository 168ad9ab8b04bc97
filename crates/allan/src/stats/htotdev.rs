//! Hadamard total deviation (NIST SP 1065 §5.2.14, eq. 29).
//!
//! On the N rate values y: for each of the N − 3m + 1 subsequences of 3m
//! values, remove the linear trend given by the means of its halves, extend
//! by uninverted even reflection to 9m values, and average the 6m squared
//! second differences of m-point means:
//! Htotvar(τ) = 1/(N−3m+1) Σ_n [1/(6·6m) Σ_i (ȳ_{i+2m} − 2ȳ_{i+m} + ȳ_i)²].
//! At m = 1 it is the overlapping Hadamard deviation, as in SP 1065,
//! Stable32 and AllanTools. Values are **not** bias-corrected (SP 1065
//! divides by 0.995 for white FM; see [`HTOTVAR_BIAS`]).
//!
//! Cost: O(m) per subsequence, O(N·m) per τ, O(m) scratch.

use super::Estimate;
use super::mtotdev::{extend_by_reflection, half_means_slope, reflected_second_differences};

/// SP 1065's bias of HTOTVAR for white FM: published values are
/// `htotdev / sqrt(HTOTVAR_BIAS)`.
pub const HTOTVAR_BIAS: f64 = 0.995;

/// Hadamard total deviation at averaging factor m (needs 3m ≤ N − 1).
pub fn htotdev(phase: &[f64], m: usize, tau0: f64) -> Option<Estimate> {
    if m == 0 || tau0.is_nan() || tau0 <= 0.0 || phase.len() < 4 {
        return None;
    }
    if m == 1 {
        // The overlapping Hadamard deviation at τ0, from phase.
        let terms = phase.len() - 3;
        let sum: f64 = phase
            .windows(4)
            .map(|w| {
                let v = w[3] - 3.0 * w[2] + 3.0 * w[1] - w[0];
                v * v
            })
            .sum();
        let dev = (sum / (6.0 * terms as f64 * tau0 * tau0)).sqrt();
        return dev.is_finite().then_some(Estimate { dev, n: terms });
    }
    // Rate values from phase: y_i = (x_{i+1} − x_i)/τ0.
    let y: Vec<f64> = phase.windows(2).map(|w| (w[1] - w[0]) / tau0).collect();
    let n = y.len();
    let l = 3 * m;
    if l > n {
        return None;
    }
    let terms = n - l + 1;
    let mut xstar = vec![0.0; 3 * l];
    let mf = m as f64;
    let mut total = 0.0;
    for i in 0..terms {
        let xs = &y[i..i + l];
        extend_by_reflection(xs, half_means_slope(xs), (l / 2) as f64, &mut xstar);
        let acc = reflected_second_differences(&xstar, m);
        total += acc / (6.0 * 6.0 * mf);
    }
    let dev = (total / terms as f64).sqrt();
    dev.is_finite().then_some(Estimate { dev, n: terms })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nbs14_ten_point_set() {
        let y = [892.0, 809.0, 823.0, 798.0, 671.0, 644.0, 883.0, 903.0, 677.0];
        let mean = y.iter().sum::<f64>() / 9.0;
        let mut x = vec![0.0];
        for v in y {
            x.push(x.last().unwrap() + v - mean);
        }
        // AllanTools 2024.6 (reference_values.json): 70.8060731859 (n 7),
        // 90.935765478 (n 4) at τ = 1, 2.
        for (m, want, n) in [(1, 70.8060731859, 7), (2, 90.935765478, 4)] {
            let e = htotdev(&x, m, 1.0).unwrap();
            assert!(((e.dev - want) / want).abs() < 1e-10, "m={m}: {}", e.dev);
            assert_eq!(e.n, n);
        }
        assert!(htotdev(&x, 3, 1.0).is_some());
        assert!(htotdev(&x, 4, 1.0).is_none());
    }
}
