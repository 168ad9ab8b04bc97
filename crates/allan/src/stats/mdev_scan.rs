//! MDEV's sum of squared window sums on data without gaps, at about one
//! memory pass per τ.
//!
//! The window sum W_j = Σ_{i=j}^{j+m−1} s_i of the second differences
//! s_i = (x[i+2m] − x[i+m]) − (x[i+m] − x[i]) moves on by the third
//! difference e_j = s_{j+m} − s_j = W_{j+1} − W_j, formed as that
//! difference. The first differences of the phase are exact where the
//! phase is far from zero (Sterbenz), so every rounding is at the scale of
//! the differences, not of the phase. Formed as x[j+3m] − 3x[j+2m] +
//! 3x[j+m] − x[j], as it first was, 3x rounded at the phase's scale, and on
//! a large offset under small noise the windows drifted between resyncs:
//! at m = 2, 1.2e-7 relative at an offset of 1e2 under noise of 1e-9, and
//! 3.3 times MDEV at 1e6 under 1e-9. Six subtractions, where that form took
//! two multiplications and three additions, and no slower (a form with one
//! multiplication was slower still).
//! Eight consecutive windows ride together, each moving on by eight third
//! differences at a time, W_{j+8} = W_j + O_j, with O_j their sum taken as a
//! tree of sliding sums: P_j = e_j + e_{j+1}, Q_j = P_j + P_{j+2},
//! O_j = Q_j + Q_{j+4}. Each level is one addition for eight windows, so a
//! window moves on for five additions per eight points (three of the tree,
//! one move, one square's sum), where summing the eight in a row took seven.
//! Every interval of max(4·RESYNC, 8m) windows starts from an exact sum of its
//! first window's m second differences, which bounds the running sum's
//! rounding drift while the exact sums cost at most an eighth of a pass more;
//! a window's square goes to accumulator j mod 8 of its interval.
//!
//! On x86-64 with AVX-512 the eight windows sit in one register and the
//! tree's levels are formed from neighbouring registers by lane rotations
//! as they are needed; with AVX2 the same in two registers; elsewhere, and
//! for the last moves before the end of the series, the third differences
//! and Q are formed a chunk at a time into buffers, in loops the compiler
//! vectorises. All do the same operations in the same order lane by lane
//! and use no fused multiply-add, so they give the same result bit for bit
//! (a test holds them to it). The register scans ask for the leading
//! stream's lines 16 KiB ahead and for the two trailing streams' a little
//! ahead ([`TRAILING`]).
//!
//! AVX-512 used to give way to AVX2 from m = 1536 on: the streams x[j] and
//! x[j + m] came from L2 there, and the 64-byte loads, every one across two
//! cache lines, cost more than the narrower registers saved. With the
//! trailing streams asked for ahead, AVX-512 was ahead at every m measured,
//! 16 to 2^20 (`allan_per_tau`, bench/README.md). On CPUs that split or
//! slow 512-bit operations the balance may differ; both give the same bits.
//!
//! Before, four windows moved by four differences summed in a row: seven
//! additions where the tree takes five, and a dependent chain every four
//! points.

use super::differences::third;
use super::modified::RESYNC;

/// Windows that ride together, and the points each moves on by at once.
const LANES: usize = 8;

/// How far past the move's window j the register scans ask for the lines
/// of x[j] and x[j + m], in points. A move reads its group three groups on
/// (the tree's reach), so the lines come 40 points ahead of their loads.
/// Those streams were read 3m and 2m points earlier, and with the leading
/// stream asked for 16 KiB ahead they no longer stay in a 48 KiB L1 cache
/// even at m = 1024 (3m points span 24 KiB). Asking for them ahead cut the
/// memory passes most from m = 1024 on; 32 points did as well at m = 16 but
/// worse at 1024, 96 and more were slower than none, and the stream
/// x[j + 2m], asked for too, gained at m = 1024 and lost at 16 and 4096
/// (`allan_per_tau N passes`, bench/README.md).
#[cfg(target_arch = "x86_64")]
const TRAILING: usize = 64;

/// Windows whose third differences the portable scan forms at a time, in L1.
const CHUNK: usize = 256;

