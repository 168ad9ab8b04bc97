//! Modified total deviation (MTOTDEV) and time total deviation (TTOTDEV),
//! NIST SP 1065 eqs. 27 and 28 (Howe & Vernotte 1999).
//!
//! # Definition
//!
//! MDEV at long τ rests on few independent terms. MTOT keeps the modified
//! Allan second difference but evaluates it on reflected copies of the data,
//! so every τ up to N/3 uses all N − 3m + 1 windows (SP 1065 eq. 27): for
//! each subsequence of 3m phase points x_n … x_{n+3m−1},
//!
//! 1. remove the linear trend through the means of its first and last
//!    halves (the "half-average" frequency offset; the halves share nothing
//!    and, for odd 3m, skip the middle point);
//! 2. extend the residual at both ends by uninverted even reflection to
//!    9m points x#;
//! 3. average the 6m squared second differences of m-point means,
//!    (x̄#_{i+2m} − 2x̄#_{i+m} + x̄#_i)², over that extension.
//!
//! Mod Totvar(τ) = 1/(2τ²(N−3m+1)) Σ_n 1/(6m) Σ_i (x̄#_{i+2m} − 2x̄#_{i+m} + x̄#_i)²,
//! τ = m·τ0, and TTOT = τ²/3 · Mod Totvar (eq. 28 as AllanTools reads it:
//! the printed τ³ there is a misprint).
//!
//! # Bias
//!
//! The deviations returned are **not** bias-corrected: Stable32 1.60 and
//! AllanTools 2024.6 print them so, and the reference tables are written that
//! way. SP 1065 Table 30/31 publish MTOT and TTOT divided by
//! √[`MTOTVAR_BIAS`] (the white-FM value 0.73); a caller who wants the
//! published numbers divides by that root.
//!
//! # Computation and cost
//!
//! A second difference of m-point sums is a lag-m third difference of
//! partial sums, and the partial sums of an evenly reflected sequence are
//! the odd extension of the window's own partial sums about the fold. So
//! each window needs only its 3m + 1 partial sums, the trend removal
//! reduces to its slope times a fixed quadratic weight, and the 9m-point
//! extension is never built (`Folds::block`). The extension is even and
//! 6m-periodic and the filter symmetric, so the 6m positions come in equal
//! pairs: 3m are evaluated. Windows are taken 256 at a time, position by
//! position, so that every pass reads contiguous phase streams and
//! vectorises.
//!
//! Per τ: O((N − 3m + 1)·m) time (the direct 6m-term sum with running
//! window sums took about four times the folded form's time; the cost per
//! window and unit of m is measured by `allan_per_tau`, bench/README.md);
//! O(m) scratch (256 + 3m
//! partial sums and 3 × 256 per-window values), no copy of the series.
//! Over a tau grid reaching N/3 that is still O(N²).
//!
//! # What prefix sums can and cannot carry
//!
//! Written out, a window's sum Σ_i (third difference of the folded partial
//! sums)² splits into three kinds of term:
//!
//! - the trend's own square, s²·Σ_j g_j²: the half-average slope s is a
//!   difference of two window sums, O(1) from prefix sums of x, and Σ g_j²
//!   depends on m alone;
//! - the cross terms s·Σ_j g_j·D_j, with D_j a fixed ±1 combination of
//!   partial sums at positions k + j, k + m − j, k + 2m − j …: a linear form
//!   in the window with weights polynomial in the position, so O(1) per
//!   window from prefix sums of x, i·x, i²·x and i³·x;
//! - the squares Σ_j D_j², which mix x(k + j) with x(k + m − j) (and the
//!   other folds) inside one square. These are what no running sum carries,
//!   as the next section shows; they alone make the cost O(m) per window.
//!
//! # Why not below O(N·m) per τ
//!
//! Only one of the 6m positions of the 9m-point extension lies wholly
//! inside the window; every other one straddles a fold, where the
//! reflection pairs a sample at k with one at m − k, 2m − k or 3m − k.
//! Expanded, a window's sum holds terms such as Σ_k P_b(k)·P_b(m − k), a
//! convolution of the window with itself about a fixed point. Window b + 1
//! moves that point by two samples, so its sum shares no product with
//! window b's: no running sum carries it, and a sliding window costs O(m)
//! per window, the cost above.
//!
//! Summed over all windows instead, those products regroup by lag into the
//! lagged products Σ_u q_u·q_{u+d} of the series' partial sums for about
//! 3m lags d, with weights piecewise polynomial in d (up to degree 4, from
//! the trend term s·g_j). Prefix moments Σ k^p·q_k, or FFT correlations,
//! would then give O(N) or O(N log N) per τ; but they square before they
//! difference. The result becomes a difference of products of partial
//! sums, which for white FM are larger than it by about (N/m)³ (more with
//! a frequency offset or drift), and a double loses that factor in
//! relative precision: at N = 10^6 and m = 16, 2·10^14, leaving about
//! two digits where the tests hold eleven against the straightforward sum
//! and nine against AllanTools. Forming each window's differences before squaring,
//! as here, is what keeps it, and costs O(m) per window. Regrouping the
//! products of the phase or of the rates instead of the partial sums only
//! moves the problem: it shrinks the factor for the noise whose
//! differences are white, but for random-walk FM the rates themselves
//! wander and their products again exceed the result by a power of N/m.

