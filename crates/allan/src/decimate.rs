//! Copies of every m-th point, at about the speed of the memory.
//!
//! The non-overlapped sums and the lag-1 ACF read the series decimated by
//! the averaging factor. Read point by point with a stride known only at
//! run time, and with the hardware prefetcher alone, the copy was slower
//! than the memory: HDEV at small m took well over two passes of memory,
//! and the ACF's copy was a third of the lag-1 method's time on an octave
//! grid (`perf record`). Here every line is asked for ahead
//! ([`crate::prefetch`], on x86-64; elsewhere the hint is nothing), and for
//! m ≤ 4 the stride is a constant the compiler turns into whole vectors
//! and shuffles. Only copies: every form gives the same values.

/// Copies `x[0], x[m], …` into `out`, `out.len()` points; m ≥ 1, and
/// `(out.len() − 1)·m` must be within `x` (the callers' bounds: a breach is
/// a fault of this crate, refused before anything is read). Inlined into
/// its callers: called as a function once per 64-point chunk of the
/// non-overlapped sums, HDEV at m = 2 took about a third more memory passes
/// than inlined (`allan_per_tau N passes`).
#[inline(always)]
pub(crate) fn every(x: &[f64], m: usize, out: &mut [f64]) {
    assert!(m >= 1, "a stride of zero");
    if let Some(last) = out.len().checked_sub(1) {
        let within = last.checked_mul(m).is_some_and(|at| at < x.len());
        assert!(
            within,
            "{} points at stride {m} past {} points",
            out.len(),
            x.len()
        );
    }
    match m {
        1 => out.copy_from_slice(&x[..out.len()]),
        2 => groups::<2>(x, out),
        3 => groups::<3>(x, out),
        4 => groups::<4>(x, out),
        _ => groups_any(x, m, out),
    }
}

/// Points copied between one group of requests for lines and the next.
const GROUP: usize = 8;

/// How far ahead of the group being copied its lines are asked for, in
/// points: 16 KiB, or for large m, 64 points of the copy.
fn ahead(m: usize) -> usize {
    (crate::prefetch::DISTANCE / 8).max(m.saturating_mul(64))
}

/// Asks for the lines that the group of [`GROUP`] points from x[at] will
/// read [`ahead`] points later: m lines up to m = 8, and one line a point
/// from there.
#[inline(always)]
fn ask(x: &[f64], m: usize, at: usize) {
    let (lines, step) = (m.min(GROUP), m.max(GROUP));
    // Only hints: an address past the series costs a wasted fetch at most,
    // so the arithmetic wraps rather than checks.
    let from = at.wrapping_add(ahead(m));
    for l in 0..lines {
        crate::prefetch::line(x, from.wrapping_add(l.wrapping_mul(step)));
    }
}

/// [`every`] with the stride a constant.
#[inline(always)]
fn groups<const M: usize>(x: &[f64], out: &mut [f64]) {
    for (g, group) in out.chunks_mut(GROUP).enumerate() {
        let at = g * GROUP * M;
        ask(x, M, at);
        let (whole, rest) = x[at..].as_chunks::<M>();
        let n = group.len().min(whole.len());
        for (slot, chunk) in group[..n].iter_mut().zip(whole) {
            *slot = chunk[0];
        }
        // At the end of the series the last point may start a part chunk:
        // it is the only one (the caller's bound).
        if n < group.len() {
            group[n] = rest[0];
        }
    }
}

/// [`every`] at any stride.
#[inline(always)]
fn groups_any(x: &[f64], m: usize, out: &mut [f64]) {
    for (g, group) in out.chunks_mut(GROUP).enumerate() {
        let at = g * GROUP * m;
        ask(x, m, at);
        for (slot, &v) in group.iter_mut().zip(x[at..].iter().step_by(m)) {
            *slot = v;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// Every stride, constant or not, copies exactly x[i·m], up to the
        /// last point the series holds.
        #[test]
        fn copies_every_mth_point(len in 1usize..3000, m in 1usize..40, short in 0usize..3) {
            let x: Vec<f64> = (0..len).map(|i| i as f64 * 0.5 - 7.0).collect();
            let n = ((len - 1) / m + 1).saturating_sub(short);
            let mut out = vec![f64::NAN; n];
            every(&x, m, &mut out);
            for (i, v) in out.iter().enumerate() {
                prop_assert_eq!(v.to_bits(), x[i * m].to_bits(), "i {} m {} len {}", i, m, len);
            }
        }
    }

    /// One point past the series, at each form of the copy, a stride
    /// whose product overflows, and a stride of zero, are refused before
    /// anything is read; the last point within the series is copied.
    #[test]
    fn a_copy_past_the_series_is_refused() {
        for m in [1, 2, 3, 4, 5, 9] {
            let x = vec![1.0; 4 * m];
            let mut out = vec![0.0; 5]; // x[4m] would be read
            let refused = std::panic::catch_unwind(move || every(&x, m, &mut out)).is_err();
            assert!(refused, "m = {m}");
            let x = vec![1.0; 4 * m + 1];
            let mut out = vec![0.0; 5];
            every(&x, m, &mut out);
            assert_eq!(out, [1.0; 5]);
        }
        let x = [1.0; 10];
        let refused = std::panic::catch_unwind(|| every(&x, usize::MAX / 2, &mut [0.0; 3])).is_err();
        assert!(refused);
        let refused = std::panic::catch_unwind(|| every(&x, 0, &mut [0.0; 3])).is_err();
        assert!(refused);
    }
}
