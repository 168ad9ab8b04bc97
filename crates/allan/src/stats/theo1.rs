//! Thêo1, NIST SP 1065 eq. 30 (Howe & Peppler 2003; Howe & Tasset 2004).
//!
//! # Definition
//!
//! The Allan variance needs 2m + 1 points for one term at τ = mτ0; Thêo1
//! ("theoretical variance #1") reaches τ = 0.75·(N−1)·τ0 by averaging, for
//! every span of m + 1 points (m even), the squared phase "bends" of all
//! nested sub-spans symmetric about its centre, each weighted by the
//! inverse of its half-width:
//!
//! Theo1(m, τ0, N) = 1/(0.75·(N−m)·(mτ0)²) Σ_{i=1}^{N−m} Σ_{δ=0}^{m/2−1}
//!   [(x_i − x_{i−δ+m/2}) + (x_{i+m} − x_{i+δ+m/2})]² / (m/2 − δ),
//!
//! for even m, 2 ≤ m ≤ N − 1 (SP 1065 recommends 10 ≤ m; Stable32 starts
//! there; AllanTools computes from m = 2). For white FM its expectation is
//! the Allan variance at **τ = 0.75·m·τ0** ([`theo1_tau`]), which is the τ
//! to plot it at; it is not the τ = m·τ0 of the other statistics.
//!
//! # Bias
//!
//! The values returned carry no bias correction, as AllanTools 2024.6
//! prints them and as Stable32 1.60 prints them with Alpha = 0 (white FM,
//! where Thêo1 is unbiased against the Allan variance). For other noise
//! types Stable32 divides by a noise-dependent factor (Howe & Tasset 2004),
//! which is left to the caller.
//!
//! # Cost
//!
//! The double sum has (N − m)·m/2 terms, the `n` reported: O(N·m) per τ,
//! at most N²/8 near m = N/2, with no scratch. Thêo1 is meant for short
//! series, where it reaches the longest τ. The sum runs over blocks of
//! consecutive i, with δ innermost over a block, so all four phase streams
//! are read forward from cache.
//!
//! # Why not below O(N·m) per τ
//!
//! Each span i weights its m/2 nested bends by 1/(m/2 − δ). Expanded, the
//! double sum holds Σ_L (1/L)·Σ_i x_i·x_{i+L} for every lag L = 1 … m/2
//! and the products x_{c−δ}·x_{c+δ} about every centre c: the lagged
//! products of the phase at m/2 lags, with harmonic weights. Those weights
//! are no polynomial in the lag, so prefix sums cannot carry them from one
//! span to the next; a span's bends share no product with the next span's
//! (their centre moves by one sample). The lagged products could come from
//! an FFT correlation in O(N log N), but that squares the phase before it
//! differences it: the result becomes a difference of terms larger than it
//! by Σx²/Σbend², about N/m for white FM and without bound under a phase
//! offset, and a double cannot keep the eleven digits the tests hold
//! against the straightforward sum (nine against AllanTools). Forming each bend before
//! squaring it keeps the digits and costs O(m) per span.

use super::Estimate;
use super::mtotdev::{Sum, valid_tau0};

/// Consecutive i per block of the double sum: four streams of this many
/// values stay in the first-level cache.
const BLOCK: usize = 512;

/// The τ at which Thêo1 with averaging factor m estimates the Allan
/// deviation: 0.75·m·τ0 (SP 1065 eq. 30; Stable32's "Thêo1 Tau" column).
pub fn theo1_tau(m: usize, tau0: f64) -> f64 {
    0.75 * m as f64 * tau0
}

/// Thêo1 deviation with even averaging factor m (NIST SP 1065 eq. 30), an
/// estimate of the Allan deviation at τ = [`theo1_tau`]`(m, τ0)` = 0.75·m·τ0,
/// without bias correction (Stable32 1.60 with Alpha = 0, AllanTools
/// 2024.6).
///
/// `n` is the number of terms of the double sum, (N − m)·m/2, as AllanTools
/// and Stable32 ("Thêo1 #") report it. Returns `None` when m is zero or odd,
/// m ≥ N, τ0 is not a positive finite number or a phase point is not
/// finite.
///
/// Cost O((N − m)·m/2) time, no scratch (the cost per term, with AVX-512
/// and with AVX2, is measured by `allan_per_tau`, bench/README.md).
pub fn theo1(phase: &[f64], m: usize, tau0: f64) -> Option<Estimate> {
    theo1_with_progress(phase, m, tau0, &|_| {})
}