use super::Estimate;

/// SP 1065's variance bias of MTOT for white FM noise (Howe & Vernotte;
/// SP 1065 Table 30/31): published MTOTDEV = [`mtotdev`] / √0.73.
pub const MTOTVAR_BIAS: f64 = 0.73;

/// SP 1065's variance bias of TTOT, the same as [`MTOTVAR_BIAS`] because
/// TTOT is MTOT scaled by τ/√3: published TTOTDEV = [`ttotdev`] / √0.73.
pub const TTOTVAR_BIAS: f64 = MTOTVAR_BIAS;

/// Whether `tau0` is a usable sampling interval.
pub(crate) fn valid_tau0(tau0: f64) -> bool {
    tau0.is_finite() && tau0 > 0.0
}

/// Windows evaluated together: each window position is one pass over
/// this many windows, reading its phase streams contiguously from cache.
const BLOCK: usize = 256;

/// The folded evaluation of SP 1065 eqs. 27 and 29 for a block of
/// consecutive windows, with its per-window scratch ([`BLOCK`] slopes and
/// two [`BLOCK`]-long accumulators). Shared by MTOT (phase windows) and
/// HTOT (rate windows, whose partial sums are phase points).
pub(crate) struct Folds {
    slope: Vec<f64>,
    pairs: Vec<f64>,
    middle: Vec<f64>,
}

impl Folds {
    /// The largest number of windows one [`Folds::block`] call takes.
    pub(crate) const BLOCK: usize = BLOCK;

    /// Scratch for one block.
    pub(crate) fn new() -> Folds {
        Folds {
            slope: vec![0.0; BLOCK],
            pairs: vec![0.0; BLOCK],
            middle: vec![0.0; BLOCK],
        }
    }

    /// Σ over windows b = 0 … len−1 (len ≤ [`BLOCK`]) of the sum, over the
    /// 6m positions, of the squared second difference of m-point **sums**
    /// on the detrended, reflected 9m-point extension of window b (SP 1065
    /// eqs. 27 and 29, steps 1–3; divide by m² for means). Window b holds
    /// 3m values given by their partial sums P_b(k) = q[b+k] − q[b],
    /// k = 0 … 3m, so `q` has at least len + 3m entries. A term linear in
    /// k may be added to P_b (a constant added to the values): the trend
    /// removal takes it out.
    ///
    /// Trend removal subtracts a + s·k from the values, s the slope between
    /// the means of the first and last ⌊3m/2⌋ values, which lie ⌈3m/2⌉
    /// samples apart; on the partial sums that is a·k + s·k(k−1)/2. The
    /// a·k part has no third difference, so only s enters.
    ///
    /// The second difference of m-sums of the extension is the lag-m third
    /// difference of its partial sums, and the partial sums of an evenly
    /// reflected sequence are the odd extension F of P about the fold
    /// (F(−k) = −P(k)). At the left fold the 6m positions give
    /// w_j = F(j) − 3F(j−m) + 3F(j−2m) − F(j−3m), and position j equals
    /// position 3m − j (the extension is even and 6m-periodic, the filter
    /// symmetric): j ∈ [0, ⌈3m/2⌉) counts twice, j = 3m/2 (3m even) once.
    /// The right fold is the left fold of the reversed window, with partial
    /// sums P(3m) − P(3m − k), without its position 0 (the left fold's).
    /// The trend's k(k−1)/2 contributes s·g_j, g_j = j² below j = m and
    /// 1.5m² − 2(j − 1.5m)² above, subtracted at the left fold and added at
    /// the right one.
    pub(crate) fn block(&mut self, q: &[f64], m: usize, len: usize) -> f64 {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx512f") {
            // SAFETY: as below, for AVX-512F, just detected.
            return unsafe { self.block_avx512(q, m, len) };
        }
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the one requirement for calling a function compiled
            // with `target_feature(enable = "avx2")` is a CPU that has
            // AVX2, which was just detected.
            return unsafe { self.block_avx2(q, m, len) };
        }
        self.block_portable(q, m, len)
    }

    /// [`Folds::block_portable`] compiled for AVX2: the window-by-window
    /// loops four windows to an instruction instead of two, with the same
    /// operations in the same order (no fused multiply-add), so the same
    /// result bit for bit.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn block_avx2(&mut self, q: &[f64], m: usize, len: usize) -> f64 {
        self.block_portable(q, m, len)
    }

    /// [`Folds::block_portable`] compiled for AVX-512: eight windows to an
    /// instruction. The lanes are windows, and each window's sum takes its
    /// positions in the same order at any width, so the bits are the same.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f")]
    fn block_avx512(&mut self, q: &[f64], m: usize, len: usize) -> f64 {
        self.block_portable(q, m, len)
    }

    #[inline(always)]
    fn block_portable(&mut self, q: &[f64], m: usize, len: usize) -> f64 {
        let l = 3 * m;
        let h1 = l / 2;
        let h2 = l - h1;
        let half = l.div_ceil(2);
        let slope = &mut self.slope[..len];
        let pairs = &mut self.pairs[..len];
        let middle = &mut self.middle[..len];
        let at = |offset: usize| &q[offset..offset + len];
        let (start, end) = (at(0), at(l));
        let span = h1 as f64 * h2 as f64;
        for ((((s, &p0), &pl), &a), &b) in slope.iter_mut().zip(start).zip(end).zip(at(h1)).zip(at(h2)) {
            *s = ((pl - b) - (a - p0)) / span;
        }
        let slope = &*slope;
        pairs.fill(0.0);
        middle.fill(0.0);
        let (mf, centre) = (m as f64, 1.5 * m as f64);
        let above = |j: usize| {
            let u = j as f64 - centre;
            1.5 * mf * mf - 2.0 * u * u
        };
        let taps = |j: usize| {
            [
                at(j),
                at(m - j),
                at(2 * m - j),
                at(l - j),
                at(2 * m + j),
                at(m + j),
            ]
        };
        // Position 0 belongs to the left fold only (g_0 = 0).
        positions::<false, false>(pairs, start, end, slope, taps(0), 0.0);
        for j in 1..m {
            let g = (j as f64) * (j as f64);
            positions::<false, true>(pairs, start, end, slope, taps(j), g);
        }
        let taps = |j: usize| {
            [
                at(j),
                at(j - m),
                at(2 * m - j),
                at(l - j),
                at(4 * m - j),
                at(m + j),
            ]
        };
        for j in m..half {
            positions::<true, true>(pairs, start, end, slope, taps(j), above(j));
        }
        if l.is_multiple_of(2) {
            positions::<true, true>(middle, start, end, slope, taps(l / 2), above(l / 2));
        }
        2.0 * pairs.iter().sum::<f64>() + middle.iter().sum::<f64>()
    }
}

