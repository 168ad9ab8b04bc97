//! MDEV's sum of squared window sums on data without gaps, at about one
//! memory pass per τ.
//!
//! The window sum W_j = Σ_{i=j}^{j+m−1} (x[i+2m] − 2x[i+m] + x[i]) moves on by
//! the third difference e_j = x[j+3m] − 3x[j+2m] + 3x[j+m] − x[j] = W_{j+1} − W_j.
//! Four consecutive windows ride together, each moving on by four third
//! differences at a time,
//! W_{j+4} = W_j + ((e_j + e_{j+1}) + e_{j+2}) + e_{j+3},
//! so one dependent addition serves four windows. Every interval of
//! max(RESYNC, 8m) windows starts from an exact sum of its first window's m
//! second differences, which bounds the running sum's rounding drift while
//! the exact sums cost at most an eighth of a pass more.
//!
//! On x86-64 with AVX2 the four windows sit in one register and the third
//! differences are formed as they are needed; elsewhere they are formed a
//! chunk at a time into a buffer. Both do the same operations in the same
//! order lane by lane and use no fused multiply-add, so they give the same
//! result bit for bit (a test holds them to it).

use super::modified::RESYNC;

/// Windows whose third differences the portable scan forms at a time, in L1.
const CHUNK: usize = 256;

/// Σ over every window j of W_j², for 3m ≤ x.len().
pub(super) fn gap_free_squares(x: &[f64], m: usize) -> f64 {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the one requirement for calling a function compiled with
        // `target_feature(enable = "avx2")` is a CPU that has AVX2, which
        // was just detected.
        return unsafe { gap_free_squares_avx2(x, m) };
    }
    intervals(x, m, scan_portable)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn gap_free_squares_avx2(x: &[f64], m: usize) -> f64 {
    intervals(x, m, |x, m, j0, moves, w, acc| scan_avx2(x, m, j0, moves, w, acc))
}

/// The resync intervals, each scanned a quad of windows at a time. A scan,
/// from the four windows j0 … j0+3 in `w`, `moves` times adds their squares
/// to `acc` and moves them on by four windows.
#[inline(always)]
fn intervals(
    x: &[f64],
    m: usize,
    scan: impl Fn(&[f64], usize, usize, usize, &mut [f64; 4], &mut [f64; 4]),
) -> f64 {
    let terms = x.len() - 3 * m + 1;
    let interval = RESYNC.max(8 * m);
    let mut acc = [0.0f64; 4];
    let mut rest = 0.0;
    let mut start = 0;
    while start < terms {
        let end = (start + interval).min(terms);
        let quads = (end - start) / 4;
        let mut last = exact_window(x, m, start);
        if quads > 0 {
            let mut w = [last, 0.0, 0.0, 0.0];
            for l in 1..4 {
                w[l] = w[l - 1] + third_difference(x, m, start + l - 1);
            }
            // The interval's last quad is not moved on: the windows after it,
            // if any, are taken one by one below.
            scan(x, m, start, quads - 1, &mut w, &mut acc);
            for l in 0..4 {
                acc[l] += w[l] * w[l];
            }
            last = w[3];
        } else {
            rest += last * last;
        }
        for j in (start + 4 * quads).max(start + 1)..end {
            last += third_difference(x, m, j - 1);
            rest += last * last;
        }
        start = end;
    }
    crate::lanes::join(acc, rest)
}

/// The scan with the third differences formed a chunk at a time into a
/// buffer, in loops the compiler vectorises for any target.
fn scan_portable(x: &[f64], m: usize, j0: usize, moves: usize, w: &mut [f64; 4], acc: &mut [f64; 4]) {
    let mut e = [0.0f64; CHUNK + 3];
    let mut done = 0;
    while done < moves {
        let n = (CHUNK / 4).min(moves - done);
        let from = j0 + 4 * done;
        third_differences(x, m, from, &mut e[..4 * n + 3]);
        for e in e[..4 * n + 3].windows(7).step_by(4) {
            for l in 0..4 {
                acc[l] += w[l] * w[l];
                w[l] += ((e[l] + e[l + 1]) + e[l + 2]) + e[l + 3];
            }
        }
        done += n;
    }
}

