//! Total deviation (NIST SP 1065 §5.2.11, eq. 25).
//!
//! The phase series of N points is extended by reflection at both ends,
//! x*[1−j] = 2x[1] − x[1+j] and x*[N+j] = 2x[N] − x[N−j] for j = 1…N−2, and
//! Totvar(τ) = Σ_{i=2}^{N−1} (x*[i−m] − 2x*[i] + x*[i+m])² / (2τ²(N−2)).
//! This is the doubly reflected form that Stable32 and AllanTools reproduce
//! (Riley's web paper prints different values; they are not used). The
//! extension is indexed, never materialised.

use super::Estimate;
use crate::lanes::{LANES, join};
use crate::phase::PhaseSeries;

/// Total deviation at averaging factor m (1 ≤ m ≤ N − 1).
pub fn totdev(series: &PhaseSeries, m: usize) -> Option<Estimate> {
    let x = series.points();
    let n = x.len();
    if m == 0 || n < 3 || m > n - 1 {
        return None;
    }
    let last = n - 1;
    // 0-based reflection: index k may run from −(N−2) to 2N−3.
    let at = |k: isize| -> f64 {
        if k < 0 {
            2.0 * x[0] - x[k.unsigned_abs()]
        } else if (k as usize) > last {
            2.0 * x[last] - x[2 * last - k as usize]
        } else {
            x[k as usize]
        }
    };
    let mi = m as isize;
    let term = |i: usize| {
        let i = i as isize;
        let v = at(i - mi) - 2.0 * at(i) + at(i + mi);
        v * v
    };
    // Terms i = 1 … N − 2. Those with m ≤ i ≤ N − 1 − m read the series
    // itself; the rest reach into a reflection.
    let first_direct = m.min(last);
    let end_direct = if 2 * m <= last { last - m + 1 } else { first_direct };
    let left: f64 = (1..first_direct).map(term).sum();
    let middle = direct_sum(x, m, first_direct, end_direct);
    let right: f64 = (end_direct..last).map(term).sum();
    let sum = left + middle + right;
    let terms = n - 2;
    let tau = m as f64 * series.tau0();
    Some(Estimate {
        dev: (sum / (2.0 * tau * tau * terms as f64)).sqrt(),
        n: terms,
    })
}

/// Σ (x[i − m] − 2x[i] + x[i + m])² over i in `from..to` (all within the
/// series), term k of the run in accumulator k mod [`LANES`], joined in a
/// fixed order: the same bits on every machine.
fn direct_sum(x: &[f64], m: usize, from: usize, to: usize) -> f64 {
    if from >= to {
        return 0.0;
    }
    let (before, at, after) = (&x[from - m..to - m], &x[from..to], &x[from + m..to + m]);
    let (b, b_tail) = before.as_chunks::<LANES>();
    let (a, a_tail) = at.as_chunks::<LANES>();
    let (c, c_tail) = after.as_chunks::<LANES>();
    let mut lanes = [0.0f64; LANES];
    for ((b, a), c) in b.iter().zip(a).zip(c) {
        for l in 0..LANES {
            let v = b[l] - 2.0 * a[l] + c[l];
            lanes[l] += v * v;
        }
    }
    let tail: f64 = b_tail
        .iter()
        .zip(a_tail)
        .zip(c_tail)
        .map(|((b, a), c)| {
            let v = b - 2.0 * a + c;
            v * v
        })
        .sum();
    join(lanes, tail)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::DataType;
    use proptest::prelude::*;

    /// SP 1065 eq. 25 term by term over the reflected series, in one
    /// serial sum: the reference for the split and the lanes.
    fn totvar_direct(x: &[f64], m: usize) -> f64 {
        let n = x.len() as isize;
        let last = n - 1;
        let at = |k: isize| -> f64 {
            if k < 0 {
                2.0 * x[0] - x[(-k) as usize]
            } else if k > last {
                2.0 * x[last as usize] - x[(2 * last - k) as usize]
            } else {
                x[k as usize]
            }
        };
        let m = m as isize;
        (1..last)
            .map(|i| (at(i - m) - 2.0 * at(i) + at(i + m)).powi(2))
            .sum()
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// Every m of random walks of random lengths (so every split of
        /// the terms between the reflections and the series, and every
        /// tail of the lanes): the same sum to rounding.
        #[test]
        fn lanes_equal_the_term_by_term_sum(seed in any::<u64>(), len in 3usize..200) {
            let x = crate::work::random_walk(len, seed);
            let series = PhaseSeries::new(&x, DataType::Phase, 1.0).expect("finite");
            for m in 1..len {
                let got = totdev(&series, m).expect("a valid factor");
                let want = totvar_direct(&x, m);
                let want_dev = (want / (2.0 * (m * m) as f64 * (len - 2) as f64)).sqrt();
                prop_assert!((got.dev - want_dev).abs() <= 1e-13 * want_dev, "m={}: {} vs {}", m, got.dev, want_dev);
            }
        }
    }
}