/// Adds, window by window, w_j² of the left fold and (if `RIGHT`) of the
/// right fold to `acc` (see [`Folds::block`]). The taps are the partial
/// sums at offsets [j, m−j, 2m−j, 3m−j, 2m+j, m+j] below j = m and
/// [j, j−m, 2m−j, 3m−j, 4m−j, m+j] (`ABOVE`) from j = m on. Relative to the
/// window start p0 (left: u = q − p0) or from the window end pl (right:
/// v = pl − q, the reversed window's partial sums):
///
/// - below: w = u_j + u_{3m−j} + 3(u_{m−j} − u_{2m−j}) − s·g, and
///   v_{3m−j} + v_j + 3(v_{2m+j} − v_{m+j}) + s·g;
/// - above: w = u_j + u_{3m−j} − 3(u_{j−m} + u_{2m−j}) − s·g, and
///   v_{3m−j} + v_j − 3(v_{4m−j} + v_{m+j}) + s·g.
///
/// Each tap is first taken relative to the window's first or last partial
/// sum, which keeps digits when the data carry a large offset.
#[inline(always)]
fn positions<const ABOVE: bool, const RIGHT: bool>(
    acc: &mut [f64],
    start: &[f64],
    end: &[f64],
    slope: &[f64],
    [a, b, c, d, e, f]: [&[f64]; 6],
    g: f64,
) {
    let fold = |outer: f64, b: f64, c: f64| {
        if ABOVE {
            outer - 3.0 * (b + c)
        } else {
            outer + 3.0 * (b - c)
        }
    };
    let ends = start.iter().zip(end).zip(slope);
    let taps = a.iter().zip(d).zip(b.iter().zip(c)).zip(e.iter().zip(f));
    for ((acc, ((&p0, &pl), &s)), (((&a, &d), (&b, &c)), (&e, &f))) in acc.iter_mut().zip(ends).zip(taps) {
        let left = fold((a - p0) + (d - p0), b - p0, c - p0) - g * s;
        *acc += left * left;
        if RIGHT {
            let right = fold((pl - a) + (pl - d), pl - e, pl - f) + g * s;
            *acc += right * right;
        }
    }
}

/// Compensated (Neumaier) running sum, so long series lose no digits to
/// the order of the outer sum.
#[derive(Default)]
pub(crate) struct Sum {
    sum: f64,
    carry: f64,
}

impl Sum {
    /// Adds one term.
    pub(crate) fn add(&mut self, v: f64) {
        let t = self.sum + v;
        if self.sum.abs() >= v.abs() {
            self.carry += (self.sum - t) + v;
        } else {
            self.carry += (v - t) + self.sum;
        }
        self.sum = t;
    }

