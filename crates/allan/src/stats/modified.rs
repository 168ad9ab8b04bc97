//! Modified Allan deviation and time deviation (NIST SP 1065 §5.2.5–5.2.6).
//!
//! Mod σ²(τ) = Σ_j [Σ_{i=j}^{j+m−1} (x[i+2m] − 2x[i+m] + x[i])]² / (2 m² τ² n),
//! n = N − 3m + 1 (SP 1065 eq. 15). The inner sums over a sliding window of m
//! second differences are kept as a running sum, so each τ costs O(N) rather
//! than O(N·m); the running sum is recomputed exactly at intervals of at least
//! m steps, which bounds rounding drift while keeping the cost O(N).

use super::Estimate;
use crate::phase::PhaseSeries;

/// Steps between exact recomputations of the running window sum.
pub(super) const RESYNC: usize = 1024;

/// Resync intervals whose running sums run side by side.
const LANES: usize = 4;

/// Modified Allan deviation at averaging factor m.
pub fn mdev(series: &PhaseSeries, m: usize) -> Option<Estimate> {
    let x = series.points();
    if m == 0 || x.len() < 3 * m {
        return None;
    }
    let (sum, n) = match series.gap_index() {
        // A window of one second difference: the sum is OADEV's at m = 1,
        // the same N − 2 terms, and its blocked sum reads the series at
        // about a memory pass where the window scan took two.
        None if m == 1 => {
            super::differences::sum_squared_overlapped_many(x, &[1], super::differences::Order::Second)[0]
        }
        None => (super::mdev_scan::gap_free_squares(x, m), x.len() - 3 * m + 1),
        // A second difference with a missing phase point counts as zero in
        // the running sum; every window that holds it is skipped anyway.
        Some(g) => window_squares(
            x,
            m,
            |j| !g.span_has_gap(j, j + 3 * m - 1),
            |v: f64| if v.is_nan() { 0.0 } else { v },
        ),
    };
    (n > 0).then(|| {
        let tau = m as f64 * series.tau0();
        let mf = m as f64;
        Estimate {
            dev: (sum / (2.0 * mf * mf * tau * tau * n as f64)).sqrt(),
            n,
        }
    })
}

/// Σ over the usable windows j of (Σ_{i=j}^{j+m−1} second difference)², and
/// their count. The window sum runs, recomputed exactly every
/// max(RESYNC, m) windows; the windows are taken a resync interval at a
/// time, so no step pays for a division to find the interval's start (the
/// sums and their order are those of one loop with `j % interval == 0`).
/// `clean` maps a NaN difference to what the running sum takes. Data
/// without gaps takes [`super::mdev_scan`] instead, at about one memory pass
/// (and at m = 1 OADEV's blocked sum).
#[inline(always)]
fn window_squares(
    x: &[f64],
    m: usize,
    usable: impl Fn(usize) -> bool,
    clean: impl Fn(f64) -> f64,
) -> (f64, usize) {
    let terms = x.len() - 3 * m + 1;
    let d = |i: usize| clean(super::differences::second(x[i], x[i + m], x[i + 2 * m]));
    let resync = RESYNC.max(m);
    let mut sum = 0.0;
    let mut n = 0usize;
    let mut start = 0;
    // The interval's second differences, each formed once (the running
    // sum takes every one twice, m windows apart) in a loop that
    // vectorises; the running sum then only reads them.
    let mut diffs: Vec<f64> = Vec::with_capacity(LANES * resync + m);
    // Whole groups of LANES intervals run side by side: each interval's
    // running sum is a chain of dependent additions, and interleaving
    // independent chains lets the core overlap them. The sums within each
    // interval are those of the one-interval loop below; only the order in
    // which the intervals' squares are added together differs.
    while start + LANES * resync <= terms {
        diffs.clear();
        diffs.extend((start..start + LANES * resync + m - 1).map(d));
        let mut s = [0.0; LANES];
        let mut sums = [0.0; LANES];
        for (l, s) in s.iter_mut().enumerate() {
            *s = diffs[l * resync..l * resync + m].iter().sum::<f64>();
            if usable(start + l * resync) {
                sums[l] += *s * *s;
                n += 1;
            }
        }
        for k in 1..resync {
            for l in 0..LANES {
                let at = l * resync + k;
                s[l] += diffs[at + m - 1] - diffs[at - 1];
                if usable(start + at) {
                    sums[l] += s[l] * s[l];
                    n += 1;
                }
            }
        }
        sum += (sums[0] + sums[1]) + (sums[2] + sums[3]);
        start += LANES * resync;
    }
    while start < terms {
        let end = (start + resync).min(terms);
        diffs.clear();
        diffs.extend((start..end + m - 1).map(d));
        let mut s = diffs[..m].iter().sum::<f64>();
        if usable(start) {
            sum += s * s;
            n += 1;
        }
        for (k, (&enter, &leave)) in diffs[m..].iter().zip(&diffs[..end - start - 1]).enumerate() {
            s += enter - leave;
            if usable(start + 1 + k) {
                sum += s * s;
                n += 1;
            }
        }
        start = end;
    }
    (sum, n)
}

