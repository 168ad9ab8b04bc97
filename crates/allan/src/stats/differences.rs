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
        None if stride == 1 => {
            // Overlapped, no gaps: the hot path, written as zipped slices so
            // the compiler can vectorise it.
            let n = last + 1;
            let sum = match order {
                Order::Second => x[..n]
                    .iter()
                    .zip(&x[m..m + n])
                    .zip(&x[2 * m..2 * m + n])
                    .map(|((a, b), c)| {
                        let v = c - 2.0 * b + a;
                        v * v
                    })
                    .sum(),
                Order::Third => x[..n]
                    .iter()
                    .zip(&x[m..m + n])
                    .zip(&x[2 * m..2 * m + n])
                    .zip(&x[3 * m..3 * m + n])
                    .map(|(((a, b), c), d)| {
                        let v = d - 3.0 * c + 3.0 * b - a;
                        v * v
                    })
                    .sum(),
            };
            (sum, n)
        }
        None => {
            let mut sum = 0.0;
            let mut n = 0;
            for j in (0..=last).step_by(stride) {
                let v = term(j);
                sum += v * v;
                n += 1;
            }
            (sum, n)
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

/// Σ f(i) for i < len, in eight interleaved accumulators: one running sum
/// would wait on every addition's latency (floating-point addition is not
/// reassociated by the compiler); eight independent ones keep the vector
/// units busy. It also rounds less than one long sum.
#[inline]
fn lanes_sum(len: usize, f: impl Fn(usize) -> f64) -> f64 {
    let mut acc = [0.0f64; 8];
    let whole = len - len % 8;
    let mut i = 0;
    while i < whole {
        for (k, slot) in acc.iter_mut().enumerate() {
            *slot += f(i + k);
        }
        i += 8;
    }
    let tail: f64 = (whole..len).map(&f).sum();
    acc.iter().sum::<f64>() + tail
}

/// Points per block of [`sum_squared_overlapped_many`]: a block's windows at
/// every offset together stay within a core's L2 cache.
const BLOCK: usize = 2048;

/// The overlapped sums of [`sum_squared`] (stride 1, no gaps) for many
/// averaging factors at once, in one blocked sweep over the data.
///
/// Computed one tau at a time, each factor streams the series from memory
/// three times (at offsets 0, m and 2m). Swept block by block with the
/// factors in increasing order, the window at 2m of one octave factor is the
/// window at m of the next, still in cache: for an octave grid the memory
/// traffic falls from three series per tau to about one. Blocks run in
/// parallel. Returns (sum, terms) per factor, in the order of `ms`.
pub(crate) fn sum_squared_overlapped_many(x: &[f64], ms: &[usize], order: Order) -> Vec<(f64, usize)> {
    let n = x.len();
    let reach = order.span();
    let terms: Vec<usize> = ms
        .iter()
        .map(|&m| if m == 0 { 0 } else { n.saturating_sub(reach * m) })
        .collect();
    let longest = terms.iter().copied().max().unwrap_or(0);
    let blocks = longest.div_ceil(BLOCK);
    let sums = (0..blocks)
        .into_par_iter()
        .fold(
            || vec![0.0; ms.len()],
            |mut acc, b| {
                let j0 = b * BLOCK;
                for ((slot, &m), &t) in acc.iter_mut().zip(ms).zip(&terms) {
                    let j1 = (j0 + BLOCK).min(t);
                    if j0 >= j1 {
                        continue;
                    }
                    let len = j1 - j0;
                    let a = &x[j0..j1];
                    let b1 = &x[j0 + m..j0 + m + len];
                    let c = &x[j0 + 2 * m..j0 + 2 * m + len];
                    *slot += match order {
                        Order::Second => lanes_sum(len, |i| {
                            let v = c[i] - 2.0 * b1[i] + a[i];
                            v * v
                        }),
                        Order::Third => {
                            let d = &x[j0 + 3 * m..j0 + 3 * m + len];
                            lanes_sum(len, |i| {
                                let v = d[i] - 3.0 * c[i] + 3.0 * b1[i] - a[i];
                                v * v
                            })
                        }
                    };
                }
                acc
            },
        )
        .reduce(
            || vec![0.0; ms.len()],
            |mut a, b| {
                a.iter_mut().zip(b).for_each(|(x, y)| *x += y);
                a
            },
        );
    sums.into_iter().zip(terms).collect()
}
