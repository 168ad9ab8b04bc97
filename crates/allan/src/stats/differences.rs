//! Sums of squared finite differences of phase: the kernel under ADEV and
//! HDEV in all their overlapped and non-overlapped forms.
//!
//! Each averaging factor costs one pass over the phase points that its terms
//! touch (O(N/stride)), with no intermediate arrays.

use rayon::prelude::*;

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
}

/// Σ over j = 0, s, 2s, … of the squared `order`-th difference of phase at
/// step m, and the number of terms. Terms that cross a gap are skipped.
pub(crate) fn sum_squared(series: &PhaseSeries, m: usize, stride: usize, order: Order) -> (f64, usize) {
    let x = series.points();
    let reach = order.span() * m;
    if m == 0 || stride == 0 || x.len() <= reach {
        return (0.0, 0);
    }
    let last = x.len() - 1 - reach; // largest valid j
    let term = |j: usize| -> f64 {
        match order {
            Order::Second => x[j + 2 * m] - 2.0 * x[j + m] + x[j],
            Order::Third => x[j + 3 * m] - 3.0 * x[j + 2 * m] + 3.0 * x[j + m] - x[j],
        }
    };
    match series.gap_index() {
        // Overlapped, no gaps: the hot path, the one-factor case of the
        // blocked sweep, so a curve computed factor by factor equals the
        // one swept at once.
        None if stride == 1 => sum_squared_overlapped_many(x, &[m], order)[0],
        None => {
            // Four interleaved sums: with one, each term would wait on the
            // previous addition while the strided reads could run ahead.
            let n = last / stride + 1;
            let mut acc = [0.0f64; 4];
            let whole = n - n % 4;
            for k in (0..whole).step_by(4) {
                for (l, slot) in acc.iter_mut().enumerate() {
                    let v = term((k + l) * stride);
                    *slot += v * v;
                }
            }
            let tail: f64 = (whole..n)
                .map(|k| {
                    let v = term(k * stride);
                    v * v
                })
                .sum();
            (crate::lanes::join(acc, tail), n)
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
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the one requirement for calling a function compiled with
        // `target_feature(enable = "avx2")` is a CPU that has AVX2, which
        // was just detected.
        return unsafe { block_sum_avx2(order, x, j0, len, m) };
    }
    block_sum_portable(order, x, j0, len, m)
}

/// [`block_sum_portable`] compiled for AVX2: four lanes to an instruction
/// instead of two, with the same operations in the same order.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn block_sum_avx2(order: Order, x: &[f64], j0: usize, len: usize, m: usize) -> f64 {
    block_sum_portable(order, x, j0, len, m)
}

#[inline(always)]
fn block_sum_portable(order: Order, x: &[f64], j0: usize, len: usize, m: usize) -> f64 {
    let a = &x[j0..j0 + len];
    let b = &x[j0 + m..j0 + m + len];
    let c = &x[j0 + 2 * m..j0 + 2 * m + len];
    // The stream at the difference's far end is the one from memory.
    let lead = j0 + order.span() * m;
    let mut acc = [0.0f64; LANES];
    let whole = len - len % LANES;
    let tail = match order {
        Order::Second => {
            let term = |a: f64, b: f64, c: f64| {
                let v = c - 2.0 * b + a;
                v * v
            };
            for (i, ((a, b), c)) in a[..whole]
                .chunks_exact(LANES)
                .zip(b[..whole].chunks_exact(LANES))
                .zip(c[..whole].chunks_exact(LANES))
                .enumerate()
            {
                crate::prefetch::ahead(x, lead + i * LANES);
                for k in 0..LANES {
                    acc[k] += term(a[k], b[k], c[k]);
                }
            }
            (whole..len).map(|i| term(a[i], b[i], c[i])).sum::<f64>()
        }
        Order::Third => {
            let d = &x[j0 + 3 * m..j0 + 3 * m + len];
            let term = |a: f64, b: f64, c: f64, d: f64| {
                let v = d - 3.0 * c + 3.0 * b - a;
                v * v
            };
            for (i, (((a, b), c), d)) in a[..whole]
                .chunks_exact(LANES)
                .zip(b[..whole].chunks_exact(LANES))
                .zip(c[..whole].chunks_exact(LANES))
                .zip(d[..whole].chunks_exact(LANES))
                .enumerate()
            {
                crate::prefetch::ahead(x, lead + i * LANES);
                for k in 0..LANES {
                    acc[k] += term(a[k], b[k], c[k], d[k]);
                }
            }
            (whole..len).map(|i| term(a[i], b[i], c[i], d[i])).sum::<f64>()
        }
    };
    acc.iter().sum::<f64>() + tail
}