/// Time deviation, τ·MDEV/√3 (SP 1065 eq. 16), in seconds of phase (or the
/// integrated unit of the rate data: rad for a gyro, m/s for an accelerometer).
pub fn tdev(series: &PhaseSeries, m: usize) -> Option<Estimate> {
    mdev(series, m).map(|e| Estimate {
        dev: e.dev * m as f64 * series.tau0() / 3f64.sqrt(),
        n: e.n,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::DataType;
    use proptest::prelude::*;

    /// SP 1065 eq. 15 as written: every window's m second differences
    /// summed afresh, windows holding a gap skipped. O(N·m).
    fn mdev_direct(x: &[f64], m: usize, tau0: f64) -> Option<(f64, usize)> {
        let mut sum = 0.0;
        let mut n = 0;
        for j in 0..=x.len().checked_sub(3 * m)? {
            if x[j..j + 3 * m].iter().any(|v| v.is_nan()) {
                continue;
            }
            let s: f64 = (j..j + m).map(|i| x[i + 2 * m] - 2.0 * x[i + m] + x[i]).sum();
            sum += s * s;
            n += 1;
        }
        let tau = m as f64 * tau0;
        (n > 0).then(|| ((sum / (2.0 * (m * m) as f64 * tau * tau * n as f64)).sqrt(), n))
    }

    /// At m = 1 MVAR is AVAR (SP 1065): MDEV takes OADEV's blocked sum of
    /// the same N − 2 terms, bit for bit, and agrees with the window scan,
    /// which m = 1 no longer takes, and the definition to rounding.
    #[test]
    fn at_one_the_modified_deviation_is_the_overlapped_one() {
        use super::super::differences::{Order, sum_squared_overlapped_many};
        for len in [3usize, 4, 17, 2048, 2051, 100_003] {
            let x = crate::work::random_walk(len, len as u64);
            let series = PhaseSeries::new(&x, DataType::Phase, 10.0).unwrap();
            let modified = mdev(&series, 1).unwrap();
            let (blocked, n) = sum_squared_overlapped_many(&x, &[1], Order::Second)[0];
            assert_eq!((modified.n, n), (len - 2, len - 2));
            let from_blocked = (blocked / (2.0 * 0.1 * 0.1 * n as f64)).sqrt();
            assert_eq!(modified.dev.to_bits(), from_blocked.to_bits(), "len {len}");
            let overlapped = super::super::oadev(&series, 1).unwrap();
            assert!(
                (modified.dev / overlapped.dev - 1.0).abs() <= 4.0 * f64::EPSILON,
                "len {len}"
            );
            let scanned = super::super::mdev_scan::gap_free_squares(&x, 1);
            let from_scan = (scanned / (2.0 * 0.01 * n as f64)).sqrt();
            let (direct, _) = mdev_direct(&x, 1, 0.1).unwrap();
            assert!((from_scan / modified.dev - 1.0).abs() < 1e-12, "len {len}");
            assert!((direct / modified.dev - 1.0).abs() < 1e-12, "len {len}");
        }
    }

    /// Small noise on a large offset, as the phase of a long recording
    /// with a bias has. MDEV ignores the offset, and the scan rounds at the
    /// scale of the differences: it agrees with the definition on the same
    /// doubles with the offset taken off (exactly, as each point lies within
    /// a factor two of it). Formed from the phase as x₃ − 3x₂ + 3x₁ − x₀,
    /// whose 3x rounds at the offset's scale, the scan's windows drifted
    /// between resyncs, in every form of the scan: at m = 2, 1.2e-7
    /// relative at an offset of 1e2 under noise of 1e-9, 1.1e-8 at 1e4
    /// under 1e-6, and 3.3 times MDEV at 1e6 under 1e-9.
    #[test]
    fn a_large_offset_costs_no_digits() {
        let noise: Vec<f64> = crate::work::uniform(0x2545_f491_4f6c_dd1d)
            .take(30_000)
            .map(|u| u - 0.5)
            .collect();
        for (offset, scale) in [(0.0, 1.0), (1e2, 1e-9), (1e6, 1e-9), (1e4, 1e-6)] {
            let x: Vec<f64> = noise.iter().map(|v| offset + scale * v).collect();
            let shifted: Vec<f64> = x.iter().map(|v| v - offset).collect();
            let series = PhaseSeries::new(&x, DataType::Phase, 1.0).unwrap();
            // Portable and register scans, with all four streams in L1 and
            // with the oldest two from L2 (from m of about 1024).
            for m in [2, 5, 16, 100, 1600, 2048] {
                let got = mdev(&series, m).unwrap().dev;
                let (want, _) = mdev_direct(&shifted, m, 1.0).unwrap();
                assert!(
                    (got / want - 1.0).abs() < 1e-9,
                    "offset {offset} m {m}: {got} vs {want}"
                );
            }
        }
    }

    #[test]
    fn interleaved_intervals_equal_the_direct_definition_on_long_series() {
        // Long enough for several groups of interleaved resync intervals
        // and a remainder, with and without gaps.
        let mut acc = 0.0;
        let mut x: Vec<f64> = (0..23_457)
            .map(|i| {
                acc += ((i * 7919) % 1009) as f64 / 1009.0 - 0.5;
                acc
            })
            .collect();
        for gapped in [false, true] {
            if gapped {
                for i in [5_000, 5_001, 12_345, 20_000] {
                    x[i] = f64::NAN;
                }
            }
            let series = PhaseSeries::new(&x, DataType::Phase, 1.0).unwrap();
            // m = 3000 with gaps: every window holds one, and both say so.
            for m in [1, 2, 7, 64, 1000, 2048, 3000] {
                let (got, want) = (mdev(&series, m), mdev_direct(series.points(), m, 1.0));
                if gapped && m == 3000 {
                    assert_eq!((got, want), (None, None));
                    continue;
                }
                let (got, (dev, n)) = (got.unwrap(), want.unwrap());
                assert_eq!(got.n, n, "m={m} gapped={gapped}");
                assert!(
                    ((got.dev - dev) / dev).abs() < 1e-12,
                    "m={m} gapped={gapped}: {} vs {dev}",
                    got.dev
                );
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        #[test]
        fn running_sum_equals_the_direct_definition(
            len in 3usize..3000,
            m_seed in 0usize..1000,
            seed in 0u64..1000,
            gaps in proptest::collection::vec(0.0f64..1.0, 0..6),
        ) {
            let mut x = crate::work::random_walk(len, seed);
            // Gaps inside the series (a NaN at an edge is trimmed).
            for g in gaps {
                let i = 1 + (g * (len.saturating_sub(2)) as f64) as usize;
                if i + 1 < len {
                    x[i] = f64::NAN;
                }
            }
            let m = 1 + m_seed % (len / 3).max(1);
            let series = PhaseSeries::new(&x, DataType::Phase, 2.0).unwrap();
            let got = mdev(&series, m);
            let want = mdev_direct(series.points(), m, series.tau0());
            match (got, want) {
                (Some(g), Some((dev, n))) => {
                    prop_assert_eq!(g.n, n);
                    prop_assert!(((g.dev - dev) / dev).abs() < 1e-12, "m={} {} vs {}", m, g.dev, dev);
                }
                (None, None) => {}
                other => prop_assert!(false, "m={}: {:?}", m, other),
            }
        }
    }
}
