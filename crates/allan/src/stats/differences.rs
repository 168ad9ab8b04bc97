//! Sums of squared finite differences of phase: the kernel under ADEV and
//! HDEV in all their overlapped and non-overlapped forms.
//!
//! Each averaging factor costs one pass over the phase points that its terms
//! touch (O(N/stride)); only the non-overlapped sums copy those points, a
//! chunk at a time, into a buffer in L1.

use rayon::prelude::*;

use super::Estimate;
use crate::phase::PhaseSeries;

/// Order of the difference: 2 for the Allan family, 3 for Hadamard.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Order {
    Second,
    Third,
}

impl Order {
    fn span(self) -> usize {
        match self {
            Order::Second => 2,
            Order::Third => 3,
        }
    }

    /// The deviation of `n` squared differences summing to `sum` at factor
    /// `m`: √(Σ / (c·n·τ²)), c = 2 for the Allan variance (SP 1065 eqs. 7,
    /// 11), 6 for the Hadamard variance (eqs. 18, 20); none without a term.
    pub(crate) fn deviation(self, (sum, n): (f64, usize), m: usize, tau0: f64) -> Option<Estimate> {
        let c = match self {
            Order::Second => 2.0,
            Order::Third => 6.0,
        };
        (n > 0).then(|| {
            let tau = m as f64 * tau0;
            Estimate {
                dev: (sum / (c * n as f64 * tau * tau)).sqrt(),
                n,
            }
        })
    }
}

/// The second difference x₂ − 2x₁ + x₀, as every sum forms it: exact where
/// the phase is far from zero (see [`third`]).
#[inline(always)]
pub(super) fn second(a: f64, b: f64, c: f64) -> f64 {
    c - 2.0 * b + a
}

/// The third difference x₃ − 3x₂ + 3x₁ − x₀, formed as a difference of
/// second differences of first differences. Each first difference is exact
/// where the phase is far from zero (Sterbenz), so it rounds at the scale
/// of the differences: formed as written, 3x rounds at the scale of the
/// phase, 1.5e-7 relative at an offset of 100 under noise of 1e-9. (The
/// second difference x₂ − 2x₁ + x₀ is exact there as written: 2x is exact,
/// and both subtractions fall within Sterbenz's range.)
#[inline(always)]
pub(super) fn third(a: f64, b: f64, c: f64, d: f64) -> f64 {
    ((d - c) - (c - b)) - ((c - b) - (b - a))
}

/// The `order`-th difference of phase at step m from x[j], as every sum
/// forms it.
#[inline(always)]
fn difference(x: &[f64], j: usize, m: usize, order: Order) -> f64 {
    match order {
        Order::Second => second(x[j], x[j + m], x[j + 2 * m]),
        Order::Third => third(x[j], x[j + m], x[j + 2 * m], x[j + 3 * m]),
    }
}

/// Which differences a sum takes: every one (j = 0, 1, 2, …) or those that
/// share no point but their ends (j = 0, m, 2m, …).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Terms {
    Overlapped,
    NonOverlapped,
}

/// Σ over j = 0, s, 2s, … of the squared `order`-th difference of phase at
/// step m, s being 1 or m as `terms` says, and the number of terms. Terms
/// that cross a gap are skipped.
pub(crate) fn sum_squared(series: &PhaseSeries, m: usize, terms: Terms, order: Order) -> (f64, usize) {
    let x = series.points();
    let reach = order.span() * m;
    if m == 0 || x.len() <= reach {
        return (0.0, 0);
    }
    let stride = match terms {
        Terms::Overlapped => 1,
        Terms::NonOverlapped => m,
    };
    let last = x.len() - 1 - reach; // largest valid j
    let term = |j: usize| difference(x, j, m, order);
    match series.gap_index() {
        // Overlapped, no gaps: the hot path, the one-factor case of the
        // blocked sweep, so a curve computed factor by factor equals the
        // one swept at once.
        None if stride == 1 => sum_squared_overlapped_many(x, &[m], order)[0],
        None => {
            let n = last / m + 1;
            (decimated_sum(x, m, n, order), n)
        }
        Some(gaps) => {
            let mut sum = 0.0;
            let mut n = 0;
            for j in (0..=last).step_by(stride) {
                let usable = if gaps.is_rate() {
                    !gaps.span_has_gap(j, j + reach)
                } else {
                    // Phase input: only the points the term uses must exist
                    // (AllanTools `gradev`).
                    let v = term(j);
                    v.is_finite()
                };
                if usable {
                    let v = term(j);
                    sum += v * v;
                    n += 1;
                }
            }
            (sum, n)
        }
    }
}