    /// The sum so far.
    pub(crate) fn value(&self) -> f64 {
        self.sum + self.carry
    }
}

/// Modified total deviation at averaging factor m, τ = m·τ0 (NIST SP 1065
/// eq. 27), **without** the white-FM bias correction (as Stable32 1.60 and
/// AllanTools 2024.6 print it; divide by √[`MTOTVAR_BIAS`] for SP 1065's
/// published values).
///
/// `n` is the number of 3m-point subsequences, N − 3m + 1, as AllanTools
/// and Stable32 report it. Returns `None` when m = 0, 3m > N, τ0 is not a
/// positive finite number or a phase point is not finite. A single
/// subsequence (3m = N) is returned; AllanTools drops one-term results, so
/// the caller's tau grid decides whether to show it.
///
/// Cost O((N − 3m + 1)·m) time and O(m) scratch (see the module notes).
pub fn mtotdev(phase: &[f64], m: usize, tau0: f64) -> Option<Estimate> {
    mtotdev_with_progress(phase, m, tau0, &|_| {})
}

/// [`mtotdev`], reporting its work as it goes: `progress` receives the
/// windows × m done since its last call, in blocks of 256 windows, so the
/// calls add up to [`crate::work::operations`] for the statistic.
pub fn mtotdev_with_progress(phase: &[f64], m: usize, tau0: f64, progress: &dyn Fn(u64)) -> Option<Estimate> {
    let n = phase.len();
    let len = m.checked_mul(3)?;
    if m == 0 || len > n || !valid_tau0(tau0) || !phase.iter().all(|v| v.is_finite()) {
        return None;
    }
    let terms = n - len + 1;
    let mut folds = Folds::new();
    // Partial sums of a block of windows, relative to its first point.
    let mut q = Vec::with_capacity(Folds::BLOCK + len);
    let mut sum = Sum::default();
    for first in (0..terms).step_by(Folds::BLOCK) {
        let count = Folds::BLOCK.min(terms - first);
        let x0 = phase[first];
        q.clear();
        q.push(0.0);
        let mut acc = 0.0;
        for &v in &phase[first..first + count + len - 1] {
            acc += v - x0;
            q.push(acc);
        }
        sum.add(folds.block(&q, m, count));
        progress((count * m) as u64);
    }
    // Σ_n Σ_i (m-sum difference)² / (m² · 6m · 2 (mτ0)² · (N − 3m + 1)).
    let mf = m as f64;
    let var = sum.value() / (12.0 * mf.powi(5) * tau0 * tau0 * terms as f64);
    let dev = var.sqrt();
    dev.is_finite().then_some(Estimate { dev, n: terms })
}

/// Time total deviation at averaging factor m: τ·MTOTDEV/√3 with τ = m·τ0
/// (NIST SP 1065 eq. 28; TTOT is to MTOT what TDEV is to MDEV), **without**
/// the bias correction (divide by √[`TTOTVAR_BIAS`] for SP 1065's published
/// values). In the unit of the phase. `n` and `None` as [`mtotdev`].
pub fn ttotdev(phase: &[f64], m: usize, tau0: f64) -> Option<Estimate> {
    ttotdev_with_progress(phase, m, tau0, &|_| {})
}