/// [`theo1`], reporting its work as it goes: `progress` receives the terms
/// of the double sum done since its last call, one block of spans at a
/// time, so the calls add up to [`crate::work::operations`].
pub fn theo1_with_progress(phase: &[f64], m: usize, tau0: f64, progress: &dyn Fn(u64)) -> Option<Estimate> {
    let n = phase.len();
    if m == 0 || !m.is_multiple_of(2) || m >= n || !valid_tau0(tau0) || !phase.iter().all(|v| v.is_finite()) {
        return None;
    }
    let h = m / 2;
    let outer = n - m;
    let terms = outer.checked_mul(h)?;
    let mut sum = Sum::default();
    for start in (0..outer).step_by(BLOCK) {
        let len = BLOCK.min(outer - start);
        // x_i and x_{i+m}, the ends of each span.
        let first = &phase[start..start + len];
        let last = &phase[start + m..start + m + len];
        for delta in 0..h {
            // x_{i+m/2−δ} and x_{i+m/2+δ}, the ends of the nested sub-span.
            let inner_lo = &phase[start + h - delta..start + h - delta + len];
            let inner_hi = &phase[start + h + delta..start + h + delta + len];
            sum.add(bend_squares(first, inner_lo, last, inner_hi) / (h - delta) as f64);
        }
        progress((len * h) as u64);
    }
    let tau = m as f64 * tau0;
    let var = sum.value() / (0.75 * outer as f64 * tau * tau);
    let dev = var.sqrt();
    dev.is_finite().then_some(Estimate { dev, n: terms })
}

/// Independent sums of [`bend_squares`]: each addition waits on the one
/// before it in its lane, and eight lanes (two AVX2 registers) keep the
/// adders busy through that latency.
const LANES: usize = 8;

/// Σ_k [(a_k − c_k) + (b_k − d_k)]² over equally long slices, in [`LANES`]
/// independent lanes so the loop vectorises. Differences of nearby phase
/// points are taken first, which keeps digits when the phase carries a
/// large offset.
#[inline]
fn bend_squares(a: &[f64], c: &[f64], b: &[f64], d: &[f64]) -> f64 {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx512f") {
        // SAFETY: as below, for AVX-512F, just detected.
        return unsafe { bend_squares_avx512(a, c, b, d) };
    }
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the one requirement for calling a function compiled with
        // `target_feature(enable = "avx2")` is a CPU that has AVX2, which
        // was just detected.
        return unsafe { bend_squares_avx2(a, c, b, d) };
    }
    bend_squares_portable(a, c, b, d)
}

/// [`bend_squares_portable`] compiled for AVX2: the eight lanes in two
/// registers, the same operations in the same order, the same bits.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn bend_squares_avx2(a: &[f64], c: &[f64], b: &[f64], d: &[f64]) -> f64 {
    bend_squares_portable(a, c, b, d)
}

/// [`bend_squares_portable`] compiled for AVX-512: the eight lanes in one
/// register, the same bits.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn bend_squares_avx512(a: &[f64], c: &[f64], b: &[f64], d: &[f64]) -> f64 {
    bend_squares_portable(a, c, b, d)
}