/// Terms of [`decimated_sum`] formed from one copy of the decimated points.
/// At 10^7 points, HDEV at m = 2, medians of 7 runs: 1.51 passes of memory
/// with 64, 1.72 with 128, 1.81 with 256, 1.96 with 2048.
const DECIMATED_CHUNK: usize = 64;

/// Σ over the first n of k of the squared `order`-th difference of the
/// decimated points y_k = x[k·m]: the non-overlapped sums without gaps.
///
/// Read term by term, with a run-time stride and the hardware prefetcher
/// alone, HDEV at small m took well over two passes of memory. Here the
/// points are copied a chunk at a time into a buffer in L1 ([`crate::decimate`]), and the terms formed from the copy in a
/// loop of whole vectors. Term k goes to accumulator k mod 4, in order of
/// k, and the tail is summed as before, so the bits are those of one
/// strided loop with four accumulators (a test holds them to it).
fn decimated_sum(x: &[f64], m: usize, n: usize, order: Order) -> f64 {
    const SUMS: usize = crate::lanes::LANES;
    const _: () = assert!(DECIMATED_CHUNK.is_multiple_of(SUMS));
    let span = order.span();
    let whole = n - n % SUMS;
    let mut y = [0.0f64; DECIMATED_CHUNK + 3];
    let mut acc = [0.0f64; SUMS];
    for k0 in (0..whole).step_by(DECIMATED_CHUNK) {
        let len = DECIMATED_CHUNK.min(whole - k0);
        // The last point read is y at whole − 1 + span, within the series
        // as n ≤ last/m + 1.
        crate::decimate::every(&x[k0 * m..], m, &mut y[..len + span]);
        let (y0, y1, y2) = (&y[..len], &y[1..len + 1], &y[2..len + 2]);
        let y3 = &y[3..len + 3];
        match order {
            Order::Second => {
                for ((a, b), c) in chunks(y0).iter().zip(chunks(y1)).zip(chunks(y2)) {
                    for l in 0..SUMS {
                        let v = second(a[l], b[l], c[l]);
                        acc[l] += v * v;
                    }
                }
            }
            Order::Third => {
                let quads = chunks(y0).iter().zip(chunks(y1)).zip(chunks(y2)).zip(chunks(y3));
                for (((a, b), c), d) in quads {
                    for l in 0..SUMS {
                        let v = third(a[l], b[l], c[l], d[l]);
                        acc[l] += v * v;
                    }
                }
            }
        }
    }
    let tail: f64 = (whole..n)
        .map(|k| {
            let v = difference(x, k * m, m, order);
            v * v
        })
        .sum();
    crate::lanes::join(acc, tail)
}

/// A slice's whole groups of four.
#[inline(always)]
fn chunks(s: &[f64]) -> &[[f64; crate::lanes::LANES]] {
    s.as_chunks::<{ crate::lanes::LANES }>().0
}

/// Accumulators of [`block_sum`]: one running sum would wait on every
/// addition's latency (floating-point addition is not reassociated by the
/// compiler); eight independent ones keep the vector units busy (two AVX2
/// registers, four SSE2 ones). It also rounds less than one long sum.
const LANES: usize = 8;