/// The scan with the four windows in one AVX2 register and each quad's
/// third differences formed as they are needed, e_{j+1…j+3} from two
/// registers by lane shuffles: no buffer, and four instructions fewer per
/// quad than the compiler makes of [`scan_portable`].
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn scan_avx2(x: &[f64], m: usize, j0: usize, moves: usize, w: &mut [f64; 4], acc: &mut [f64; 4]) {
    // Moving quad k on reads the third differences of quad k + 1, which
    // reach x[j0 + 4(k+1) + 3 + 3m]; at the very end of the series the last
    // of them may not exist (nor is it needed), so that move is left to the
    // portable scan.
    let fused = match (x.len() - 3 * m).checked_sub(j0 + 4) {
        Some(room) => moves.min(room / 4),
        None => 0,
    };
    if fused > 0 {
        fused_moves(x, m, j0, fused, w, acc);
    }
    if fused < moves {
        scan_portable(x, m, j0 + 4 * fused, moves - fused, w, acc);
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn fused_moves(x: &[f64], m: usize, j0: usize, moves: usize, w: &mut [f64; 4], acc: &mut [f64; 4]) {
    use std::arch::x86_64::{
        __m256d, _mm256_add_pd, _mm256_loadu_pd, _mm256_mul_pd, _mm256_permute2f128_pd, _mm256_set1_pd,
        _mm256_shuffle_pd, _mm256_storeu_pd, _mm256_sub_pd,
    };
    // The four phase streams of quads 0 ..= moves, as arrays of four: the
    // loop below then indexes nothing.
    let len = 4 * (moves + 1);
    let stream = |k: usize| x[j0 + k * m..j0 + k * m + len].as_chunks::<4>().0;
    let (a, b, c, d) = (stream(0), stream(1), stream(2), stream(3));
    // SAFETY: unaligned loads of four f64 from arrays of four.
    let load = |v: &[f64; 4]| -> __m256d { unsafe { _mm256_loadu_pd(v.as_ptr()) } };
    let three = _mm256_set1_pd(3.0);
    // e_j … e_{j+3}, as `third_difference` forms each: ((d − 3c) + 3b) − a.
    let quad = |a, b, c, d| -> __m256d {
        let (a, b, c, d) = (load(a), load(b), load(c), load(d));
        _mm256_sub_pd(
            _mm256_add_pd(_mm256_sub_pd(d, _mm256_mul_pd(three, c)), _mm256_mul_pd(three, b)),
            a,
        )
    };
    let store = |to: &mut [f64; 4], v: __m256d| {
        // SAFETY: an unaligned store of four f64 into an array of four.
        unsafe { _mm256_storeu_pd(to.as_mut_ptr(), v) }
    };
    let (mut wv, mut av) = (load(w), load(acc));
    let mut cur = quad(&a[0], &b[0], &c[0], &d[0]);
    let lead = j0 + 3 * m;
    for (k, (((a, b), c), d)) in a[1..].iter().zip(&b[1..]).zip(&c[1..]).zip(&d[1..]).enumerate() {
        crate::prefetch::ahead(x, lead + 4 * k);
        let next = quad(a, b, c, d);
        // [e1 e2 e3 e4], [e2 e3 e4 e5], [e3 e4 e5 e6] from [e0 e1 e2 e3] and
        // [e4 e5 e6 e7].
        let two = _mm256_permute2f128_pd::<0x21>(cur, next);
        let one = _mm256_shuffle_pd::<0b0101>(cur, two);
        let three_on = _mm256_shuffle_pd::<0b0101>(two, next);
        let step = _mm256_add_pd(_mm256_add_pd(_mm256_add_pd(cur, one), two), three_on);
        av = _mm256_add_pd(av, _mm256_mul_pd(wv, wv));
        wv = _mm256_add_pd(wv, step);
        cur = next;
    }
    store(w, wv);
    store(acc, av);
}

/// W_j summed afresh, in four interleaved sums.
#[inline(always)]
fn exact_window(x: &[f64], m: usize, j: usize) -> f64 {
    let (a, b, c) = (&x[j..j + m], &x[j + m..j + 2 * m], &x[j + 2 * m..j + 3 * m]);
    let mut acc = [0.0f64; 4];
    let whole = m - m % 4;
    for ((a, b), c) in a[..whole]
        .chunks_exact(4)
        .zip(b[..whole].chunks_exact(4))
        .zip(c[..whole].chunks_exact(4))
    {
        for k in 0..4 {
            acc[k] += c[k] - 2.0 * b[k] + a[k];
        }
    }
    let tail: f64 = (whole..m).map(|i| c[i] - 2.0 * b[i] + a[i]).sum();
    crate::lanes::join(acc, tail)
}

/// e_j = W_{j+1} − W_j.
#[inline(always)]
fn third_difference(x: &[f64], m: usize, j: usize) -> f64 {
    x[j + 3 * m] - 3.0 * x[j + 2 * m] + 3.0 * x[j + m] - x[j]
}

/// e_j for j in j0..j0 + out.len(), in a loop that vectorises.
#[inline(always)]
fn third_differences(x: &[f64], m: usize, j0: usize, out: &mut [f64]) {
    let len = out.len();
    let (a, b) = (&x[j0..j0 + len], &x[j0 + m..j0 + m + len]);
    let (c, d) = (&x[j0 + 2 * m..j0 + 2 * m + len], &x[j0 + 3 * m..j0 + 3 * m + len]);
    for ((((o, a), b), c), d) in out.iter_mut().zip(a).zip(b).zip(c).zip(d) {
        *o = d - 3.0 * c + 3.0 * b - a;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// Whatever the CPU, the same bits: the AVX2 scan against the
        /// portable one on random walks of any length and step.
        #[test]
        fn every_scan_gives_the_same_bits(len in 3usize..5000, m_seed in 0usize..2000, seed in 0u64..1000) {
            let x = crate::work::random_walk(len, seed);
            let m = 1 + m_seed % (len / 3);
            let portable = intervals(&x, m, scan_portable);
            prop_assert_eq!(gap_free_squares(&x, m).to_bits(), portable.to_bits());
        }
    }
}
