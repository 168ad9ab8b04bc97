//! Hadamard total deviation (HTOTDEV), NIST SP 1065 eq. 29 (Howe et al.,
//! PTTI 2000).
//!
//! # Definition
//!
//! HDEV ignores a constant frequency drift but, like ADEV, has few
//! independent terms at long τ. HTOT evaluates the Hadamard difference on
//! reflected copies of the rate data so that every τ up to N/3 uses all
//! windows. On the N − 1 rate values y_i = (x_{i+1} − x_i)/τ0 of N phase
//! points, for each subsequence of 3m values y_n … y_{n+3m−1}:
//!
//! 1. remove the linear frequency trend through the means of its first and
//!    last halves (as for MTOT, SP 1065 eq. 27);
//! 2. extend the residual at both ends by uninverted even reflection to 9m
//!    values y#;
//! 3. average the 6m squared second differences of m-point means,
//!    (ȳ#_{i+2m} − 2ȳ#_{i+m} + ȳ#_i)², over that extension.
//!
//! Htotvar(τ) = 1/(6(N−3m)) Σ_n 1/(6m) Σ_i (ȳ#_{i+2m} − 2ȳ#_{i+m} + ȳ#_i)²,
//! τ = m·τ0, with N − 3m = (N − 1) − 3m + 1 subsequences. At m = 1 SP 1065,
//! Stable32 and AllanTools use the overlapping Hadamard deviation instead
//! ("for best consistency", Riley), and so does [`htotdev`].
//!
//! # Bias
//!
//! The deviations returned are **not** bias-corrected: Stable32 1.60 and
//! AllanTools 2024.6 print them so. SP 1065 Table 30/31 publish HTOT for
//! m ≥ 2 divided by √[`HTOTVAR_BIAS`] (the white-FM value 0.995); the m = 1
//! value (OHDEV) is published as is.
//!
//! # Computation and cost
//!
//! The partial sums of the rate values are the phase points (times 1/τ0),
//! so each window is read straight from its 3m + 1 phase points: no rate
//! series is formed, and the folded evaluation shared with MTOT
//! ([`super::mtotdev`]) needs no partial sums of its own. Per τ (m ≥ 2):
//! O((N − 3m)·m) time (per window and unit of m, measured by
//! `allan_per_tau`, bench/README.md), and O(1) scratch (3 × 256 per-window
//! values). At m = 1 the OHDEV
//! of the crate is used, which copies the series once (O(N)).
//!
//! HTOT is MTOT's folded sum on the rate windows, so it stays O(N·m) per τ
//! for the reasons given in [`super::mtotdev`] ("Why not below O(N·m) per
//! τ"): the reflection makes every window's sum a self-convolution about
//! its own centre, which no running sum carries to the next window, and
//! regrouping by lag squares partial sums before differencing them, which
//! loses the digits the reference tests hold.

use super::Estimate;
use super::mtotdev::{Folds, Sum, valid_tau0};
use crate::DataType;
use crate::phase::PhaseSeries;

/// SP 1065's variance bias of HTOT (m ≥ 2) for white FM noise: published
/// HTOTDEV = [`htotdev`] / √0.995 for m ≥ 2, unchanged at m = 1.
pub const HTOTVAR_BIAS: f64 = 0.995;

/// Hadamard total deviation at averaging factor m, τ = m·τ0, from phase
/// (NIST SP 1065 eq. 29; the overlapping Hadamard deviation at m = 1),
/// **without** the white-FM bias correction (as Stable32 1.60 and
/// AllanTools 2024.6 print it; see [`HTOTVAR_BIAS`]).
///
/// `n` is the number of 3m-value rate subsequences, N − 3m for N phase
/// points (N − 3 OHDEV terms at m = 1), as AllanTools and Stable32 report
/// it. Returns `None` when m = 0, 3m > N − 1, τ0 is not a positive finite
/// number or a phase point is not finite. A single subsequence (3m = N − 1)
/// is returned; AllanTools drops one-term results, so the caller's tau grid
/// decides whether to show it.
///
/// Cost O((N − 3m)·m) time and O(1) scratch for m ≥ 2 (see the module
/// notes); O(N) time and one copy of the series at m = 1.
pub fn htotdev(phase: &[f64], m: usize, tau0: f64) -> Option<Estimate> {
    htotdev_with_progress(phase, m, tau0, &|_| {})
}