/// Σ over every window j of W_j², for 3m ≤ x.len().
pub(super) fn gap_free_squares(x: &[f64], m: usize) -> f64 {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx512f") {
            // SAFETY: the one requirement for calling a function compiled
            // with `target_feature(enable = "avx512f")` is a CPU that has
            // AVX-512F, which was just detected.
            return unsafe { gap_free_squares_avx512(x, m) };
        }
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: as above, for AVX2.
            return unsafe { gap_free_squares_avx2(x, m) };
        }
    }
    intervals(x, m, scan_portable)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn gap_free_squares_avx512(x: &[f64], m: usize) -> f64 {
    intervals(x, m, |x, m, j0, moves, w, acc| {
        scan_avx512(x, m, j0, moves, w, acc)
    })
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn gap_free_squares_avx2(x: &[f64], m: usize) -> f64 {
    intervals(x, m, |x, m, j0, moves, w, acc| scan_avx2(x, m, j0, moves, w, acc))
}

/// The running windows and their squares' accumulators.
type Lanes = [f64; LANES];

/// The resync intervals, each scanned eight windows at a time. A scan, from
/// the eight windows j0 … j0+7 in `w`, `moves` times adds their squares to
/// `acc` and moves them on by eight windows.
#[inline(always)]
fn intervals(x: &[f64], m: usize, scan: impl Fn(&[f64], usize, usize, usize, &mut Lanes, &mut Lanes)) -> f64 {
    let terms = x.len() - 3 * m + 1;
    // Four times the gapped form's interval: each one costs an exact
    // window and a register scan's set-up, which at m = 16 on 10^7 points
    // took about 0.4 ms of 2.8; the drift over 4096 moves of eight stays far
    // below the 1e-12 the tests hold MDEV to.
    let interval = (4 * RESYNC).max(8 * m);
    let mut acc = [0.0f64; LANES];
    let mut rest = 0.0;
    let mut start = 0;
    while start < terms {
        let end = (start + interval).min(terms);
        let groups = (end - start) / LANES;
        let mut last = exact_window(x, m, start);
        if groups > 0 {
            let mut w = [last; LANES];
            for l in 1..LANES {
                w[l] = w[l - 1] + third_difference(x, m, start + l - 1);
            }
            // The interval's last group is not moved on: the windows after
            // it, if any, are taken one by one below.
            scan(x, m, start, groups - 1, &mut w, &mut acc);
            for l in 0..LANES {
                acc[l] += w[l] * w[l];
            }
            last = w[LANES - 1];
        } else {
            rest += last * last;
        }
        for j in (start + LANES * groups).max(start + 1)..end {
            last += third_difference(x, m, j - 1);
            rest += last * last;
        }
        start = end;
    }
    let [a, b, c, d, e, f, g, h] = acc;
    (((a + b) + (c + d)) + ((e + f) + (g + h))) + rest
}

/// The scan with the third differences and then Q formed a chunk at a time
/// into two buffers, in loops the compiler vectorises for any target, and O
/// as the windows move. The register scans take it for the moves near the
/// end of the series, where they would read third differences that do not
/// exist. On SSE2 alone it is somewhat slower than the scan before the tree
/// was, and faster than forming each level in a pass of its own or the
/// register scans' steps on arrays of eight.
#[inline(always)]
fn scan_portable(x: &[f64], m: usize, j0: usize, moves: usize, w: &mut Lanes, acc: &mut Lanes) {
    let mut e = [0.0f64; CHUNK + LANES - 1];
    let mut t = [0.0f64; CHUNK + LANES - 1];
    // Copied into locals for the chunk's loops, so that the compiler need
    // not assume the references alias the buffers.
    let (mut wl, mut al) = (*w, *acc);
    let mut done = 0;
    while done < moves {
        let n = (CHUNK / LANES).min(moves - done);
        let len = LANES * n;
        // O_j for the len windows from `from` reads e_j … e_{j+7}.
        let from = j0 + LANES * done;
        third_differences(x, m, from, &mut e[..len + 7]);
        // Q in one pass, its two levels formed from the same loads; O as
        // the windows move.
        {
            let q = &mut t[..len + 4];
            let (e0, e1, e2, e3) = (&e[..len + 4], &e[1..len + 5], &e[2..len + 6], &e[3..len + 7]);
            for i in 0..len + 4 {
                q[i] = (e0[i] + e1[i]) + (e2[i] + e3[i]);
            }
        }
        let (q, q4) = (&t[..len], &t[4..len + 4]);
        for (q, q4) in q.as_chunks::<LANES>().0.iter().zip(q4.as_chunks::<LANES>().0) {
            for l in 0..LANES {
                al[l] += wl[l] * wl[l];
                wl[l] += q[l] + q4[l];
            }
        }
        done += n;
    }
    (*w, *acc) = (wl, al);
}

/// The scan with the eight windows in one AVX-512 register: the third
/// differences of eight windows formed at a time, and each level of the
/// tree from two neighbouring registers by one lane rotation (VALIGNQ), so
/// nothing goes through memory but the series.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn scan_avx512(x: &[f64], m: usize, j0: usize, moves: usize, w: &mut Lanes, acc: &mut Lanes) {
    register_scan(x, m, j0, moves, w, acc, |fused, w, acc| {
        fused_moves(x, m, j0, fused, w, acc)
    });
}