/// [`ttotdev`], reporting its work as [`mtotdev_with_progress`] does.
pub fn ttotdev_with_progress(phase: &[f64], m: usize, tau0: f64, progress: &dyn Fn(u64)) -> Option<Estimate> {
    let e = mtotdev_with_progress(phase, m, tau0, progress)?;
    let tau = m as f64 * tau0;
    Some(Estimate {
        dev: tau * e.dev / 3f64.sqrt(),
        n: e.n,
    })
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// `|value − printed| ≤` half a unit of the last of `digits` significant
    /// digits of `printed`: a table value matched to the digits it shows.
    pub(crate) fn matches_printed(value: f64, printed: f64, digits: i32) -> bool {
        let unit = 10f64.powi(printed.abs().log10().floor() as i32 - digits + 1);
        (value - printed).abs() <= 0.5 * unit * (1.0 + 1e-9)
    }

    /// Relative error of `value` against `want`.
    pub(crate) fn rel(value: f64, want: f64) -> f64 {
        ((value - want) / want).abs()
    }

    /// SP 1065 Table 30 input (9 frequency values, τ0 = 1) as phase,
    /// x = [0, cumsum(y − ȳ)].
    pub(crate) fn nbs14_10_phase() -> Vec<f64> {
        let y = [892.0, 809.0, 823.0, 798.0, 671.0, 644.0, 883.0, 903.0, 677.0];
        integrate(&y)
    }

    /// The same phase as SP 1065 Table 30 prints it (5 decimals), the input
    /// of its published values (AllanTools tests/nbs14 uses it too).
    pub(crate) fn nbs14_10_phase_table30() -> Vec<f64> {
        vec![
            0.0, 103.11111, 123.22222, 157.33333, 166.44444, 48.55555, -96.33333, -2.22222, 111.88889, 0.0,
        ]
    }

    /// The 1000-point NBS14 set of SP 1065 Table 31: n_0 = 1234567890,
    /// n_{i+1} = 16807·n_i mod (2³¹ − 1), y_i = n_i/(2³¹ − 1), i = 0 … 999.
    pub(crate) fn nbs14_1000_freq() -> Vec<f64> {
        let mut n: u64 = 1_234_567_890;
        (0..1000)
            .map(|_| {
                let y = n as f64 / 2_147_483_647.0;
                n = 16807 * n % 2_147_483_647;
                y
            })
            .collect()
    }

    /// The 1000-point set as phase, [0, cumsum(y − ȳ)]: Stable32's
    /// PHASE.DAT (equal to the shipped file to 1e-13).
    pub(crate) fn phase_dat() -> Vec<f64> {
        integrate(&nbs14_1000_freq())
    }

    /// [0, cumsum(y − ȳ)] with τ0 = 1, as AllanTools' `frequency2phase`.
    pub(crate) fn integrate(y: &[f64]) -> Vec<f64> {
        let mean = y.iter().sum::<f64>() / y.len() as f64;
        let mut x = Vec::with_capacity(y.len() + 1);
        let mut acc = 0.0;
        x.push(acc);
        for v in y {
            acc += v - mean;
            x.push(acc);
        }
        x
    }

    /// A reproducible irregular series (random walk plus trend and offset)
    /// for checks against the direct definition.
    pub(crate) fn walk(len: usize, seed: u64) -> Vec<f64> {
        crate::work::random_walk(len, seed)
            .into_iter()
            .enumerate()
            .map(|(i, x)| x + 0.01 * i as f64 + 3.0)
            .collect()
    }

    /// A deviation as each statistic's function computes it.
    pub(crate) type Deviation = fn(&[f64], usize, f64) -> Option<Estimate>;

    /// `x` plus the line `offset + slope·i`.
    pub(crate) fn with_line(x: &[f64], offset: f64, slope: f64) -> Vec<f64> {
        x.iter()
            .enumerate()
            .map(|(i, v)| v + offset + slope * i as f64)
            .collect()
    }

    /// Checks that `stat` gives `x` and `moved` (`x` plus what the statistic
    /// takes out) the same deviation, to 1e-9 relative, at each factor of `ms`.
    pub(crate) fn check_same_deviation(stat: Deviation, x: &[f64], moved: &[f64], ms: &[usize]) {
        for &m in ms {
            let a = stat(x, m, 1.0).unwrap().dev;
            let b = stat(moved, m, 1.0).unwrap().dev;
            assert!(rel(a, b) < 1e-9, "m={m}: {a} vs {b}");
        }
    }

    /// A variance built out from its definition, the reference of a folded sum.
    pub(crate) type Direct = fn(&[f64], usize, f64) -> f64;

    /// Checks `stat` on PHASE.DAT against AllanTools' rows (m, deviation,
    /// count): the deviation to 1e-9 relative, the count exactly.
    pub(crate) fn check_phase_dat(stat: Deviation, rows: &[(usize, f64, usize)]) {
        let x = phase_dat();
        for &(m, want, n) in rows {
            let e = stat(&x, m, 1.0).unwrap();
            assert!(rel(e.dev, want) < 1e-9, "m={m}: {} vs {want}", e.dev);
            assert_eq!(e.n, n, "m={m}");
        }
    }

    /// Checks a folded statistic against its definition built out in full
    /// (`direct`, a variance) to 1e-11 relative: at every factor `factors`
    /// gives for each short walk, then at the factors `ms` on a 700-point
    /// walk, several blocks of windows with the last one partial.
    pub(crate) fn check_folded_against_direct(
        (stat, direct): (Deviation, Direct),
        short: [(usize, u64); 3],
        factors: fn(usize) -> std::ops::RangeInclusive<usize>,
        ms: &[usize],
        tau0: f64,
    ) {
        for (len, seed) in short {
            let x = walk(len, seed);
            for m in factors(len) {
                let want = direct(&x, m, tau0).sqrt();
                let got = stat(&x, m, tau0).unwrap().dev;
                assert!(rel(got, want) < 1e-11, "len={len} m={m}: {got} vs {want}");
            }
        }
        let x = walk(700, 4);
        for &m in ms {
            let want = direct(&x, m, tau0).sqrt();
            let got = stat(&x, m, tau0).unwrap().dev;
            assert!(rel(got, want) < 1e-11, "m={m}: {got} vs {want}");
        }
    }

    /// The inner sums of SP 1065 eqs. 27 and 29 as written, over every
    /// 3m-point subsequence of `s`: build the 9m-point extension of each
    /// detrended subsequence and sum all 6m squared second differences of
    /// m-point means, each subsequence's divided by 6m. O(N·m²); returns
    /// the total and the number of subsequences.
    pub(crate) fn extended_windows_direct(s: &[f64], m: usize) -> (f64, usize) {
        let l = 3 * m;
        let mut total = 0.0;
        for xs in s.windows(l) {
            let h1 = l / 2;
            let h2 = l - h1;
            let mean1 = xs[..h1].iter().sum::<f64>() / h1 as f64;
            let mean2 = xs[h2..].iter().sum::<f64>() / h1 as f64;
            let slope = (mean2 - mean1) / h2 as f64;
            let d: Vec<f64> = xs.iter().enumerate().map(|(k, v)| v - slope * k as f64).collect();
            let ext: Vec<f64> = d.iter().rev().chain(&d).chain(d.iter().rev()).copied().collect();
            let mean = |i: usize| ext[i..i + m].iter().sum::<f64>() / m as f64;
            let inner: f64 = (0..6 * m)
                .map(|i| (mean(i + 2 * m) - 2.0 * mean(i + m) + mean(i)).powi(2))
                .sum();
            total += inner / (6.0 * m as f64);
        }
        (total, s.len() - l + 1)
    }

    /// SP 1065 eq. 27 as written, on the phase. The reference for the
    /// folded computation.
    fn mtotvar_direct(x: &[f64], m: usize, tau0: f64) -> f64 {
        let (total, terms) = extended_windows_direct(x, m);
        let tau = m as f64 * tau0;
        total / (2.0 * tau * tau * terms as f64)
    }

    #[test]
    fn nbs14_ten_point_set() {
        let x = nbs14_10_phase();
        // AllanTools 2024.6, reference_values.json
        // "nbs14_10pt.allantools_2024.06_computed": mtotdev, ttotdev, n.
        // Stable32 1.60 without bias correction ("stable32_v1.60_no_bias_
        // correction"): mtotdev 64.509, 64.794; ttotdev 37.244, 74.818.
        let cases = [
            (1, 64.5089625556, 37.2442668966, 8, 64.509, 37.244),
            (2, 64.7943631093, 74.8180859663, 5, 64.794, 74.818),
        ];
        for (m, md, td, n, s32m, s32t) in cases {
            let e = mtotdev(&x, m, 1.0).unwrap();
            assert!(rel(e.dev, md) < 1e-10, "m={m}: {}", e.dev);
            assert_eq!(e.n, n);
            assert!(matches_printed(e.dev, s32m, 5), "m={m}: {}", e.dev);
            let t = ttotdev(&x, m, 1.0).unwrap();
            assert!(rel(t.dev, td) < 1e-10, "m={m}: {}", t.dev);
            assert_eq!(t.n, n);
            assert!(matches_printed(t.dev, s32t, 5), "m={m}: {}", t.dev);
        }
        // SP 1065 Table 30 publishes the bias-corrected values (taus 1, 2):
        // MTOT 75.50203, 75.83606; TTOT 43.59112, 87.56794. They are
        // computed from the phase as the table prints it, to 5 decimals (on
        // the exact phase MTOT at τ = 2 is 75.8360659, which rounds up).
        let printed = nbs14_10_phase_table30();
        let published = [(1, 75.50203, 43.59112), (2, 75.83606, 87.56794)];
        for (m, pm, pt) in published {
            let cm = mtotdev(&printed, m, 1.0).unwrap().dev / MTOTVAR_BIAS.sqrt();
            let ct = ttotdev(&printed, m, 1.0).unwrap().dev / TTOTVAR_BIAS.sqrt();
            assert!(matches_printed(cm, pm, 7), "m={m}: {cm}");
            assert!(matches_printed(ct, pt, 7), "m={m}: {ct}");
        }
        // m = 3: two subsequences of 9 of the 10 points; m = 4 needs 12.
        assert_eq!(mtotdev(&x, 3, 1.0).map(|e| e.n), Some(2));
        assert!(mtotdev(&x, 4, 1.0).is_none());
    }

    /// AllanTools 2024.6 on PHASE.DAT (the 1000-point set, τ0 = 1), from
    ///
    /// ```text
    /// python3 -m venv v && v/bin/pip install allantools==2024.6 numpy
    /// import numpy as np, allantools as at
    /// n = 1234567890; y = []
    /// for i in range(1000):
    ///     y.append(n / 2147483647.0); n = (16807 * n) % 2147483647
    /// y = np.array(y); x = np.concatenate(([0.0], np.cumsum(y - y.mean())))
    /// ms = np.array([1, 2, 4, 8, 16, 32, 64, 128, 256, 10, 20, 40, 100, 200.])
    /// for f in (at.mtotdev, at.ttotdev):
    ///     t, d, e, ns = f(x, rate=1.0, data_type='phase', taus=ms)
    ///     print([(int(a), repr(float(b)), int(c)) for a, b, c in zip(t, d, ns)])
    /// ```
    const ALLANTOOLS_PHASE_DAT: [(usize, f64, f64, usize); 14] = [
        (1, 0.20663914268817002, 0.11930316465612846, 999),
        (2, 0.14337124709598073, 0.16555085620983367, 996),
        (4, 0.09461323118181823, 0.2184998979668922, 990),
        (8, 0.0657213688380369, 0.30355399992121035, 978),
        (10, 0.0555288597686791, 0.32059602135239856, 972),
        (16, 0.037135008950816326, 0.34303851862580753, 954),
        (20, 0.03311442464738858, 0.38237243968458745, 942),
        (32, 0.0291137526573665, 0.5378826538832234, 906),
        (40, 0.026852333876903677, 0.6201280876880019, 882),
        (64, 0.023606398236653444, 0.8722662640978799, 810),
        (100, 0.019546751292673598, 1.1285322120607768, 702),
        (128, 0.016668312513796597, 1.231802203747491, 618),
        (200, 0.008484217888666715, 0.9796730963770334, 402),
        (256, 0.0059607431876067, 0.8810077910873488, 234),
    ];

    #[test]
    fn phase_dat_against_allantools() {
        let mtot: Vec<_> = ALLANTOOLS_PHASE_DAT
            .iter()
            .map(|&(m, md, _, n)| (m, md, n))
            .collect();
        let ttot: Vec<_> = ALLANTOOLS_PHASE_DAT
            .iter()
            .map(|&(m, _, td, n)| (m, td, n))
            .collect();
        check_phase_dat(mtotdev, &mtot);
        check_phase_dat(ttotdev, &ttot);
    }

    #[test]
    fn phase_dat_against_stable32() {
        let x = phase_dat();
        // Stable32 1.60 on PHASE.DAT, allantools tests/phasedat:
        // phase_dat_mtotdev_octave.txt + phase_dat_mtotdev_decade.txt and
        // phase_dat_ttotdev_octave.txt + phase_dat_ttotdev_decade.txt
        // (AF, #, Mod Totdev, Time Totdev; 5 significant digits printed).
        let table = [
            (1, 999, 2.0664e-01, 1.1930e-01),
            (2, 996, 1.4337e-01, 1.6555e-01),
            (4, 990, 9.4613e-02, 2.1850e-01),
            (8, 978, 6.5721e-02, 3.0355e-01),
            (10, 972, 5.5529e-02, 3.2060e-01),
            (16, 954, 3.7135e-02, 3.4304e-01),
            (20, 942, 3.3114e-02, 3.8237e-01),
            (32, 906, 2.9114e-02, 5.3788e-01),
            (40, 882, 2.6852e-02, 6.2013e-01),
            (64, 810, 2.3606e-02, 8.7227e-01),
            (100, 702, 1.9547e-02, 1.1285e+00),
            (128, 618, 1.6668e-02, 1.2318e+00),
            (200, 402, 8.4842e-03, 9.7967e-01),
            (256, 234, 5.9607e-03, 8.8101e-01),
        ];
        for (m, n, mt, tt) in table {
            let e = mtotdev(&x, m, 1.0).unwrap();
            assert_eq!(e.n, n, "m={m}");
            assert!(matches_printed(e.dev, mt, 5), "m={m}: {} vs {mt}", e.dev);
            let t = ttotdev(&x, m, 1.0).unwrap();
            assert!(matches_printed(t.dev, tt, 5), "m={m}: {} vs {tt}", t.dev);
        }
        // SP 1065 Table 31 (bias-corrected, τ = 1, 10, 100): MTOT
        // 0.2418528, 0.06499161, 0.02287774; TTOT 0.1396338, 0.3752293,
        // 1.320847.
        let published = [
            (1, 0.2418528, 0.1396338),
            (10, 0.06499161, 0.3752293),
            (100, 0.02287774, 1.320847),
        ];
        for (m, pm, pt) in published {
            let cm = mtotdev(&x, m, 1.0).unwrap().dev / MTOTVAR_BIAS.sqrt();
            let ct = ttotdev(&x, m, 1.0).unwrap().dev / TTOTVAR_BIAS.sqrt();
            assert!(matches_printed(cm, pm, 7), "m={m}: {cm} vs {pm}");
            assert!(matches_printed(ct, pt, 7), "m={m}: {ct} vs {pt}");
        }
    }

    #[test]
    fn folded_sum_equals_direct_definition() {
        check_folded_against_direct(
            (mtotdev, mtotvar_direct),
            [(40, 1), (61, 2), (97, 3)],
            |len| 1..=len / 3,
            &[1, 2, 3, 5, 8, 33, 150, 233],
            0.5,
        );
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]

        /// The folded, blocked sum equals SP 1065 eq. 27 built out in full,
        /// on random lengths (one or several blocks of windows), factors,
        /// offsets and sampling intervals.
        #[test]
        fn folded_sum_equals_direct_on_random_lengths(
            len in 3usize..420,
            pick in 0.0f64..1.0,
            seed in proptest::prelude::any::<u64>(),
            offset in -1e3f64..1e3,
            tau0 in 1e-3f64..10.0,
        ) {
            let x: Vec<f64> = walk(len, seed).iter().map(|v| v + offset).collect();
            let m = 1 + ((len / 3 - 1) as f64 * pick) as usize;
            // The definition as written rounds at the scale of the data, so
            // on a large offset it is the less exact of the two: one window
            // of three points whose curvature is 5.5e-4 under an offset of
            // -849 left it 1.5e-10 from the folded sum. It reads the same
            // points less the first (MTOT ignores an offset, and the
            // difference is exact where the offset dominates, by Sterbenz).
            let shifted: Vec<f64> = x.iter().map(|v| v - x[0]).collect();
            let want = mtotvar_direct(&shifted, m, tau0).sqrt();
            let got = mtotdev(&x, m, tau0).unwrap();
            proptest::prop_assert!(rel(got.dev, want) < 1e-11, "len={} m={}: {} vs {}", len, m, got.dev, want);
            proptest::prop_assert_eq!(got.n, len - 3 * m + 1);
            let t = ttotdev(&x, m, tau0).unwrap().dev;
            proptest::prop_assert!(rel(t, m as f64 * tau0 * want / 3f64.sqrt()) < 1e-11);
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(48))]

        /// Whatever the CPU, the same bits: the dispatched block and each
        /// build this CPU can run (AVX2, AVX-512) against the portable one.
        #[test]
        fn every_block_gives_the_same_bits(len in 3usize..900, pick in 0.0f64..1.0, seed in proptest::prelude::any::<u64>()) {
            let q = integrate(&walk(len, seed));
            let m = 1 + ((len / 3 - 1) as f64 * pick) as usize;
            let windows = (q.len() - 3 * m).min(BLOCK);
            let mut folds = Folds::new();
            let portable = folds.block_portable(&q, m, windows).to_bits();
            proptest::prop_assert_eq!(folds.block(&q, m, windows).to_bits(), portable);
            #[cfg(target_arch = "x86_64")]
            {
                if std::arch::is_x86_feature_detected!("avx2") {
                    // SAFETY: AVX2 was just detected.
                    let avx2 = unsafe { folds.block_avx2(&q, m, windows) };
                    proptest::prop_assert_eq!(avx2.to_bits(), portable);
                }
                if std::arch::is_x86_feature_detected!("avx512f") {
                    // SAFETY: AVX-512F was just detected.
                    let avx512 = unsafe { folds.block_avx512(&q, m, windows) };
                    proptest::prop_assert_eq!(avx512.to_bits(), portable);
                }
            }
        }
    }

    #[test]
    fn ignores_phase_offset_and_frequency_offset() {
        // The per-window trend removal takes out any linear phase trend.
        let x = walk(300, 7);
        check_same_deviation(mtotdev, &x, &with_line(&x, 1e3, -0.25), &[1, 2, 5, 17, 64, 100]);
        // A pure line gives exactly nothing.
        let line: Vec<f64> = (0..50).map(|i| 2.0 + 0.5 * i as f64).collect();
        assert!(mtotdev(&line, 4, 1.0).unwrap().dev < 1e-12);
    }

    #[test]
    fn scales_with_tau0() {
        // Same phase at τ0 = 2: MTOT halves, TTOT is unchanged.
        let x = walk(120, 11);
        for m in [1, 3, 10] {
            let a = mtotdev(&x, m, 1.0).unwrap();
            let b = mtotdev(&x, m, 2.0).unwrap();
            assert!(rel(b.dev, 0.5 * a.dev) < 1e-14);
            let ta = ttotdev(&x, m, 1.0).unwrap().dev;
            let tb = ttotdev(&x, m, 2.0).unwrap().dev;
            assert!(rel(tb, ta) < 1e-14);
        }
    }

    #[test]
    fn unsupported_inputs_give_none() {
        let x = walk(30, 5);
        assert!(mtotdev(&x, 0, 1.0).is_none());
        assert!(mtotdev(&x, 11, 1.0).is_none());
        assert!(mtotdev(&x, usize::MAX, 1.0).is_none());
        assert!(mtotdev(&x, usize::MAX / 3 + 1, 1.0).is_none());
        assert!(mtotdev(&[], 1, 1.0).is_none());
        assert!(mtotdev(&x[..2], 1, 1.0).is_none());
        for tau0 in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(mtotdev(&x, 2, tau0).is_none(), "tau0={tau0}");
            assert!(ttotdev(&x, 2, tau0).is_none(), "tau0={tau0}");
        }
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let mut y = x.clone();
            y[17] = bad;
            assert!(mtotdev(&y, 2, 1.0).is_none());
            assert!(ttotdev(&y, 2, 1.0).is_none());
        }
        // Huge values that overflow the sums give None, not inf.
        let big: Vec<f64> = x.iter().map(|v| v * 1e300).collect();
        assert!(mtotdev(&big, 2, 1.0).is_none());
        // The smallest series: 3 points at m = 1, one subsequence.
        assert_eq!(mtotdev(&[0.0, 1.0, 5.0], 1, 1.0).map(|e| e.n), Some(1));
    }
}