/// [`htotdev`], reporting its work as it goes: `progress` receives the
/// windows × m done since its last call (the whole series at once at
/// m = 1), so the calls add up to [`crate::work::operations`].
pub fn htotdev_with_progress(phase: &[f64], m: usize, tau0: f64, progress: &dyn Fn(u64)) -> Option<Estimate> {
    let n = phase.len();
    let len = m.checked_mul(3)?;
    if m == 0 || n == 0 || len > n - 1 || !valid_tau0(tau0) || !phase.iter().all(|v| v.is_finite()) {
        return None;
    }
    if m == 1 {
        let series = PhaseSeries::new(phase, DataType::Phase, 1.0 / tau0).ok()?;
        let e = super::ohdev(&series, 1);
        progress(n as u64);
        return e;
    }
    let terms = n - len;
    let mut folds = Folds::new();
    let mut sum = Sum::default();
    for first in (0..terms).step_by(Folds::BLOCK) {
        let count = Folds::BLOCK.min(terms - first);
        // The phase points are the partial sums of the rate values.
        sum.add(folds.block(&phase[first..first + count + len], m, count));
        progress((count * m) as u64);
    }
    // Window sums are of τ0·y: Σ_n Σ_i (m-sum difference)² /
    // (τ0² m² · 6 · 6m · (N − 3m)).
    let mf = m as f64;
    let var = sum.value() / (36.0 * mf.powi(3) * tau0 * tau0 * terms as f64);
    let dev = var.sqrt();
    dev.is_finite().then_some(Estimate { dev, n: terms })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::mtotdev::tests::{
        check_folded_against_direct, check_phase_dat, check_same_deviation, extended_windows_direct,
        integrate, matches_printed, nbs14_10_phase, nbs14_10_phase_table30, nbs14_1000_freq, phase_dat, rel,
        walk,
    };

    /// SP 1065 eq. 29 as written, on rate values. The reference for the
    /// folded computation (m ≥ 2).
    fn htotvar_direct(x: &[f64], m: usize, tau0: f64) -> f64 {
        let y: Vec<f64> = x.windows(2).map(|w| (w[1] - w[0]) / tau0).collect();
        let (total, terms) = extended_windows_direct(&y, m);
        total / (6.0 * terms as f64)
    }

    #[test]
    fn nbs14_ten_point_set() {
        let x = nbs14_10_phase();
        // AllanTools 2024.6, reference_values.json "nbs14_10pt.
        // allantools_2024.06_computed.htotdev": 70.8060731859 (n 7),
        // 90.935765478 (n 4) at τ = 1, 2.
        for (m, want, n) in [(1, 70.8060731859, 7), (2, 90.935765478, 4)] {
            let e = htotdev(&x, m, 1.0).unwrap();
            assert!(rel(e.dev, want) < 1e-10, "m={m}: {}", e.dev);
            assert_eq!(e.n, n);
        }
        // SP 1065 Table 30 (bias-corrected for m ≥ 2): 70.80607, 91.16396,
        // computed from the phase as the table prints it (5 decimals).
        let printed = nbs14_10_phase_table30();
        assert!(matches_printed(
            htotdev(&printed, 1, 1.0).unwrap().dev,
            70.80607,
            7
        ));
        let c2 = htotdev(&printed, 2, 1.0).unwrap().dev / HTOTVAR_BIAS.sqrt();
        assert!(matches_printed(c2, 91.16396, 7), "{c2}");
        // 9 rate values: m = 3 is one subsequence, m = 4 is too long.
        assert_eq!(htotdev(&x, 3, 1.0).map(|e| e.n), Some(1));
        assert!(htotdev(&x, 4, 1.0).is_none());
    }

    /// AllanTools 2024.6 on PHASE.DAT (1000-point set, τ0 = 1), from
    ///
    /// ```text
    /// import numpy as np, allantools as at     # allantools==2024.6
    /// n = 1234567890; y = []
    /// for i in range(1000):
    ///     y.append(n / 2147483647.0); n = (16807 * n) % 2147483647
    /// y = np.array(y); x = np.concatenate(([0.0], np.cumsum(y - y.mean())))
    /// ms = np.array([1, 2, 4, 8, 16, 32, 64, 128, 256, 10, 20, 40, 100, 200.])
    /// t, d, e, ns = at.htotdev(x, rate=1.0, data_type='phase', taus=ms)
    /// print([(int(a), repr(float(b)), int(c)) for a, b, c in zip(t, d, ns)])
    /// ```
    ///
    /// (`at.htotdev(y, data_type='freq')` agrees to 1e-15.)
    const ALLANTOOLS_PHASE_DAT: [(usize, f64, usize); 14] = [
        (1, 0.29438832912413204, 998),
        (2, 0.20246625949942565, 995),
        (4, 0.14216462831686905, 989),
        (8, 0.10795284739233267, 977),
        (10, 0.09590720410647499, 971),
        (16, 0.06510204584116777, 953),
        (20, 0.053674709267604113, 941),
        (32, 0.044531930794228146, 905),
        (40, 0.04173040005941452, 881),
        (64, 0.0334922085850932, 809),
        (100, 0.030504478811998362, 701),
        (128, 0.028789940479667517, 617),
        (200, 0.01829577724074852, 401),
        (256, 0.014773396838998707, 233),
    ];

    #[test]
    fn phase_dat_against_allantools() {
        check_phase_dat(htotdev, &ALLANTOOLS_PHASE_DAT);
    }

    #[test]
    fn phase_dat_against_stable32() {
        let x = phase_dat();
        // Stable32 1.60, allantools tests/phasedat: phase_dat_htotdev_octave_
        // nobias.txt (no bias correction, from the 1000 frequency values)
        // and phase_dat_htotdev_octave.txt (bias-corrected for AF ≥ 2):
        // AF, #, Hadamard Sig without and with correction.
        let table = [
            (1, 998, 2.9439e-01, 2.9439e-01),
            (2, 995, 2.0247e-01, 2.0297e-01),
            (4, 989, 1.4216e-01, 1.4252e-01),
            (8, 977, 1.0795e-01, 1.0822e-01),
            (16, 953, 6.5102e-02, 6.5265e-02),
            (32, 905, 4.4532e-02, 4.4644e-02),
            (64, 809, 3.3492e-02, 3.3576e-02),
            (128, 617, 2.8790e-02, 2.8790e-02),
            (256, 233, 1.4773e-02, 1.4773e-02),
        ];
        for (m, n, plain, corrected) in table {
            let e = htotdev(&x, m, 1.0).unwrap();
            assert_eq!(e.n, n, "m={m}");
            assert!(matches_printed(e.dev, plain, 5), "m={m}: {} vs {plain}", e.dev);
            // The corrected table divides by the factor of the noise type
            // Stable32 identified (Alpha column): 0.995 for white FM
            // (alpha 0) at AF 2 … 64; none for alpha 1 (AF 128, 256),
            // which has no HTOT factor, nor at AF 1 (OHDEV).
            let c = if (2..=64).contains(&m) {
                e.dev / HTOTVAR_BIAS.sqrt()
            } else {
                e.dev
            };
            assert!(matches_printed(c, corrected, 5), "m={m}: {c} vs {corrected}");
        }
        // SP 1065 Table 31 (bias-corrected for m ≥ 2, τ = 1, 10, 100):
        // 0.2943883, 0.09614787, 0.03058103.
        assert!(matches_printed(htotdev(&x, 1, 1.0).unwrap().dev, 0.2943883, 7));
        let c100 = htotdev(&x, 100, 1.0).unwrap().dev / HTOTVAR_BIAS.sqrt();
        assert!(matches_printed(c100, 0.03058103, 7), "{c100}");
        // At τ = 10 the corrected value, 0.0961478750096, is a rounding tie
        // of the 7th digit (1e-10 relative above 0.096147875): SP 1065 prints
        // it rounded down, as a computation with single-precision rates
        // gives 0.0961478746. Check that it is that tie.
        let c10 = htotdev(&x, 10, 1.0).unwrap().dev / HTOTVAR_BIAS.sqrt();
        assert!(rel(c10, 0.096147875) < 2e-10, "{c10}");
    }

    #[test]
    fn depends_on_the_rates_only() {
        // Half the phase at half the sampling interval: the same rates,
        // hence the same HTOT (PHASE.DAT is the integral of the frequency
        // set that Stable32 read for the table above).
        let x = integrate(&nbs14_1000_freq());
        let half: Vec<f64> = x.iter().map(|v| v * 0.5).collect();
        for m in [1, 2, 7, 50] {
            let a = htotdev(&x, m, 1.0).unwrap();
            let b = htotdev(&half, m, 0.5).unwrap();
            assert!(rel(a.dev, b.dev) < 1e-13, "m={m}");
            assert_eq!(a.n, b.n);
        }
    }

    #[test]
    fn folded_sum_equals_direct_definition() {
        check_folded_against_direct(
            (htotdev, htotvar_direct),
            [(41, 1), (62, 2), (98, 3)],
            |len| 2..=(len - 1) / 3,
            &[2, 3, 5, 8, 33, 150, 233],
            0.25,
        );
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]

        /// The folded, blocked sum equals SP 1065 eq. 29 built out in full
        /// on the rate values, on random lengths (one or several blocks of
        /// windows), factors m ≥ 2, offsets and sampling intervals.
        #[test]
        fn folded_sum_equals_direct_on_random_lengths(
            len in 7usize..420,
            pick in 0.0f64..1.0,
            seed in proptest::prelude::any::<u64>(),
            offset in -1e3f64..1e3,
            tau0 in 1e-3f64..10.0,
        ) {
            let x: Vec<f64> = walk(len, seed).iter().map(|v| v + offset).collect();
            let m = 2 + (((len - 1) / 3 - 2) as f64 * pick) as usize;
            // The definition as written rounds at the scale of the data:
            // it reads the same points less the first, which the statistic
            // ignores (as MTOTDEV's test explains).
            let shifted: Vec<f64> = x.iter().map(|v| v - x[0]).collect();
            let want = htotvar_direct(&shifted, m, tau0).sqrt();
            let got = htotdev(&x, m, tau0).unwrap();
            proptest::prop_assert!(rel(got.dev, want) < 1e-11, "len={} m={}: {} vs {}", len, m, got.dev, want);
            proptest::prop_assert_eq!(got.n, len - 3 * m);
        }
    }

    #[test]
    fn ignores_frequency_drift() {
        // A quadratic phase (linear frequency drift) is removed by every
        // window's trend removal, and by the third difference at m = 1.
        let x = walk(300, 9);
        let drift: Vec<f64> = x
            .iter()
            .enumerate()
            .map(|(i, v)| {
                let t = i as f64;
                v + 5.0 + 0.3 * t + 1e-3 * t * t
            })
            .collect();
        check_same_deviation(htotdev, &x, &drift, &[1, 2, 3, 16, 50, 99]);
    }

    #[test]
    fn unsupported_inputs_give_none() {
        let x = walk(31, 4);
        assert!(htotdev(&x, 0, 1.0).is_none());
        assert!(htotdev(&x, 11, 1.0).is_none());
        assert_eq!(htotdev(&x, 10, 1.0).map(|e| e.n), Some(1));
        assert!(htotdev(&x, usize::MAX / 3 + 1, 1.0).is_none());
        assert!(htotdev(&[], 1, 1.0).is_none());
        assert!(htotdev(&x[..3], 1, 1.0).is_none());
        assert_eq!(htotdev(&x[..4], 1, 1.0).map(|e| e.n), Some(1));
        for tau0 in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e-320] {
            for m in [1, 2] {
                assert!(htotdev(&x, m, tau0).is_none(), "tau0={tau0} m={m}");
            }
        }
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let mut y = x.clone();
            y[12] = bad;
            for m in [1, 2] {
                assert!(htotdev(&y, m, 1.0).is_none(), "{bad} m={m}");
            }
        }
    }
}