/// A register scan, `fused` as many moves as it can take from `j0`, then
/// [`scan_portable`] for the rest. Moving group k on reads the third
/// differences of groups up to k + 3 (the tree's three levels each reach
/// one group further), the last of them up to e_{j0+8k+31}; near the end of
/// the series those may not exist.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn register_scan(
    x: &[f64],
    m: usize,
    j0: usize,
    moves: usize,
    w: &mut Lanes,
    acc: &mut Lanes,
    fused_moves: impl FnOnce(usize, &mut Lanes, &mut Lanes),
) {
    let fused = match (x.len() - 3 * m).checked_sub(j0 + 4 * LANES) {
        Some(room) => moves.min(room / LANES + 1),
        None => 0,
    };
    if fused > 0 {
        fused_moves(fused, w, acc);
    }
    if fused < moves {
        scan_portable(x, m, j0 + LANES * fused, moves - fused, w, acc);
    }
}

/// The scan with the eight windows in two AVX2 registers, the tree's levels
/// formed as in [`scan_avx512`] from lane shuffles of neighbouring
/// registers (the rotation by four lanes is only a change of register).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn scan_avx2(x: &[f64], m: usize, j0: usize, moves: usize, w: &mut Lanes, acc: &mut Lanes) {
    register_scan(x, m, j0, moves, w, acc, |fused, w, acc| {
        fused_moves_avx2(x, m, j0, fused, w, acc)
    });
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn fused_moves_avx2(x: &[f64], m: usize, j0: usize, moves: usize, w: &mut Lanes, acc: &mut Lanes) {
    use std::arch::x86_64::{
        __m256d, _mm256_add_pd, _mm256_loadu_pd, _mm256_mul_pd, _mm256_permute2f128_pd, _mm256_shuffle_pd,
        _mm256_storeu_pd, _mm256_sub_pd,
    };
    /// Eight lanes as two registers, lanes 0–3 and 4–7.
    #[derive(Clone, Copy)]
    struct V(__m256d, __m256d);
    let len = LANES * (moves + 3);
    let stream = |k: usize| x[j0 + k * m..j0 + k * m + len].as_chunks::<LANES>().0;
    let (a, b, c, d) = (stream(0), stream(1), stream(2), stream(3));
    // SAFETY: unaligned loads of four f64 from the halves of arrays of eight.
    let load = |v: &[f64; LANES]| -> V {
        unsafe { V(_mm256_loadu_pd(v.as_ptr()), _mm256_loadu_pd(v.as_ptr().add(4))) }
    };
    let add = |u: V, v: V| V(_mm256_add_pd(u.0, v.0), _mm256_add_pd(u.1, v.1));
    let group = |k: usize| -> V {
        let (a, b, c, d) = (load(&a[k]), load(&b[k]), load(&c[k]), load(&d[k]));
        // As `third_difference`: the difference of two second differences,
        // each a difference of first differences.
        let e = |a, b, c, d| {
            let (dc, cb, ba) = (_mm256_sub_pd(d, c), _mm256_sub_pd(c, b), _mm256_sub_pd(b, a));
            _mm256_sub_pd(_mm256_sub_pd(dc, cb), _mm256_sub_pd(cb, ba))
        };
        V(e(a.0, b.0, c.0, d.0), e(a.1, b.1, c.1, d.1))
    };
    // [u1 u2 u3 v0] and [u2 u3 v0 v1] of two four-lane registers.
    let by1 = |u, v| _mm256_shuffle_pd::<0b0101>(u, _mm256_permute2f128_pd::<0x21>(u, v));
    let by2 = |u, v| _mm256_permute2f128_pd::<0x21>(u, v);
    let on1 = |g: V, next: V| V(by1(g.0, g.1), by1(g.1, next.0));
    let on2 = |g: V, next: V| V(by2(g.0, g.1), by2(g.1, next.0));
    let on4 = |g: V, next: V| V(g.1, next.0);
    let (e0, e1, mut e2) = (group(0), group(1), group(2));
    let p0 = add(e0, on1(e0, e1));
    let mut p1 = add(e1, on1(e1, e2));
    let mut q0 = add(p0, on2(p0, p1));
    let (mut wv, mut av) = (load(w), load(acc));
    let lead = j0 + 3 * m + 3 * LANES;
    for k in 0..moves {
        ask(x, m, j0 + LANES * k, lead + LANES * k);
        let e3 = group(k + 3);
        let p2 = add(e2, on1(e2, e3));
        let q1 = add(p1, on2(p1, p2));
        let o = add(q0, on4(q0, q1));
        av = add(av, V(_mm256_mul_pd(wv.0, wv.0), _mm256_mul_pd(wv.1, wv.1)));
        wv = add(wv, o);
        (e2, p1, q0) = (e3, p2, q1);
    }
    // SAFETY: unaligned stores of four f64 into the halves of arrays of eight.
    unsafe {
        _mm256_storeu_pd(w.as_mut_ptr(), wv.0);
        _mm256_storeu_pd(w.as_mut_ptr().add(4), wv.1);
        _mm256_storeu_pd(acc.as_mut_ptr(), av.0);
        _mm256_storeu_pd(acc.as_mut_ptr().add(4), av.1);
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn fused_moves(x: &[f64], m: usize, j0: usize, moves: usize, w: &mut Lanes, acc: &mut Lanes) {
    use std::arch::x86_64::{
        __m512d, _mm512_add_pd, _mm512_alignr_epi64, _mm512_castpd_si512, _mm512_castsi512_pd,
        _mm512_loadu_pd, _mm512_mul_pd, _mm512_storeu_pd, _mm512_sub_pd,
    };
    // The four phase streams of groups 0 ..= moves + 2, as arrays of eight:
    // the loop below then indexes nothing.
    let len = LANES * (moves + 3);
    let stream = |k: usize| x[j0 + k * m..j0 + k * m + len].as_chunks::<LANES>().0;
    let (a, b, c, d) = (stream(0), stream(1), stream(2), stream(3));
    // SAFETY: unaligned loads of eight f64 from arrays of eight.
    let load = |v: &[f64; LANES]| -> __m512d { unsafe { _mm512_loadu_pd(v.as_ptr()) } };
    // e_j … e_{j+7} of group k, as `third_difference` forms each:
    // ((x₃ − x₂) − (x₂ − x₁)) − ((x₂ − x₁) − (x₁ − x₀)).
    let group = |k: usize| -> __m512d {
        let (a, b, c, d) = (load(&a[k]), load(&b[k]), load(&c[k]), load(&d[k]));
        let (dc, cb, ba) = (_mm512_sub_pd(d, c), _mm512_sub_pd(c, b), _mm512_sub_pd(b, a));
        _mm512_sub_pd(_mm512_sub_pd(dc, cb), _mm512_sub_pd(cb, ba))
    };
    // Lanes s … 7 of `lo` then 0 … s−1 of `hi`: v_{j+s} for the group of lo.
    macro_rules! on {
        ($lo:expr, $hi:expr, $s:literal) => {
            _mm512_castsi512_pd(_mm512_alignr_epi64::<$s>(
                _mm512_castpd_si512($hi),
                _mm512_castpd_si512($lo),
            ))
        };
    }
    let (e0, e1, mut e2) = (group(0), group(1), group(2));
    let p0 = _mm512_add_pd(e0, on!(e0, e1, 1));
    let mut p1 = _mm512_add_pd(e1, on!(e1, e2, 1));
    let mut q0 = _mm512_add_pd(p0, on!(p0, p1, 2));
    let (mut wv, mut av) = (load(w), load(acc));
    let lead = j0 + 3 * m + 3 * LANES;
    for k in 0..moves {
        ask(x, m, j0 + LANES * k, lead + LANES * k);
        let e3 = group(k + 3);
        let p2 = _mm512_add_pd(e2, on!(e2, e3, 1));
        let q1 = _mm512_add_pd(p1, on!(p1, p2, 2));
        let o = _mm512_add_pd(q0, on!(q0, q1, 4));
        av = _mm512_add_pd(av, _mm512_mul_pd(wv, wv));
        wv = _mm512_add_pd(wv, o);
        (e2, p1, q0) = (e3, p2, q1);
    }
    // SAFETY: unaligned stores of eight f64 into arrays of eight.
    unsafe {
        _mm512_storeu_pd(w.as_mut_ptr(), wv);
        _mm512_storeu_pd(acc.as_mut_ptr(), av);
    }
}

/// The cache lines a register scan's move at window j asks for: the
/// leading stream's [`crate::prefetch::DISTANCE`] bytes past `lead`, and
/// the two trailing streams' [`TRAILING`] points ahead.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn ask(x: &[f64], m: usize, j: usize, lead: usize) {
    crate::prefetch::ahead(x, lead);
    crate::prefetch::line(x, j + TRAILING);
    crate::prefetch::line(x, j + m + TRAILING);
}

/// W_j summed afresh, in four interleaved sums, each second difference
/// formed as (x₂ − x₁) − (x₁ − x₀), as the moves form them.
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
            acc[k] += (c[k] - b[k]) - (b[k] - a[k]);
        }
    }
    let tail: f64 = (whole..m).map(|i| (c[i] - b[i]) - (b[i] - a[i])).sum();
    crate::lanes::join(acc, tail)
}