/// Σ over i < `len` of the squared `order`-th difference at step m starting
/// at phase point j0 + i: one block of the overlapped sums. Element i goes
/// to accumulator i mod [`LANES`] whatever the instruction set, so the
/// result is the same bit for bit on every x86-64 (no fused multiply-add is
/// ever used).
#[inline]
fn block_sum(order: Order, x: &[f64], j0: usize, len: usize, m: usize) -> f64 {
    let mut acc = [0.0f64; LANES];
    // The stream at the difference's far end is the one from memory.
    let lead = j0 + order.span() * m + crate::prefetch::DISTANCE / 8;
    let run = Run {
        order,
        x,
        j0,
        len,
        m,
        prefetch: lead,
    };
    let tail = block_lanes(run, &mut acc);
    acc.iter().sum::<f64>() + tail
}

/// Where [`block_lanes`] sums: the terms at j0 + i for i < `len`, of
/// `order` at step m, asking for the line at `prefetch` (stepped by a line
/// a group of lanes).
#[derive(Clone, Copy)]
struct Run<'a> {
    order: Order,
    x: &'a [f64],
    j0: usize,
    len: usize,
    m: usize,
    prefetch: usize,
}

/// Adds the terms of `run` to the lanes `acc` (a block's lanes may be
/// filled in several calls, in order), and returns the sum of the terms
/// past the last whole [`LANES`].
#[inline]
fn block_lanes(run: Run, acc: &mut [f64; LANES]) -> f64 {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the one requirement for calling a function compiled with
        // `target_feature(enable = "avx2")` is a CPU that has AVX2, which
        // was just detected.
        return unsafe { block_lanes_avx2(run, acc) };
    }
    block_lanes_portable(run, acc)
}

/// [`block_lanes_portable`] compiled for AVX2: four lanes to an instruction
/// instead of two, with the same operations in the same order.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn block_lanes_avx2(run: Run, acc: &mut [f64; LANES]) -> f64 {
    block_lanes_portable(run, acc)
}

#[inline(always)]
fn block_lanes_portable(run: Run, acc: &mut [f64; LANES]) -> f64 {
    let Run {
        order,
        x,
        j0,
        len,
        m,
        prefetch,
    } = run;
    let a = &x[j0..j0 + len];
    let b = &x[j0 + m..j0 + m + len];
    let c = &x[j0 + 2 * m..j0 + 2 * m + len];
    let whole = len - len % LANES;
    match order {
        Order::Second => {
            let term = |a: f64, b: f64, c: f64| {
                let v = second(a, b, c);
                v * v
            };
            for (i, ((a, b), c)) in a[..whole]
                .chunks_exact(LANES)
                .zip(b[..whole].chunks_exact(LANES))
                .zip(c[..whole].chunks_exact(LANES))
                .enumerate()
            {
                crate::prefetch::line(x, prefetch.wrapping_add(i * LANES));
                for k in 0..LANES {
                    acc[k] += term(a[k], b[k], c[k]);
                }
            }
            (whole..len).map(|i| term(a[i], b[i], c[i])).sum::<f64>()
        }
        Order::Third => {
            let d = &x[j0 + 3 * m..j0 + 3 * m + len];
            let term = |a: f64, b: f64, c: f64, d: f64| {
                let v = third(a, b, c, d);
                v * v
            };
            for (i, (((a, b), c), d)) in a[..whole]
                .chunks_exact(LANES)
                .zip(b[..whole].chunks_exact(LANES))
                .zip(c[..whole].chunks_exact(LANES))
                .zip(d[..whole].chunks_exact(LANES))
                .enumerate()
            {
                crate::prefetch::line(x, prefetch.wrapping_add(i * LANES));
                for k in 0..LANES {
                    acc[k] += term(a[k], b[k], c[k], d[k]);
                }
            }
            (whole..len).map(|i| term(a[i], b[i], c[i], d[i])).sum::<f64>()
        }
    }
}

