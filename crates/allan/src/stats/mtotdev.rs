//! Modified total deviation and time total deviation (NIST SP 1065 §5.2.12
//! and §5.2.13, eqs. 27 and 28; Howe & Vernotte 1999).
//!
//! For each of the N − 3m + 1 subsequences of 3m phase points: remove the
//! linear trend given by the means of its first and last halves, extend it
//! by uninverted even reflection at both ends to 9m points, and average the
//! 6m squared second differences of m-point sums over the extension:
//! Mod Totvar(τ) = 1/(2τ²(N−3m+1)) Σ_n [1/(6m) Σ_i (z̄_{i+2m} − 2z̄_{i+m} + z̄_i)²],
//! z̄ the m-point means. Values are **not** bias-corrected (SP 1065 divides
//! by 0.73 for white FM); Stable32 1.60 and AllanTools print them so, and
//! [`MTOTVAR_BIAS`] gives the published correction.
//!
//! Cost: O(m) per subsequence with running sums, O(N·m) per τ, O(m) scratch.

use super::Estimate;

/// SP 1065's bias of MTOTVAR for white FM: published values are
/// `mtotdev / sqrt(MTOTVAR_BIAS)`.
pub const MTOTVAR_BIAS: f64 = 0.73;

/// Σ over the 6m positions of the squared second difference of m-point
/// sums on the 9m-point extension `xstar`, with running window sums.
pub(crate) fn reflected_second_differences(xstar: &[f64], m: usize) -> f64 {
    let (mut s1, mut s2, mut s3) = (
        xstar[..m].iter().sum::<f64>(),
        xstar[m..2 * m].iter().sum::<f64>(),
        xstar[2 * m..3 * m].iter().sum::<f64>(),
    );
    let mf = m as f64;
    let mut acc = 0.0;
    for j in 0..6 * m {
        if j > 0 {
            s1 += xstar[j + m - 1] - xstar[j - 1];
            s2 += xstar[j + 2 * m - 1] - xstar[j + m - 1];
            s3 += xstar[j + 3 * m - 1] - xstar[j + 2 * m - 1];
        }
        let v = (s1 - 2.0 * s2 + s3) / mf;
        acc += v * v;
    }
    acc
}

/// Fills `xstar` (9m long, for a 3m subsequence) with
/// [reversed, detrended, reversed] where detrended[k] = xs[k] − slope·(k − k0).
pub(crate) fn extend_by_reflection(xs: &[f64], slope: f64, k0: f64, xstar: &mut [f64]) {
    let l = xs.len();
    for (k, &v) in xs.iter().enumerate() {
        let d = v - slope * (k as f64 - k0);
        xstar[l + k] = d;
        xstar[l - 1 - k] = d;
        xstar[3 * l - 1 - k] = d;
    }
}

/// The slope per sample between the means of the first and last halves of
/// `xs` (the halves share the middle point when the length is odd).
pub(crate) fn half_means_slope(xs: &[f64]) -> f64 {
    let l = xs.len();
    let h1 = l / 2;
    let h2 = l - h1;
    let mean1 = xs[..h1].iter().sum::<f64>() / h1 as f64;
    let mean2 = xs[h2..].iter().sum::<f64>() / (l - h2) as f64;
    // Distance between the centres of the two halves, in samples.
    let span = if l % 2 == 1 {
        0.5 * (l - 1) as f64 + 1.0
    } else {
        0.5 * l as f64
    };
    (mean2 - mean1) / span
}

/// Modified total deviation at averaging factor m (needs 3m ≤ N).
pub fn mtotdev(phase: &[f64], m: usize, tau0: f64) -> Option<Estimate> {
    let n = phase.len();
    if m == 0 || 3 * m > n || tau0.is_nan() || tau0 <= 0.0 {
        return None;
    }
    let l = 3 * m;
    let terms = n - l + 1;
    let mut xstar = vec![0.0; 3 * l];
    let mut total = 0.0;
    for i in 0..terms {
        let xs = &phase[i..i + l];
        extend_by_reflection(xs, half_means_slope(xs), 0.0, &mut xstar);
        total += reflected_second_differences(&xstar, m) / (6.0 * m as f64);
    }
    let tau = m as f64 * tau0;
    let dev = (total / (2.0 * tau * tau * terms as f64)).sqrt();
    dev.is_finite().then_some(Estimate { dev, n: terms })
}

/// Time total deviation, τ·MTOTDEV/√3 (SP 1065 eq. 28), not bias-corrected.
pub fn ttotdev(phase: &[f64], m: usize, tau0: f64) -> Option<Estimate> {
    mtotdev(phase, m, tau0).map(|e| Estimate {
        dev: e.dev * m as f64 * tau0 / 3f64.sqrt(),
        n: e.n,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// SP 1065 Table 30 input as phase, x = [0, cumsum(y − ȳ)].
    fn nbs14_phase() -> Vec<f64> {
        let y = [892.0, 809.0, 823.0, 798.0, 671.0, 644.0, 883.0, 903.0, 677.0];
        let mean = y.iter().sum::<f64>() / 9.0;
        let mut x = vec![0.0];
        for v in y {
            x.push(x.last().unwrap() + v - mean);
        }
        x
    }

    #[test]
    fn nbs14_ten_point_set() {
        let x = nbs14_phase();
        // AllanTools 2024.6 (reference_values.json): mtotdev 64.5089625556,
        // 64.7943631093 (n 8, 5); ttotdev 37.2442668966, 74.8180859663;
        // Stable32 1.60 (no bias correction): 64.509, 64.794; 37.244, 74.818.
        let cases = [
            (1, 64.5089625556, 37.2442668966, 8),
            (2, 64.7943631093, 74.8180859663, 5),
        ];
        for (m, md, td, n) in cases {
            let e = mtotdev(&x, m, 1.0).unwrap();
            assert!(((e.dev - md) / md).abs() < 1e-10, "m={m}: {}", e.dev);
            assert_eq!(e.n, n);
            let t = ttotdev(&x, m, 1.0).unwrap();
            assert!(((t.dev - td) / td).abs() < 1e-10, "m={m}: {}", t.dev);
        }
        // SP 1065 Table 30 publishes the bias-corrected values.
        let corrected = mtotdev(&x, 1, 1.0).unwrap().dev / MTOTVAR_BIAS.sqrt();
        assert!((corrected - 75.50203).abs() < 1e-4 * 75.5, "{corrected}");
        assert!(mtotdev(&x, 4, 1.0).is_none());
    }
}