/// e_j = W_{j+1} − W_j.
#[inline(always)]
fn third_difference(x: &[f64], m: usize, j: usize) -> f64 {
    third(x[j], x[j + m], x[j + 2 * m], x[j + 3 * m])
}

/// e_j for j in j0..j0 + out.len(), in a loop that vectorises.
#[inline(always)]
fn third_differences(x: &[f64], m: usize, j0: usize, out: &mut [f64]) {
    let len = out.len();
    let (a, b) = (&x[j0..j0 + len], &x[j0 + m..j0 + m + len]);
    let (c, d) = (&x[j0 + 2 * m..j0 + 2 * m + len], &x[j0 + 3 * m..j0 + 3 * m + len]);
    for ((((o, a), b), c), d) in out.iter_mut().zip(a).zip(b).zip(c).zip(d) {
        *o = third(*a, *b, *c, *d);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Every scan against the portable one, bit for bit, where this CPU
    /// has it; returns how many forms were compared.
    fn same_bits(x: &[f64], m: usize) -> usize {
        let portable = intervals(x, m, |x, m, j0, moves, w, acc| {
            scan_portable(x, m, j0, moves, w, acc)
        })
        .to_bits();
        assert_eq!(gap_free_squares(x, m).to_bits(), portable, "m = {m}");
        #[allow(unused_mut)]
        let mut forms = 1;
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx512f") {
                // SAFETY: AVX-512F was just detected.
                assert_eq!(
                    unsafe { gap_free_squares_avx512(x, m) }.to_bits(),
                    portable,
                    "m = {m}"
                );
                forms += 1;
            }
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: AVX2 was just detected.
                assert_eq!(
                    unsafe { gap_free_squares_avx2(x, m) }.to_bits(),
                    portable,
                    "m = {m}"
                );
                forms += 1;
            }
        }
        forms
    }

    /// Factors near the ends of the register scans' reach (m near len/3)
    /// and where the dispatch once changed form (1536), large factors the
    /// AVX-512 scan now takes, and a series of many resync intervals: cases
    /// random draws reach only by chance.
    #[test]
    fn the_dispatch_boundaries_give_the_same_bits() {
        let x = crate::work::random_walk(20_011, 3);
        let mut forms = 0;
        for m in [1, 2, 7, 8, 9, 1535, 1536, 1537, 2048, 6000, 6667, 6668, 6670] {
            forms = same_bits(&x, m);
        }
        let long = crate::work::random_walk(400_003, 5);
        for m in [1, 3, 64, 1000, 1536, 50_000, 133_334] {
            same_bits(&long, m);
        }
        if forms == 1 {
            eprintln!("this CPU has neither AVX2 nor AVX-512: only the portable scan was run");
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// Whatever the CPU, the same bits: the AVX-512 and AVX2 scans
        /// against the portable one on random walks of any length and step
        /// (each where this CPU has it).
        #[test]
        fn every_scan_gives_the_same_bits(len in 3usize..5000, m_seed in 0usize..2000, seed in 0u64..1000) {
            let x = crate::work::random_walk(len, seed);
            same_bits(&x, 1 + m_seed % (len / 3));
        }
    }
}