/// Points of the pieces a far factor's blocks are taken in by
/// [`far_block_sums`]: its streams' pieces, three or four of them, stay
/// together in a 48 KiB L1 cache.
const PIECE: usize = 1024;
const _: () = assert!(BLOCK.is_multiple_of(PIECE) && PIECE.is_multiple_of(LANES));

/// Pieces ahead in [`far_block_sums`]' order whose leading stream is
/// asked for: two (a piece takes about a microsecond from memory).
const PIECES_AHEAD: usize = 2;

/// Whether [`sum_squared_overlapped_many`] takes factor m's whole blocks
/// from [`far_block_sums`]: when m is the one factor of the sweep (a
/// single τ), and a multiple of [`BLOCK`], so that each block's pieces
/// come in order.
///
/// With other factors beside it, block order is faster: they read the
/// stream at j for it, and an octave sweep's neighbours m and 2m share the
/// one at 2m, so such a sweep takes about one memory pass a factor.
/// Taken by residue, a factor reads the series on its own: an octave sweep
/// went 15 % slower, and lists such as 1, 16, 256, 4096 or a factor given
/// twice slower too.
fn is_far(m: usize, ms: &[usize]) -> bool {
    ms.len() == 1 && m >= BLOCK && m.is_multiple_of(BLOCK)
}

/// Blocks a run of [`far_block_sums`] takes at least: each run reads its
/// first two pieces of every residue without the reuse.
const MIN_FAR_RUN: usize = 16;

/// [`block_sum`] of every whole block of factor m (`is_far`), in block
/// order, the same bits, taken in another order; runs of blocks go in
/// parallel when `parallel`.
///
/// In block order the streams at j and j + m come back to data read as the
/// leading stream m and 2m points before: at m ≥ 2048 those are 16 KiB and
/// more behind, out of a 48 KiB L1 cache once three streams share it. Here
/// the pieces of [`PIECE`] points go by residue: piece p, then p + m/PIECE,
/// p + 2m/PIECE, …, where each piece's trailing streams are the leading
/// streams of the one or two before it, still in L1, and only the leading
/// stream comes from memory, asked for [`PIECES_AHEAD`] pieces ahead. A
/// block's lanes take its pieces in order (a block holds BLOCK/PIECE
/// consecutive residues, and m/PIECE is a multiple of that), so each block
/// sums as [`block_sum`] sums it; the blocks of a residue class of blocks
/// (g, g + m/BLOCK, …) are cut into runs of consecutive ones, for the
/// threads. Against whole blocks this saves about a third of a memory pass
/// at m = 4096 (`allan_per_tau 10000000 passes`, bench/README.md);
/// 512-point pieces, or three or four pieces ahead, did no better.
fn far_block_sums(order: Order, x: &[f64], m: usize, blocks: usize, parallel: bool) -> Vec<f64> {
    let per_block = BLOCK / PIECE;
    let stride = m / PIECE; // pieces between one and the next in the order
    let groups = m / BLOCK; // residue classes of blocks
    let lead = order.span() * m;
    // Blocks in class g, and runs of about 32 in all.
    let class = |g: usize| (blocks - g).div_ceil(groups);
    let span = class(0).div_ceil(32usize.div_ceil(groups)).max(MIN_FAR_RUN);
    let runs: Vec<(usize, usize)> = (0..groups.min(blocks))
        .flat_map(|g| (0..class(g)).step_by(span).map(move |t0| (g, t0)))
        .collect();
    // Blocks g + t·groups for t in t0 .. t0 + span.
    let run = |&(g, t0): &(usize, usize)| {
        let t1 = (t0 + span).min(class(g));
        let mut acc = vec![[0.0f64; LANES]; t1 - t0];
        for r in g * per_block..(g + 1) * per_block {
            for t in t0..t1 {
                let piece = r + t * stride;
                let next = (piece + PIECES_AHEAD * stride) * PIECE + lead;
                // Whole pieces leave no terms past the lanes.
                let this = Run {
                    order,
                    x,
                    j0: piece * PIECE,
                    len: PIECE,
                    m,
                    prefetch: next,
                };
                let rest = block_lanes(this, &mut acc[t - t0]);
                debug_assert_eq!(rest, 0.0);
            }
        }
        // block_sum then adds its empty rest, −0.0, which changes no sum.
        acc.iter().map(|a| a.iter().sum::<f64>()).collect::<Vec<f64>>()
    };
    let sums: Vec<Vec<f64>> = if parallel {
        runs.par_iter().map(run).collect()
    } else {
        runs.iter().map(run).collect()
    };
    let mut out = vec![0.0; blocks];
    for (&(g, t0), sums) in runs.iter().zip(sums) {
        for (t, sum) in (t0..).zip(sums) {
            out[g + t * groups] = sum;
        }
    }
    out
}