/// Points per block of [`sum_squared_overlapped_many`]: a block's windows at
/// every offset together stay within a core's L2 cache.
const BLOCK: usize = 2048;

/// Terms below which [`sum_squared_overlapped_many`] stays on the calling
/// thread (about 0.1 ms of work).
const SMALL_SWEEP: usize = 1 << 18;

/// The overlapped sums of [`sum_squared`] (stride 1, no gaps) for many
/// averaging factors at once, in one blocked sweep over the data.
///
/// Computed one tau at a time, each factor streams the series from memory
/// three times (at offsets 0, m and 2m). Swept block by block with the
/// factors in increasing order, the window at 2m of one octave factor is the
/// window at m of the next, still in cache: for an octave grid the memory
/// traffic falls from three series per tau to about one. Runs of blocks go
/// in parallel, with the same result whatever the threads. Returns (sum,
/// terms) per factor, in the order of `ms`.
pub(crate) fn sum_squared_overlapped_many(x: &[f64], ms: &[usize], order: Order) -> Vec<(f64, usize)> {
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
    let run = |r: usize| {
        let mut acc = vec![0.0; ms.len()];
        for b in r * per_run..((r + 1) * per_run).min(blocks) {
            let j0 = b * BLOCK;
            for ((slot, &m), &t) in acc.iter_mut().zip(ms).zip(&terms) {
                let j1 = (j0 + BLOCK).min(t);
                if j0 >= j1 {
                    continue;
                }
                *slot += block_sum(order, x, j0, j1 - j0, m);
            }
        }
        acc
    };
    let runs = blocks.div_ceil(per_run);
    // A small sweep costs less than waking the thread pool; it runs here,
    // with the same runs in the same order.
    let partial: Vec<Vec<f64>> = if terms.iter().sum::<usize>() < SMALL_SWEEP {
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

    /// Whatever the threads, the same bits: the sweep and the phase
    /// conversion on one thread and on three, on a series long enough for
    /// many blocks and several scan chunks.
    #[test]
    fn the_same_bits_on_any_number_of_threads() {
        let rate = crate::work::random_walk(300_000, 5);
        let ms: Vec<usize> = (1..2000).step_by(7).collect();
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
                prop_assert_eq!(
                    block_sum(order, &x, 0, terms, m).to_bits(),
                    block_sum_portable(order, &x, 0, terms, m).to_bits()
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
                    prop_assert_eq!(sum_squared(&series, m, 1, order), (sum, n));
                    let direct: f64 = (0..len - order.span() * m).map(|j| term(&x, j, m, order)).sum();
                    prop_assert!(((sum - direct) / direct).abs() < 1e-12, "m={} {} vs {}", m, sum, direct);
                }
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
                let (sum, n) = sum_squared(&series, m, m, order);
                let starts = (0..len - order.span() * m).step_by(m);
                let direct: f64 = starts.clone().map(|j| term(&x, j, m, order)).sum();
                prop_assert_eq!(n, starts.count());
                prop_assert!(((sum - direct) / direct).abs() < 1e-12, "m={} {} vs {}", m, sum, direct);
            }
        }
    }
}