#[inline(always)]
fn bend_squares_portable(a: &[f64], c: &[f64], b: &[f64], d: &[f64]) -> f64 {
    let (a8, a1) = a.as_chunks::<LANES>();
    let (c8, c1) = c.as_chunks::<LANES>();
    let (b8, b1) = b.as_chunks::<LANES>();
    let (d8, d1) = d.as_chunks::<LANES>();
    let mut lanes = [0.0f64; LANES];
    for (((a, c), b), d) in a8.iter().zip(c8).zip(b8).zip(d8) {
        for l in 0..LANES {
            let v = (a[l] - c[l]) + (b[l] - d[l]);
            lanes[l] += v * v;
        }
    }
    let mut tail = 0.0;
    for (((a, c), b), d) in a1.iter().zip(c1).zip(b1).zip(d1) {
        let v = (a - c) + (b - d);
        tail += v * v;
    }
    lanes.iter().sum::<f64>() + tail
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::mtotdev::tests::{
        check_phase_dat, check_same_deviation, matches_printed, nbs14_10_phase, phase_dat, rel, walk,
        with_line,
    };

    /// SP 1065 eq. 30 term by term, as written. The reference for the
    /// blocked computation.
    fn theo1_direct(x: &[f64], m: usize, tau0: f64) -> f64 {
        let n = x.len();
        let h = m / 2;
        let mut total = 0.0;
        for i in 0..n - m {
            for d in 0..h {
                let v = x[i] - x[i + h - d] + x[i + m] - x[i + h + d];
                total += v * v / (h - d) as f64;
            }
        }
        let tau = m as f64 * tau0;
        (total / (0.75 * (n - m) as f64 * tau * tau)).sqrt()
    }

    /// AllanTools 2024.6 on PHASE.DAT (1000-point set, τ0 = 1), from
    ///
    /// ```text
    /// import numpy as np, allantools as at     # allantools==2024.6
    /// n = 1234567890; y = []
    /// for i in range(1000):
    ///     y.append(n / 2147483647.0); n = (16807 * n) % 2147483647
    /// y = np.array(y); x = np.concatenate(([0.0], np.cumsum(y - y.mean())))
    /// ms = np.array([2, 4, 8, 10, 16, 20, 32, 40, 64, 100, 128, 202, 256,
    ///                400, 512, 998, 1000.])
    /// t, d, e, ns = at.theo1(x, rate=1.0, data_type='phase', taus=ms)
    /// print([(int(a), repr(float(b)), int(c)) for a, b, c in zip(t, d, ns)])
    /// ```
    ///
    /// (`t` is m·τ0 there; the Thêo1 τ is 0.75 of it.)
    const ALLANTOOLS_PHASE_DAT: [(usize, f64, usize); 17] = [
        (2, 0.23860632931225687, 999),
        (4, 0.16549589582333266, 1994),
        (8, 0.11999093365421167, 3972),
        (10, 0.10757398887390159, 4955),
        (16, 0.08504033366063067, 7880),
        (20, 0.07276234458854028, 9810),
        (32, 0.0542582514848987, 15504),
        (40, 0.04865168747225535, 19220),
        (64, 0.039798777244554946, 29984),
        (100, 0.03178931260064373, 45050),
        (128, 0.02996311607682276, 55872),
        (202, 0.02411967911935575, 80699),
        (256, 0.020764288156895124, 95360),
        (400, 0.014320582165601293, 120200),
        (512, 0.012455746138602473, 125184),
        (998, 0.005023363466312229, 1497),
        (1000, 0.005052399627392014, 500),
    ];

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(48))]

        /// Whatever the CPU, the same bits: the dispatched sum and each
        /// build this CPU can run (AVX2, AVX-512) against the portable one.
        #[test]
        fn every_bend_sum_gives_the_same_bits(len in 1usize..600, seed in proptest::prelude::any::<u64>()) {
            let x = walk(4 * len, seed);
            let (a, c, b, d) = (&x[..len], &x[len..2 * len], &x[2 * len..3 * len], &x[3 * len..]);
            let portable = bend_squares_portable(a, c, b, d).to_bits();
            proptest::prop_assert_eq!(bend_squares(a, c, b, d).to_bits(), portable);
            #[cfg(target_arch = "x86_64")]
            {
                if std::arch::is_x86_feature_detected!("avx2") {
                    // SAFETY: AVX2 was just detected.
                    let avx2 = unsafe { bend_squares_avx2(a, c, b, d) };
                    proptest::prop_assert_eq!(avx2.to_bits(), portable);
                }
                if std::arch::is_x86_feature_detected!("avx512f") {
                    // SAFETY: AVX-512F was just detected.
                    let avx512 = unsafe { bend_squares_avx512(a, c, b, d) };
                    proptest::prop_assert_eq!(avx512.to_bits(), portable);
                }
            }
        }
    }

    #[test]
    fn phase_dat_against_allantools() {
        check_phase_dat(theo1, &ALLANTOOLS_PHASE_DAT);
    }

    #[test]
    fn phase_dat_against_stable32() {
        let x = phase_dat();
        // Stable32 1.60, allantools tests/phasedat: phase_dat_theo1_alpha0_
        // decade.txt plus rows of phase_dat_theo1_alpha0.txt (AF, Thêo1
        // Tau, Thêo1 #, Thêo1; Alpha = 0, 5 significant digits).
        let table = [
            (10, 7.5, 4955, 1.0757e-01),
            (12, 9.0, 5934, 9.8141e-02),
            (20, 15.0, 9810, 7.2762e-02),
            (40, 30.0, 19220, 4.8652e-02),
            (68, 51.0, 31722, 3.8744e-02),
            (100, 75.0, 45050, 3.1789e-02),
            (202, 151.5, 80699, 2.4120e-02),
            (400, 300.0, 120200, 1.4321e-02),
            (942, 706.5, 27789, 7.7650e-03),
            (984, 738.0, 8364, 5.5184e-03),
            (998, 748.5, 1497, 5.0234e-03),
        ];
        for (m, tau, n, dev) in table {
            let e = theo1(&x, m, 1.0).unwrap();
            assert_eq!(e.n, n, "m={m}");
            assert_eq!(theo1_tau(m, 1.0), tau);
            assert!(matches_printed(e.dev, dev, 5), "m={m}: {} vs {dev}", e.dev);
        }
        // reference_values.json "stable32_v1.60_no_bias_correction.
        // theo1_AF_10_100_1000": 0.10757, 0.031789, 0.0050524.
        for (m, dev) in [(10, 0.10757), (100, 0.031789), (1000, 0.0050524)] {
            let e = theo1(&x, m, 1.0).unwrap();
            assert!(matches_printed(e.dev, dev, 5), "m={m}: {} vs {dev}", e.dev);
        }
    }

    #[test]
    fn blocked_sum_equals_direct_definition() {
        // Lengths around the block size exercise partial blocks and tails.
        for (len, seed) in [(11, 1), (60, 2), (BLOCK + 3, 3), (2 * BLOCK + 41, 4)] {
            let x = walk(len, seed);
            for m in (2..len).step_by(2) {
                if len > 100 && m % 38 != 2 && m + 2 < len {
                    continue;
                }
                let want = theo1_direct(&x, m, 0.1);
                let got = theo1(&x, m, 0.1).unwrap().dev;
                assert!(rel(got, want) < 1e-11, "len={len} m={m}: {got} vs {want}");
            }
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]

        /// The blocked sum equals SP 1065 eq. 30 term by term on random
        /// lengths (partial blocks, several blocks), even factors, offsets
        /// and sampling intervals.
        #[test]
        fn blocked_sum_equals_direct_on_random_lengths(
            len in 3usize..(2 * BLOCK + 200),
            pick in 0.0f64..1.0,
            seed in proptest::prelude::any::<u64>(),
            offset in -1e3f64..1e3,
            tau0 in 1e-3f64..10.0,
        ) {
            let x: Vec<f64> = walk(len, seed).iter().map(|v| v + offset).collect();
            let m = 2 * (1 + (((len - 1) / 2 - 1) as f64 * pick) as usize);
            // The definition as written rounds at the scale of the data:
            // it reads the same points less the first, which the statistic
            // ignores (as MTOTDEV's test explains).
            let shifted: Vec<f64> = x.iter().map(|v| v - x[0]).collect();
            let want = theo1_direct(&shifted, m, tau0);
            let got = theo1(&x, m, tau0).unwrap();
            proptest::prop_assert!(rel(got.dev, want) < 1e-11, "len={} m={}: {} vs {}", len, m, got.dev, want);
            proptest::prop_assert_eq!(got.n, (len - m) * (m / 2));
        }
    }

    #[test]
    fn ignores_phase_and_frequency_offset() {
        let x = walk(200, 8);
        check_same_deviation(theo1, &x, &with_line(&x, -40.0, 0.7), &[2, 10, 64, 150, 198]);
    }

    #[test]
    fn ten_point_set_term_count() {
        // N = 10 phase points: m = 2 … 8 even, (N − m)·m/2 terms.
        let x = nbs14_10_phase();
        for m in [2, 4, 6, 8] {
            assert_eq!(theo1(&x, m, 1.0).map(|e| e.n), Some((10 - m) * m / 2));
        }
        assert_eq!(theo1(&x, 9, 1.0), None);
        assert_eq!(theo1(&x, 10, 1.0), None);
    }

    #[test]
    fn unsupported_inputs_give_none() {
        let x = walk(20, 3);
        for m in [0, 1, 3, 19, 20, 21, usize::MAX, usize::MAX - 1] {
            assert!(theo1(&x, m, 1.0).is_none(), "m={m}");
        }
        assert!(theo1(&[], 2, 1.0).is_none());
        assert!(theo1(&x[..2], 2, 1.0).is_none());
        assert_eq!(theo1(&x[..3], 2, 1.0).map(|e| e.n), Some(1));
        for tau0 in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(theo1(&x, 4, tau0).is_none(), "tau0={tau0}");
        }
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let mut y = x.clone();
            y[0] = bad;
            assert!(theo1(&y, 4, 1.0).is_none(), "{bad}");
        }
        assert!((theo1_tau(10, 0.01) - 0.075).abs() < 1e-16);
    }
}