/// Points per block of [`sum_squared_overlapped_many`]: a block's windows at
/// every offset together stay within a core's L2 cache.
const BLOCK: usize = 2048;

/// Terms below which [`sum_squared_overlapped_many`] stays on the calling
/// thread: below it, handing work to other threads costs more than it saves.
const SMALL_SWEEP: usize = 1 << 18;

/// The overlapped sums of [`sum_squared`] (stride 1, no gaps) for many
/// averaging factors at once, in one blocked sweep over the data.
///
/// Computed one tau at a time, each factor streams the series from memory
/// three times (at offsets 0, m and 2m). Swept block by block with the
/// factors in increasing order, the window at 2m of one octave factor is the
/// window at m of the next, still in cache: for an octave grid the memory
/// traffic falls from three series per tau to about one. Runs of blocks go
/// in parallel, with the same result whatever the threads. A single factor
/// of 2048 or a multiple of it takes its whole blocks in another order,
/// with the same bits ([`is_far`], [`far_block_sums`]). Returns (sum,
/// terms) per factor, in the order of `ms`.
pub(crate) fn sum_squared_overlapped_many(x: &[f64], ms: &[usize], order: Order) -> Vec<(f64, usize)> {
    sweep(x, ms, order, is_far)
}

/// [`sum_squared_overlapped_many`], taking the whole blocks of the factors
/// `far` picks from [`far_block_sums`] (the tests pick none, for the
/// reference, or every one that can be).
fn sweep(x: &[f64], ms: &[usize], order: Order, far: fn(usize, &[usize]) -> bool) -> Vec<(f64, usize)> {
    let n = x.len();
    let reach = order.span();
    let terms: Vec<usize> = ms
        .iter()
        .map(|&m| if m == 0 { 0 } else { n.saturating_sub(reach * m) })
        .collect();
    let longest = terms.iter().copied().max().unwrap_or(0);
    let blocks = longest.div_ceil(BLOCK);
    // Blocks go to a number of runs that depends on the series and the grid
    // alone, each run summed in order and the runs' sums added in order: the
    // same bits whatever the threads (a fold split by work stealing would
    // change the last bits from run to run). At most 32 runs, and at most
    // 2^22 partial sums held at once.
    let runs = blocks.clamp(1, 32).min((1 << 22) / ms.len().max(1)).max(1);
    let per_run = blocks.div_ceil(runs).max(1);
    // A small sweep costs less than waking the thread pool; it runs here,
    // with the same runs in the same order.
    let small = terms.iter().sum::<usize>() < SMALL_SWEEP;
    // The far factors' whole blocks, each summed as block_sum sums it.
    let far_sums = |(&m, &t): (&usize, &usize)| {
        (m > 0 && far(m, ms) && t >= BLOCK).then(|| far_block_sums(order, x, m, t / BLOCK, !small))
    };
    let far_sums: Vec<Option<Vec<f64>>> = if small {
        ms.iter().zip(&terms).map(far_sums).collect()
    } else {
        ms.par_iter().zip(&terms).map(far_sums).collect()
    };
    let run = |r: usize| {
        let mut acc = vec![0.0; ms.len()];
        for b in r * per_run..((r + 1) * per_run).min(blocks) {
            let j0 = b * BLOCK;
            for (((slot, &m), &t), far) in acc.iter_mut().zip(ms).zip(&terms).zip(&far_sums) {
                let j1 = (j0 + BLOCK).min(t);
                if j0 >= j1 {
                    continue;
                }
                *slot += match far.as_ref().and_then(|f| f.get(b)) {
                    Some(&sum) => sum,
                    None => block_sum(order, x, j0, j1 - j0, m),
                };
            }
        }
        acc
    };
    let runs = blocks.div_ceil(per_run);
    let partial: Vec<Vec<f64>> = if small {
        (0..runs).map(run).collect()
    } else {
        (0..runs).into_par_iter().map(run).collect()
    };
    let mut sums = vec![0.0; ms.len()];
    for run in partial {
        sums.iter_mut().zip(run).for_each(|(s, p)| *s += p);
    }
    sums.into_iter().zip(terms).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The squared difference at j, as SP 1065 writes it.
    fn term(x: &[f64], j: usize, m: usize, order: Order) -> f64 {
        let v = match order {
            Order::Second => x[j + 2 * m] - 2.0 * x[j + m] + x[j],
            Order::Third => x[j + 3 * m] - 3.0 * x[j + 2 * m] + 3.0 * x[j + m] - x[j],
        };
        v * v
    }

    /// Small noise on a large offset: the differences ignore the offset,
    /// and formed from first differences (exact there, by Sterbenz) they
    /// round at the scale of the noise, so every form of the sums agrees
    /// with the same doubles with the offset taken off (exactly).
    #[test]
    fn a_large_offset_costs_no_digits() {
        let noise = crate::work::random_walk(20_000, 3);
        for (offset, scale) in [(0.0, 1.0), (1e2, 1e-9), (1e6, 1e-9), (1e4, 1e-6)] {
            let x: Vec<f64> = noise.iter().map(|v| offset + scale * (v - noise[0])).collect();
            let shifted: Vec<f64> = x.iter().map(|v| v - offset).collect();
            let (on, off) = (
                PhaseSeries::new(&x, crate::DataType::Phase, 1.0).unwrap(),
                PhaseSeries::new(&shifted, crate::DataType::Phase, 1.0).unwrap(),
            );
            for order in [Order::Second, Order::Third] {
                for m in [1, 2, 16, 2048] {
                    for terms in [Terms::Overlapped, Terms::NonOverlapped] {
                        let (got, _) = sum_squared(&on, m, terms, order);
                        let (want, _) = sum_squared(&off, m, terms, order);
                        assert!(
                            (got / want - 1.0).abs() < 1e-12,
                            "{order:?} offset {offset} m {m} {terms:?}: {got} vs {want}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn only_a_single_far_factor_is_taken_by_residue() {
        assert!(is_far(2048, &[2048]));
        assert!(is_far(3 * 2048, &[3 * 2048]));
        assert!(
            !is_far(4096, &[1, 16, 256, 4096]),
            "other factors read its streams"
        );
        assert!(!is_far(4096, &[4096, 4096]), "given twice");
        assert!(!is_far(3000, &[3000]), "not a multiple of BLOCK");
        assert!(!is_far(1024, &[1024]));
        let octave: Vec<usize> = (0..16).map(|k| 1 << k).collect();
        assert!(octave.iter().all(|&m| !is_far(m, &octave)));
    }

    /// Whatever the threads, the same bits: the sweep and the phase
    /// conversion on one thread and on three, on a series long enough for
    /// many blocks and several scan chunks, single far factors included.
    #[test]
    fn the_same_bits_on_any_number_of_threads() {
        let rate = crate::work::random_walk(300_000, 5);
        let ms: Vec<usize> = (1..2000).step_by(7).chain([2048, 4096, 8192]).collect();
        let on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let series = PhaseSeries::new(&rate, crate::DataType::Freq, 1.0).unwrap();
                let phase: Vec<u64> = series.points().iter().map(|v| v.to_bits()).collect();
                let sums: Vec<(u64, usize)> =
                    sum_squared_overlapped_many(series.points(), &ms, Order::Second)
                        .into_iter()
                        .map(|(s, n)| (s.to_bits(), n))
                        .collect();
                (phase, sums)
            })
        };
        let one = on(1);
        for _ in 0..3 {
            assert!(on(3) == one, "a three-thread run differs from the one-thread run");
        }
    }

    /// The decimated copy's bits at the strides with a copy of their own
    /// and beyond, on term counts around the chunk's and the lanes' edges:
    /// cases random draws reach only now and then.
    #[test]
    fn decimated_sums_at_chunk_edges() {
        for m in [2, 3, 4, 5, 8, 9] {
            for order in [Order::Second, Order::Third] {
                let span = order.span();
                for n in [1, 3, 4, 5, 63, 64, 65, 67, 127, 128, 129, 300] {
                    for extra in [0, m - 1] {
                        let len = (n - 1) * m + span * m + 1 + extra;
                        let x = crate::work::random_walk(len, (n * m) as u64);
                        let series = PhaseSeries::new(&x, crate::DataType::Phase, 1.0).unwrap();
                        let (got, terms) = sum_squared(&series, m, Terms::NonOverlapped, order);
                        assert_eq!(terms, n, "{order:?} m {m} len {len}");
                        let want = strided_loop(&x, m, n, order);
                        assert_eq!(got.to_bits(), want.to_bits(), "{order:?} m {m} n {n}");
                    }
                }
            }
        }
    }

    /// The non-overlapped sum as one strided loop with four accumulators,
    /// the tail summed on its own: the form the decimated copy replaced.
    fn strided_loop(x: &[f64], m: usize, n: usize, order: Order) -> f64 {
        let term = |j: usize| {
            let v = difference(x, j, m, order);
            v * v
        };
        let mut acc = [0.0f64; 4];
        let whole = n - n % 4;
        for k in (0..whole).step_by(4) {
            for (l, slot) in acc.iter_mut().enumerate() {
                *slot += term((k + l) * m);
            }
        }
        let tail: f64 = (whole..n).map(|k| term(k * m)).sum();
        crate::lanes::join(acc, tail)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// Whatever the CPU, the same bits: the dispatched block sum (AVX2
        /// where the CPU has it) against the portable one, on random walks of
        /// any length and step, in both orders.
        #[test]
        fn every_block_sum_gives_the_same_bits(len in 4usize..6000, m_seed in 0usize..2000, seed in 0u64..1000) {
            let x = crate::work::random_walk(len, seed);
            for order in [Order::Second, Order::Third] {
                let m = 1 + m_seed % (len / (order.span() + 1)).max(1);
                if order.span() * m >= len {
                    continue;
                }
                let terms = len - order.span() * m;
                let mut acc = [0.0; LANES];
                let run = Run { order, x: &x, j0: 0, len: terms, m, prefetch: 0 };
                let rest = block_lanes_portable(run, &mut acc);
                prop_assert_eq!(
                    block_sum(order, &x, 0, terms, m).to_bits(),
                    (acc.iter().sum::<f64>() + rest).to_bits()
                );
            }
        }

        /// One factor at a time equals the blocked sweep over many, and both
        /// equal the definition to rounding.
        #[test]
        fn one_factor_equals_the_sweep_and_the_definition(len in 4usize..6000, seed in 0u64..1000) {
            let x = crate::work::random_walk(len, seed);
            let series = PhaseSeries::new(&x, crate::DataType::Phase, 1.0).unwrap();
            let ms: Vec<usize> = (0..12).map(|k| 1usize << k).filter(|&m| 3 * m < len).collect();
            for order in [Order::Second, Order::Third] {
                let swept = sum_squared_overlapped_many(&x, &ms, order);
                for (&m, &(sum, n)) in ms.iter().zip(&swept) {
                    if order.span() * m >= len {
                        continue;
                    }
                    prop_assert_eq!(sum_squared(&series, m, Terms::Overlapped, order), (sum, n));
                    let direct: f64 = (0..len - order.span() * m).map(|j| term(&x, j, m, order)).sum();
                    prop_assert!(((sum - direct) / direct).abs() < 1e-12, "m={} {} vs {}", m, sum, direct);
                }
            }
        }

        /// Far factors' blocks taken by residue give the bits of block
        /// order, in both orders, alone and with other factors beside
        /// them, on series that end anywhere in a block and hold one to
        /// many residues and runs.
        #[test]
        fn far_factors_give_the_bits_of_block_order(
            len in 3 * BLOCK + 1..40 * BLOCK,
            seed in 0u64..1000,
            threads in 1usize..4,
        ) {
            let x = crate::work::random_walk(len, seed);
            let ms: Vec<usize> = [1, 7, 1000, BLOCK - 1, BLOCK, BLOCK + 1, 2 * BLOCK, 3 * BLOCK, 4 * BLOCK, 8 * BLOCK]
                .into_iter()
                .filter(|&m| 2 * m < len)
                .collect();
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            for order in [Order::Second, Order::Third] {
                let bits = |ms: &[usize], far: fn(usize, &[usize]) -> bool| -> Vec<(u64, usize)> {
                    pool.install(|| sweep(&x, ms, order, far))
                        .into_iter()
                        .map(|(s, n)| (s.to_bits(), n))
                        .collect()
                };
                // Every multiple of BLOCK, with other factors beside it.
                let every = |m: usize, _: &[usize]| m >= BLOCK && m.is_multiple_of(BLOCK);
                let want = bits(&ms, |_, _| false);
                prop_assert_eq!(bits(&ms, every), want, "{:?} len {}", order, len);
                // Each factor alone, as is_far takes it.
                for &m in &ms {
                    prop_assert_eq!(bits(&[m], is_far), bits(&[m], |_, _| false), "{:?} m {} len {}", order, m, len);
                }
            }
        }

        /// The decimated copy gives the bits of the strided loop with four
        /// accumulators it replaced.
        #[test]
        fn decimated_sums_give_the_strided_loops_bits(len in 4usize..6000, m_seed in 1usize..500, seed in 0u64..1000) {
            let x = crate::work::random_walk(len, seed);
            let m = 1 + m_seed % (len / 4).max(1);
            for order in [Order::Second, Order::Third] {
                if order.span() * m >= len {
                    continue;
                }
                let n = (len - 1 - order.span() * m) / m + 1;
                let strided = strided_loop(&x, m, n, order);
                prop_assert_eq!(decimated_sum(&x, m, n, order).to_bits(), strided.to_bits(), "{:?} m {} len {}", order, m, len);
            }
        }

        /// The non-overlapped sums' four accumulators against one running sum.
        #[test]
        fn strided_sums_equal_the_definition(len in 4usize..6000, m_seed in 1usize..500, seed in 0u64..1000) {
            let x = crate::work::random_walk(len, seed);
            let series = PhaseSeries::new(&x, crate::DataType::Phase, 1.0).unwrap();
            let m = 1 + m_seed % (len / 4).max(1);
            for order in [Order::Second, Order::Third] {
                if order.span() * m >= len {
                    continue;
                }
                let (sum, n) = sum_squared(&series, m, Terms::NonOverlapped, order);
                let starts = (0..len - order.span() * m).step_by(m);
                let direct: f64 = starts.clone().map(|j| term(&x, j, m, order)).sum();
                prop_assert_eq!(n, starts.count());
                prop_assert!(((sum - direct) / direct).abs() < 1e-12, "m={} {} vs {}", m, sum, direct);
            }
        }
    }
}
