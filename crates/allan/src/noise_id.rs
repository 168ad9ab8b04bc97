//! Power-law noise identification at one averaging factor.
//!
//! The EDF of a stability estimate, hence its confidence interval, depends on
//! the dominant power-law noise at that τ: S_y(f) ∝ f^α with α = 2 white PM,
//! 1 flicker PM, 0 white FM, −1 flicker FM, −2 random-walk FM (and −3, −4 for
//! the Hadamard statistics). For an IMU's rate output these are, in the
//! IEEE Std 952 words, quantization-like noise (α = 2), angle/velocity random
//! walk (α = 0), bias instability (α = −1) and rate random walk (α = −2).
//!
//! Methods, in the order tried (as Stable32 and AllanTools do):
//! 1. **Lag-1 autocorrelation** ([`NoiseIdMethod::Lag1Acf`]), W. J. Riley and
//!    C. A. Greenhall, "Power law noise identification using the lag 1
//!    autocorrelation", Proc. 18th EFTF, 2004: needs at least
//!    [`MIN_ACF_POINTS`] phase points after decimation by m.
//! 2. **B1 ratio with R(n)** ([`NoiseIdMethod::B1Ratio`]), NIST SP 1065
//!    (Barnes' B1 bias function, Howe's R(n) = MVAR/AVAR to split white from
//!    flicker PM): for shorter decimated series, down to
//!    [`MIN_B1_AVERAGES`] averages of the rate.
//! 3. Otherwise the documented default [`DEFAULT_ALPHA`] (white FM),
//!    [`NoiseIdMethod::Assumed`].

use std::f64::consts::PI;
use std::fmt;

use crate::Stat;

mod lag1;

/// Most decimated points the lag-1 method looks at: longer series are
/// identified on their first 2^14 decimated points.
///
/// Its statistic r1 has a standard error of about 1/√n, ±0.008 at 2^14
/// points, against decision boundaries 0.25 apart in δ = r1/(1 + r1). The
/// cap was 2^17 (±0.003); at 2^14 the calls are statistically the same,
/// and identification costs an eighth as much at the factors that read the
/// cap: on an octave grid, identification, EDF and intervals went from
/// about half of OADEV's own time to about a tenth (`allan_per_tau 1000000
/// grids`, bench/README.md).
///
/// `bench/noise_id_points.py` compares the two caps with AllanTools' own
/// method (`autocorr_noise_id`) on AllanTools' own power-law noise (Kasdin),
/// 30 seeds at m = 1, 2, 4 and 8:
/// - on pure white and flicker PM, white, flicker and random-walk FM
///   (dmax = 2) and α = −3 and −4 (dmax = 3), the two caps made the same
///   call in all 840 trials, and r1 moved between them by 0.004–0.012
///   (standard deviation over the seeds), about the sampling spread of the
///   difference, √(1/2^14 − 1/2^17) = 0.007. The call was the true α in
///   every trial but 150, alike for both caps: α = −3 read as −4 from
///   m = 2, and α = −4 as −5 (clamped to −4) from m = 4, the method's own
///   reading of that noise decimated.
/// - on two-noise mixtures they differed only where the 2^17 call was
///   itself split across seeds: white FM plus random-walk FM at its
///   crossover, where either cap called white FM in 60–67 % of the seeds;
/// - as the level q of random-walk FM under white FM sweeps the crossover
///   through m = 1, both caps call white FM in every seed up to q = 0.25
///   and in none from q = 0.40; between, 0.97 and 0.33 of the seeds with
///   2^14 points against 1.00 and 0.30 with 2^17.
///
/// A test holds the two caps to the same call on exactly generated pure
/// noises, and a Python test holds imutherm's calls to AllanTools' on all
/// the points of Kasdin noise.
pub const MAX_ACF_POINTS: usize = 1 << 14;

/// Riley & Greenhall's minimum length of the decimated phase series for the
/// lag-1 autocorrelation method.
pub const MIN_ACF_POINTS: usize = 30;

/// Fewest rate averages (of m samples each) on which the B1 ratio is still
/// computed: with fewer, the ratio of the standard to the Allan variance of
/// the averages carries no information (it is identically 1 for two).
pub const MIN_B1_AVERAGES: usize = 4;

/// The α assumed when no identification is possible: white FM (α = 0).
///
/// It is the noise the stability statistics were designed around, the one
/// Stable32's and AllanTools' published interval tables assume when noise
/// identification is off, and the dominant noise of an IMU's rate output at
/// short and medium τ (angle/velocity random walk).
pub const DEFAULT_ALPHA: i32 = 0;

/// How the noise type of a point was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NoiseIdMethod {
    /// Lag-1 autocorrelation of the decimated, detrended, differenced phase
    /// (Riley & Greenhall 2004).
    Lag1Acf,
    /// Barnes' B1 ratio (standard / Allan variance of the rate averages),
    /// with R(n) = MVAR/AVAR separating white and flicker PM (SP 1065).
    B1Ratio,
    /// Not identified: the data were too short or degenerate, and α was
    /// assumed (see [`DEFAULT_ALPHA`]) or given by the caller.
    Assumed,
    /// B1 or the assumption gave an α above the one the lag-1 ACF found at
    /// a shorter τ, and was lowered to it (see [`cap_by_shorter_tau`]).
    Capped,
}

impl NoiseIdMethod {
    /// Short name for tables and JSON: `acf`, `b1`, `assumed`.
    pub fn name(self) -> &'static str {
        match self {
            NoiseIdMethod::Lag1Acf => "acf",
            NoiseIdMethod::B1Ratio => "b1",
            NoiseIdMethod::Assumed => "assumed",
            NoiseIdMethod::Capped => "capped",
        }
    }
}

/// Written as its [`NoiseIdMethod::name`].
impl serde::Serialize for NoiseIdMethod {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.name())
    }
}

impl fmt::Display for NoiseIdMethod {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The identified noise type at one averaging factor, with the diagnostics
/// of the method that found it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NoiseId {
    /// Power-law exponent α of the rate noise, S_y ∝ f^α, clamped to the
    /// statistic family's range (−2..=2 Allan, −4..=2 Hadamard).
    pub alpha: i32,
    /// How α was found.
    pub method: NoiseIdMethod,
    /// Lag-1 autocorrelation r1 of the series after the final differencing
    /// (lag-1 method only).
    pub rho: Option<f64>,
    /// Non-integer estimate of α before rounding and clamping:
    /// 2 − 2(δ + d) with δ = r1/(1 + r1) (lag-1 method only).
    pub alpha_estimate: Option<f64>,
    /// Number of differences d taken (lag-1 method only).
    pub differences: Option<u32>,
    /// Measured B1 ratio (B1 method only).
    pub b1: Option<f64>,
    /// Measured R(n) = MVAR/AVAR, when it was needed to split white from
    /// flicker PM (B1 method only).
    pub rn: Option<f64>,
}

impl NoiseId {
    /// A noise type not identified from data but assumed (or given).
    pub fn assumed(alpha: i32) -> Self {
        NoiseId {
            alpha,
            method: NoiseIdMethod::Assumed,
            rho: None,
            alpha_estimate: None,
            differences: None,
            b1: None,
            rn: None,
        }
    }
}

/// Lowers, in a curve's identifications (ascending m), every α that rests on
/// few points (B1 or assumed) to the α the lag-1 ACF found at the largest
/// shorter τ, when it is above it.
///
/// Why: the rate noise is a sum of power laws S_y(f) = Σ h_α f^α, so the
/// dominant α can only fall as τ grows (lower frequencies belong to the
/// steeper terms). The ACF method, with ≥ 30 points, is reliable; B1 with
/// 4…29 averages is not, and when it errs upwards at the longest τ (white
/// FM read as flicker PM, say) the EDF of the Allan family rises several
/// fold and the interval shrinks accordingly: white noise at m = N/8 gets
/// an interval a third as wide as it should. Capping keeps B1 where it is
/// consistent with the curve and makes the interval conservative where it
/// is not. Stable32 and AllanTools report the uncapped B1 value.
pub fn cap_by_shorter_tau(ids: &mut [NoiseId]) {
    let mut ceiling: Option<i32> = None;
    for id in ids.iter_mut() {
        match id.method {
            NoiseIdMethod::Lag1Acf => ceiling = Some(id.alpha),
            NoiseIdMethod::B1Ratio | NoiseIdMethod::Assumed | NoiseIdMethod::Capped => {
                if let Some(c) = ceiling
                    && id.alpha > c
                {
                    id.alpha = c;
                    id.method = NoiseIdMethod::Capped;
                }
            }
        }
    }
}

/// Identifies the dominant power-law noise at averaging factor `m` from the
/// phase series `phase` (integrated rate, no NaN), for the statistic family
/// of `stat`.
///
/// 1. With ≥ [`MIN_ACF_POINTS`] points in `phase[0], phase[m], phase[2m], …`:
///    Riley & Greenhall's lag-1 ACF method, as AllanTools'
///    `autocorr_noise_id` (dmin = 0): remove a quadratic fit (frequency
///    offset and drift), then for d = 0, 1, … compute the lag-1
///    autocorrelation r1, δ = r1/(1 + r1), and stop when δ < 0.25 or
///    d = dmax (2 for the Allan family, 3 for HDEV, OHDEV, HTOTDEV);
///    otherwise difference once more. Then α = 2 − round(2δ) − 2d (rounding
///    half to even, as NumPy).
/// 2. Otherwise, with ≥ [`MIN_B1_AVERAGES`] averages of m rate samples: the
///    B1 ratio of their standard to their Allan variance is compared with
///    Barnes' theoretical B1(N, μ) at the geometric-mean boundaries between
///    neighbouring μ (as AllanTools' `b1_boundary`); μ = −2 (white or
///    flicker PM) is split by R(n) = MVAR/AVAR against its white-PM (1/m)
///    and flicker-PM (f_h = 1/(2τ0)) values (AllanTools' `rn_boundary`).
/// 3. Otherwise, or when the data are degenerate (constant after detrending,
///    non-finite, `m = 0`): [`DEFAULT_ALPHA`], method `Assumed`.
///
/// The result is clamped to −2..=2 for the Allan family and −4..=2 for the
/// Hadamard family. Never panics.
pub fn identify(phase: &[f64], m: usize, stat: Stat) -> NoiseId {
    identify_checked(phase, m, stat, false)
}

/// [`identify`] on a series expected to be finite throughout, such as the
/// clean stretch of a [`crate::PhaseSeries`] (which refuses infinite
/// samples and whose clean stretch holds no gap). It skips [`identify`]'s
/// scan of every point before the B1 method, which with every τ on the
/// grid made noise identification O(N) per τ, hence O(N²) per curve; the
/// B1 method then checks only the decimated points it reads, and R(n) its
/// own sums. On finite data the result is identical to [`identify`]'s
/// (checked by a property test); the cost per τ is O(N/m) wherever the
/// lag-1 ACF or the B1 ratio decides, and O(N) only where R(n) must split
/// white from flicker PM. The curve's own path is
/// [`identify_finite_staged`], which leaves R(n) out where the cap makes it
/// moot; this one stays as its reference in tests.
#[cfg(test)]
pub(crate) fn identify_finite(phase: &[f64], m: usize, stat: Stat) -> NoiseId {
    identify_checked(phase, m, stat, true)
}

fn identify_checked(phase: &[f64], m: usize, stat: Stat, finite: bool) -> NoiseId {
    match stage(phase, m, stat, finite) {
        Staged::Final(id) => id,
        Staged::PhaseNoise { b1 } => split_phase_noise(phase, m, b1),
    }
}

/// An identification up to the one step that reads the whole series.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Staged {
    /// The lag-1 ACF, the B1 ratio (at μ ≠ −2) or the default decided.
    Final(NoiseId),
    /// The B1 ratio `b1` found white or flicker PM (μ = −2): R(n) must
    /// still tell them apart ([`split_phase_noise`]).
    PhaseNoise { b1: f64 },
}

/// [`identify_finite`] without its O(N) step: R(n) is left for
/// [`split_phase_noise`], or for [`capped_without_rn`] to show it is not
/// needed. O(N/m) per factor (at most [`MAX_ACF_POINTS`] points).
pub(crate) fn identify_finite_staged(phase: &[f64], m: usize, stat: Stat) -> Staged {
    stage(phase, m, stat, true)
}

fn stage(phase: &[f64], m: usize, stat: Stat, finite: bool) -> Staged {
    let (alpha_min, d_max) = family_limits(stat);
    if m == 0 {
        return Staged::Final(NoiseId::assumed(DEFAULT_ALPHA));
    }
    if let Some(acf) = lag1_acf_id(phase, m, d_max) {
        return Staged::Final(NoiseId {
            alpha: acf.alpha.clamp(alpha_min, 2),
            method: NoiseIdMethod::Lag1Acf,
            rho: Some(acf.r1),
            alpha_estimate: Some(acf.alpha_estimate),
            differences: Some(acf.d),
            b1: None,
            rn: None,
        });
    }
    // The ACF path checks the points it uses; this one scans them all, but
    // runs only at the largest factors, where too few points remain.
    if !finite && phase.iter().any(|v| !v.is_finite()) {
        return Staged::Final(NoiseId::assumed(DEFAULT_ALPHA));
    }
    match b1_mu(phase, m, alpha_min) {
        Some((-2, b1)) => Staged::PhaseNoise { b1 },
        Some((mu, b1)) => Staged::Final(NoiseId {
            alpha: mu_to_alpha(mu).clamp(alpha_min, 2),
            method: NoiseIdMethod::B1Ratio,
            rho: None,
            alpha_estimate: None,
            differences: None,
            b1: Some(b1),
            rn: None,
        }),
        None => Staged::Final(NoiseId::assumed(DEFAULT_ALPHA)),
    }
}

/// White (α = 2) or flicker (α = 1) PM, after the B1 ratio `b1` found one
/// of them at factor `m`, by R(n) = MVAR/AVAR against its white-PM (1/m)
/// and flicker-PM (f_h = 1/(2τ0)) values (AllanTools' `rn_boundary`); the
/// default [`DEFAULT_ALPHA`] when R(n) is undefined. O(N).
pub(crate) fn split_phase_noise(phase: &[f64], m: usize, b1: f64) -> NoiseId {
    let Some(rn) = modified_to_allan_ratio(phase, m) else {
        return NoiseId::assumed(DEFAULT_ALPHA);
    };
    let mf = m as f64;
    let rn_white = 1.0 / mf;
    // SP 1065 / IEEE 1139: flicker PM AVAR ∝ (1.038 + 3 ln(2π f_h τ))/(4π²),
    // MVAR ∝ 3 ln(256/27)/(8π²), with f_h = 1/(2τ0).
    let avar_flicker = (1.038 + 3.0 * (2.0 * PI * 0.5 * mf).ln()) / (4.0 * PI * PI);
    let mvar_flicker = 3.0 * (256.0f64 / 27.0).ln() / (8.0 * PI * PI);
    let rn_flicker = mvar_flicker / avar_flicker;
    let boundary = (rn_white * rn_flicker).sqrt();
    // 1 and 2 lie in every family's range: no clamp.
    let alpha = if rn < boundary { 2 } else { 1 };
    NoiseId {
        alpha,
        method: NoiseIdMethod::B1Ratio,
        rho: None,
        alpha_estimate: None,
        differences: None,
        b1: Some(b1),
        rn: Some(rn),
    }
}

/// What [`cap_by_shorter_tau`] makes of a [`Staged::PhaseNoise`] reading
/// at factor `m` under `ceiling` (the α of the lag-1 ACF at the largest
/// shorter τ of the curve), when that is known without R(n); `None` when
/// R(n) must be computed.
///
/// Why this is exact: [`split_phase_noise`] gives α = 2 or 1 (B1), or 0
/// (assumed) when R(n) is undefined. Under a ceiling c ≤ −1 all three are
/// lowered to c, method `Capped`. Under c = 0, α = 2 and 1 become 0
/// `Capped` while an undefined R(n) would stay 0 `Assumed`: R(n) is shown
/// defined by [`rn_is_defined`] at O(N/m), with `max_abs` the largest |x|
/// of `phase`. Under c ≥ 1, or with no ACF at a shorter τ, the split
/// matters and R(n) is computed. For rate noise that is white FM or redder
/// at the longest τ the ACF reads, the case of IMU data, R(n) is then never
/// needed, and noise identification stays O(N/m) per τ on every grid.
pub(crate) fn capped_without_rn(
    ceiling: Option<i32>,
    phase: &[f64],
    m: usize,
    b1: f64,
    max_abs: impl FnOnce() -> f64,
) -> Option<NoiseId> {
    let c = ceiling?;
    let known = c <= -1 || (c == 0 && rn_is_defined(phase, m, max_abs()));
    known.then_some(NoiseId {
        alpha: c,
        method: NoiseIdMethod::Capped,
        b1: Some(b1),
        ..NoiseId::assumed(c)
    })
}

/// A sufficient condition, checked in O(N/m), for
/// [`modified_to_allan_ratio`] to be `Some` on finite `x` of largest
/// magnitude `max_abs`: with |x| ≤ 1e50 every sum stays below 1e140, so
/// nothing overflows; and a decimated second difference whose square is at
/// least 1e-100 is one of the AVAR's terms (computed by the same expression),
/// so AVAR > 0 and R(n) ≤ 1e140/1e-112 is finite.
fn rn_is_defined(x: &[f64], m: usize, max_abs: f64) -> bool {
    let n = x.len();
    // A NaN bound (never from finite data) fails the range check too.
    if m == 0 || n < 3 * m || n as u64 > 1 << 40 || !(0.0..=1e50).contains(&max_abs) {
        return false;
    }
    (0..n - 2 * m)
        .step_by(m)
        .any(|i| (x[i + 2 * m] - 2.0 * x[i + m] + x[i]).powi(2) >= 1e-100)
}

/// (smallest α, dmax) of the statistic's family: the Hadamard statistics
/// converge down to α = −4 and are identified with up to three differences.
fn family_limits(stat: Stat) -> (i32, u32) {
    match stat {
        Stat::Hdev | Stat::Ohdev | Stat::Htotdev => (-4, 3),
        _ => (-2, 2),
    }
}

/// Outcome of the lag-1 ACF method before clamping.
#[derive(Debug, Clone, Copy, PartialEq)]
struct AcfId {
    alpha: i32,
    alpha_estimate: f64,
    d: u32,
    r1: f64,
}

/// Riley & Greenhall's lag-1 ACF identification on phase decimated by `m`,
/// unclamped; `None` below [`MIN_ACF_POINTS`] points or on degenerate data.
fn lag1_acf_id(phase: &[f64], m: usize, d_max: u32) -> Option<AcfId> {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the one requirement for calling a function compiled with
        // `target_feature(enable = "avx2")` is a CPU that has AVX2, which
        // was just detected.
        return unsafe { lag1_acf_id_avx2(phase, m, d_max, MAX_ACF_POINTS) };
    }
    lag1_acf_id_portable(phase, m, d_max, MAX_ACF_POINTS)
}

/// [`lag1_acf_id`] compiled for AVX2: its sums run in four lanes, one
/// 256-bit register where SSE2 takes two, with the same operations in the
/// same order and no fused multiply-add, so the same bits (a test holds the
/// two to it), about a tenth faster than SSE2 (`perf record`). The fit's
/// sums are written in explicit vectors (`lag1::fit_sums_avx2`), where the
/// compiler had paired each lane's two products with shuffles: that cut
/// about a quarter of one identification (`allan_per_tau 1000000 ident`,
/// bench/README.md).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn lag1_acf_id_avx2(phase: &[f64], m: usize, d_max: u32, max_points: usize) -> Option<AcfId> {
    lag1_acf_id_by::<true>(phase, m, d_max, max_points)
}

#[inline(always)]
fn lag1_acf_id_portable(phase: &[f64], m: usize, d_max: u32, max_points: usize) -> Option<AcfId> {
    lag1_acf_id_by::<false>(phase, m, d_max, max_points)
}

/// The method, its fit's sums in explicit AVX2 vectors when `AVX2` (see
/// `lag1::gather_fit_by`).
#[inline(always)]
fn lag1_acf_id_by<const AVX2: bool>(phase: &[f64], m: usize, d_max: u32, max_points: usize) -> Option<AcfId> {
    if phase.len().div_ceil(m.max(1)).min(max_points) < MIN_ACF_POINTS {
        return None;
    }
    debug_assert!(d_max as usize <= lag1::MAX_ORDER, "dmax {d_max}");
    let (x, fit) = lag1::gather_fit_by::<AVX2>(phase, m, max_points)?;
    let r1s = lag1::lag1_by_order(&x, &fit, d_max as usize);
    let mut d = 0u32;
    loop {
        let r1 = r1s.get(d as usize).copied().flatten()?;
        let delta = r1 / (1.0 + r1);
        if delta < 0.25 || d >= d_max {
            let p = -2.0 * (delta + f64::from(d));
            let alpha = -(2.0 * delta).round_ties_even() - 2.0 * f64::from(d) + 2.0;
            if !alpha.is_finite() {
                return None;
            }
            // |alpha| is small here (r1 ∈ [−1, 1]); clamp before the cast.
            let alpha = alpha.clamp(-100.0, 100.0) as i32;
            return Some(AcfId {
                alpha,
                alpha_estimate: p + 2.0,
                d,
                r1,
            });
        }
        d += 1;
    }
}

/// Barnes' B1(N, μ): expected ratio of the N-sample to the two-sample
/// variance for noise whose Allan variance goes as τ^μ (SP 1065; Barnes
/// 1974): N(1 − N^μ)/(2(N − 1)(1 − 2^μ)), and N·ln N/(2(N − 1)·ln 2) at μ = 0.
fn b1_theory(n: f64, mu: i32) -> f64 {
    if mu == 0 {
        n * n.ln() / (2.0 * (n - 1.0) * 2f64.ln())
    } else {
        n * (1.0 - n.powi(mu)) / (2.0 * (n - 1.0) * (1.0 - 2f64.powi(mu)))
    }
}

/// α for Barnes' μ (μ = −2 is white *or* flicker PM, split by R(n)).
fn mu_to_alpha(mu: i32) -> i32 {
    -1 - mu
}

/// The B1-ratio identification of Stable32 and AllanTools: `Some((mu, b1))`
/// with Barnes' μ (−2: white or flicker PM, for [`split_phase_noise`]), or
/// `None` when fewer than [`MIN_B1_AVERAGES`] averages exist or the data are
/// degenerate.
fn b1_mu(phase: &[f64], m: usize, alpha_min: i32) -> Option<(i32, f64)> {
    let n_avg = phase.len().saturating_sub(1) / m;
    if n_avg < MIN_B1_AVERAGES {
        return None;
    }
    // Rate averages over m samples (any common scale cancels in the ratio).
    let y: Vec<f64> = (0..n_avg).map(|k| phase[(k + 1) * m] - phase[k * m]).collect();
    if !y.iter().all(|v| v.is_finite()) {
        return None;
    }
    let n = n_avg as f64;
    let mean = y.iter().sum::<f64>() / n;
    let var = y.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    let avar = 0.5 * y.windows(2).map(|w| (w[1] - w[0]).powi(2)).sum::<f64>() / (n - 1.0);
    let b1 = var / avar;
    if !(b1.is_finite() && avar > 0.0) {
        return None;
    }
    // Candidate μ from white/flicker PM (−2) up to the family's reddest noise.
    let mu_max = -1 - alpha_min;
    let mut mu = -2;
    while mu < mu_max {
        let boundary = (b1_theory(n, mu) * b1_theory(n, mu + 1)).sqrt();
        if b1 < boundary {
            break;
        }
        mu += 1;
    }
    Some((mu, b1))
}

/// R(n) = MVAR/AVAR at averaging factor m, both overlapped estimators on the
/// full phase series (SP 1065 eqs. 11 and 15; τ cancels).
///
/// O(N): the only part of the identification that reads the whole series,
/// run where B1 cannot tell white from flicker PM. The AVAR sum, the
/// running MVAR window and the MVAR sum are three dependency chains; one
/// pass advances them together so they overlap in the pipeline, each
/// summing in index order as before (the result is bit for bit the same).
fn modified_to_allan_ratio(x: &[f64], m: usize) -> Option<f64> {
    let n = x.len();
    let terms_mod = n.checked_sub(3 * m)?.checked_add(1)?;
    if terms_mod == 0 {
        return None;
    }
    let second = |i: usize| x[i + 2 * m] - 2.0 * x[i + m] + x[i];
    let terms_avar = n - 2 * m;
    // Running sum of m consecutive second differences.
    let mut window: f64 = (0..m).map(second).sum();
    let mut mvar = window * window;
    let mut avar = 0.0;
    // MVAR window j = i + 1 drops second(i) and takes second(i + m).
    for i in 0..terms_mod - 1 {
        let s = second(i);
        avar += s * s;
        window += second(i + m) - s;
        mvar += window * window;
    }
    for i in terms_mod - 1..terms_avar {
        let s = second(i);
        avar += s * s;
    }
    let avar = avar / terms_avar as f64;
    let mf = m as f64;
    let mvar = mvar / (terms_mod as f64 * mf * mf);
    let rn = mvar / avar;
    (rn.is_finite() && avar.is_finite() && mvar.is_finite() && avar > 0.0).then_some(rn)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::mtotdev::tests::{integrate, nbs14_1000_freq};
    use proptest::prelude::*;

    /// The AVX2 build of the lag-1 method gives the portable build's bits,
    /// on white and integrated noise, at every difference order it reaches.
    #[test]
    #[cfg(target_arch = "x86_64")]
    fn the_avx2_build_gives_the_same_bits() {
        if !std::arch::is_x86_feature_detected!("avx2") {
            eprintln!("this CPU has no AVX2: nothing to compare");
            return;
        }
        let white = crate::work::random_walk(70_001, 9);
        let mut orders = std::collections::HashSet::new();
        for phase in [white.clone(), integrate(&white), integrate(&integrate(&white))] {
            for m in [1, 2, 3, 5, 8, 13, 100, 1000] {
                let bits =
                    |a: Option<AcfId>| a.map(|a| (a.alpha, a.alpha_estimate.to_bits(), a.d, a.r1.to_bits()));
                let portable = lag1_acf_id_portable(&phase, m, 3, MAX_ACF_POINTS);
                // SAFETY: AVX2 was just detected.
                let avx2 = unsafe { lag1_acf_id_avx2(&phase, m, 3, MAX_ACF_POINTS) };
                assert_eq!(bits(avx2), bits(portable), "m = {m}");
                orders.extend(portable.map(|a| a.d));
            }
        }
        assert!(orders.len() >= 2, "difference orders reached: {orders:?}");
    }

    #[test]
    fn few_point_readings_never_rise_above_the_acf_at_shorter_tau() {
        let id = |alpha, method| NoiseId {
            method,
            ..NoiseId::assumed(alpha)
        };
        use NoiseIdMethod::{Assumed, B1Ratio, Lag1Acf};
        let mut ids = [
            id(2, B1Ratio), // nothing shorter to go by: kept
            id(0, Lag1Acf),
            id(-1, Lag1Acf),
            id(1, B1Ratio),  // above −1: capped
            id(-2, B1Ratio), // below: kept
            id(0, Assumed),  // above −1 (the last ACF): capped
        ];
        cap_by_shorter_tau(&mut ids);
        let got: Vec<(i32, &str)> = ids.iter().map(|i| (i.alpha, i.method.name())).collect();
        assert_eq!(
            got,
            [
                (2, "b1"),
                (0, "acf"),
                (-1, "acf"),
                (-1, "capped"),
                (-2, "b1"),
                (-1, "capped")
            ]
        );
    }

    /// Deterministic series for the AllanTools comparison, built as the
    /// generator builds them: "wpm" the LCG values used as phase, "wfm"
    /// PHASE.DAT (integrated LCG), "rwfm" PHASE.DAT integrated once more.
    fn lcg_series(name: &str) -> Vec<f64> {
        let y = nbs14_1000_freq();
        let wfm = integrate(&y);
        match name {
            "wpm" => y,
            "wfm" => wfm,
            _ => {
                let mut acc = 0.0;
                let mut x = vec![0.0];
                for v in &wfm {
                    acc += v;
                    x.push(acc);
                }
                x
            }
        }
    }

    /// AllanTools 2024.6 `ci.autocorr_noise_id(x, af, data_type="phase",
    /// dmin=0, dmax)`: (series, dmax, af, alpha_int, alpha, d, rho) with
    /// AllanTools' rho = r1/(1 + r1). Generator:
    /// crates/allan/tests/fixtures/edf_ci_noise_id_reference.py, section "acf".
    #[rustfmt::skip]
    const ALLANTOOLS_ACF: &[(&str, u32, usize, i32, f64, u32, f64)] = &[
        ("wpm", 2, 1, 2, 2.055974805742119, 0, -0.027987402871059705),
        ("wpm", 2, 2, 2, 1.9893144085183945, 0, 0.005342795740802787),
        ("wpm", 2, 4, 2, 1.7528875875077206, 0, 0.12355620624613967),
        ("wpm", 2, 8, 2, 1.763806561818435, 0, 0.1180967190907825),
        ("wpm", 2, 16, 2, 2.0532885438457367, 0, -0.02664427192286837),
        ("wpm", 2, 32, 2, 1.84511265296844, 0, 0.07744367351577998),
        ("wpm", 3, 1, 2, 2.055974805742119, 0, -0.027987402871059705),
        ("wpm", 3, 2, 2, 1.9893144085183945, 0, 0.005342795740802787),
        ("wpm", 3, 4, 2, 1.7528875875077206, 0, 0.12355620624613967),
        ("wpm", 3, 8, 2, 1.763806561818435, 0, 0.1180967190907825),
        ("wpm", 3, 16, 2, 2.0532885438457367, 0, -0.02664427192286837),
        ("wpm", 3, 32, 2, 1.84511265296844, 0, 0.07744367351577998),
        ("wfm", 2, 1, 0, 0.0548546443509248, 1, -0.027427322175462412),
        ("wfm", 2, 2, 0, 0.058516077729898086, 1, -0.029258038864949),
        ("wfm", 2, 4, 0, 0.10663215247008262, 1, -0.05331607623504134),
        ("wfm", 2, 8, 0, 0.39808903862923906, 1, -0.19904451931461953),
        ("wfm", 2, 16, 0, -0.3039411567852346, 1, 0.15197057839261735),
        ("wfm", 2, 32, 0, 0.11008186424207644, 1, -0.05504093212103817),
        ("wfm", 3, 1, 0, 0.0548546443509248, 1, -0.027427322175462412),
        ("wfm", 3, 2, 0, 0.058516077729898086, 1, -0.029258038864949),
        ("wfm", 3, 4, 0, 0.10663215247008262, 1, -0.05331607623504134),
        ("wfm", 3, 8, 0, 0.39808903862923906, 1, -0.19904451931461953),
        ("wfm", 3, 16, 0, -0.3039411567852346, 1, 0.15197057839261735),
        ("wfm", 3, 32, 0, 0.11008186424207644, 1, -0.05504093212103817),
        ("rwfm", 2, 1, -2, -1.9452234882116861, 2, -0.027388255894156888),
        ("rwfm", 2, 2, -2, -2.3119555759238075, 2, 0.15597778796190365),
        ("rwfm", 2, 4, -2, -2.2812990923585366, 2, 0.14064954617926842),
        ("rwfm", 2, 8, -2, -2.3319965543015178, 2, 0.16599827715075874),
        ("rwfm", 2, 16, -3, -2.601443027728916, 2, 0.3007215138644577),
        ("rwfm", 2, 32, -2, -2.425750134157326, 2, 0.2128750670786631),
        ("rwfm", 3, 1, -2, -1.9452234882116861, 2, -0.027388255894156888),
        ("rwfm", 3, 2, -2, -2.3119555759238075, 2, 0.15597778796190365),
        ("rwfm", 3, 4, -2, -2.2812990923585366, 2, 0.14064954617926842),
        ("rwfm", 3, 8, -2, -2.3319965543015178, 2, 0.16599827715075874),
        ("rwfm", 3, 16, -4, -3.675762253608669, 3, -0.1621188731956656),
        ("rwfm", 3, 32, -2, -2.425750134157326, 2, 0.2128750670786631),
    ];

    #[test]
    fn lag1_acf_matches_allantools() {
        for &(name, d_max, m, alpha_int, alpha, d, delta) in ALLANTOOLS_ACF {
            let x = lcg_series(name);
            let got = lag1_acf_id(&x, m, d_max).expect("acf id");
            let ctx = format!("{name} dmax={d_max} m={m}: {got:?}");
            assert_eq!(got.alpha, alpha_int, "{ctx}");
            assert_eq!(got.d, d, "{ctx}");
            assert!((got.alpha_estimate - alpha).abs() < 1e-10, "{ctx} vs {alpha}");
            let got_delta = got.r1 / (1.0 + got.r1);
            assert!((got_delta - delta).abs() < 1e-10, "{ctx} vs {delta}");
        }
    }

    #[test]
    fn identify_clamps_to_the_family_range() {
        // Integrated PHASE.DAT at m = 16: AllanTools says α = −3 with dmax = 2
        // and −4 with dmax = 3 (table above).
        let x = lcg_series("rwfm");
        let allan = identify(&x, 16, Stat::Oadev);
        assert_eq!(allan.method, NoiseIdMethod::Lag1Acf);
        assert_eq!(allan.alpha, -2);
        assert_eq!(allan.differences, Some(2));
        let hadamard = identify(&x, 16, Stat::Ohdev);
        assert_eq!(hadamard.alpha, -4);
        assert_eq!(hadamard.differences, Some(3));
        // PHASE.DAT itself is white FM at every octave Stable32 lists
        // (allantools_phasedat/phase_dat_oadev_octave.txt, Alpha column 0).
        let x = lcg_series("wfm");
        for m in [1, 2, 4, 8, 16, 32] {
            let id = identify(&x, m, Stat::Oadev);
            assert_eq!((id.alpha, id.method), (0, NoiseIdMethod::Lag1Acf), "m={m}");
        }
    }

    /// splitmix64 (Steele, Lea & Flood 2014): a tiny deterministic generator.
    struct SplitMix(u64);

    impl SplitMix {
        fn next_u64(&mut self) -> u64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        }

        /// Uniform in (0, 1].
        fn uniform(&mut self) -> f64 {
            ((self.next_u64() >> 11) as f64 + 1.0) / (1u64 << 53) as f64
        }

        /// Standard normal by Box–Muller.
        fn gauss(&mut self) -> f64 {
            let (u1, u2) = (self.uniform(), self.uniform());
            (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
        }

        fn white(&mut self, n: usize) -> Vec<f64> {
            (0..n).map(|_| self.gauss()).collect()
        }
    }

    fn cumsum(y: &[f64]) -> Vec<f64> {
        let mut acc = 0.0;
        std::iter::once(0.0)
            .chain(y.iter().map(|v| {
                acc += v;
                acc
            }))
            .collect()
    }

    /// The cap of [`MAX_ACF_POINTS`] makes the call the first 2^17 points
    /// make, on every pure noise these generators give exactly (white PM,
    /// white FM, random-walk FM, and for the Hadamard family the twice
    /// integrated random walk), and r1 moves between the two by no more
    /// than their sampling spread allows: the difference of the estimates
    /// has a standard deviation of about √(1/2^14 − 1/2^17) ≈ 0.0073, and
    /// the bound is six of it. The calls are compared as `identify`
    /// reports them, clamped to the family's range. (`bench/noise_id_points.py` shows the same
    /// on AllanTools' Kasdin noise, flicker included, with AllanTools'
    /// own method.)
    #[test]
    fn the_cap_makes_the_calls_of_eight_times_the_points() {
        const LARGE: usize = 1 << 17;
        let spread = (1.0 / MAX_ACF_POINTS as f64 - 1.0 / LARGE as f64).sqrt();
        for seed in 0..4u64 {
            let mut rng = SplitMix(seed);
            let m = 1 + (seed as usize % 2) * 2; // 1 and 3
            let wpm = rng.white(LARGE * m);
            let wfm = cumsum(&rng.white(LARGE * m));
            let rwfm = cumsum(&cumsum(&rng.white(LARGE * m)));
            let rrfm = cumsum(&rwfm);
            for (phase, d_max, truth) in [(wpm, 2, 2), (wfm, 2, 0), (rwfm, 2, -2), (rrfm, 3, -4)] {
                let small = lag1_acf_id_portable(&phase, m, d_max, MAX_ACF_POINTS).expect("acf");
                let large = lag1_acf_id_portable(&phase, m, d_max, LARGE).expect("acf");
                let ctx = format!("seed {seed}, m = {m}, α = {truth}: {small:?} vs {large:?}");
                // The twice integrated walk can read as α = −5 (it does at
                // m = 3, r1 near the rounding boundary of 1/3), which the
                // Hadamard family's clamp reports as −4.
                let reported = |a: &AcfId| (a.alpha.clamp(-4, 2), a.d);
                assert_eq!(reported(&small), reported(&large), "{ctx}");
                assert_eq!(reported(&small).0, truth, "{ctx}");
                assert!((small.r1 - large.r1).abs() <= 6.0 * spread, "{ctx}");
            }
        }
    }

    const N_RATE: usize = 8192;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(24))]

        /// On finite data the identification without the full finiteness
        /// scan gives the same result at every factor, through the ACF, the
        /// B1 ratio (with and without R(n)) and the assumed default.
        #[test]
        fn identify_finite_equals_identify(seed in any::<u64>(), len in 5usize..400, kind in 0usize..3) {
            let mut rng = SplitMix(seed);
            let white = rng.white(len);
            let data = match kind {
                0 => white,             // white PM: B1 then R(n)
                1 => cumsum(&white),    // white FM
                _ => cumsum(&cumsum(&white)), // random-walk FM
            };
            for m in 1..=data.len() / 2 {
                for stat in [Stat::Oadev, Stat::Hdev, Stat::Mtotdev] {
                    let a = identify(&data, m, stat);
                    let b = identify_finite(&data, m, stat);
                    prop_assert_eq!(a, b, "m={} {}", m, stat);
                }
            }
        }

        /// White FM: i.i.d. rate samples integrated to phase → α = 0.
        #[test]
        fn white_fm_is_identified(seed in any::<u64>()) {
            let phase = cumsum(&SplitMix(seed).white(N_RATE));
            for m in [1, 2, 4, 8, 16] {
                for stat in [Stat::Oadev, Stat::Mdev, Stat::Ohdev] {
                    let id = identify(&phase, m, stat);
                    prop_assert_eq!(id.method, NoiseIdMethod::Lag1Acf);
                    prop_assert_eq!(id.alpha, 0, "m={} {} {:?}", m, stat, id);
                }
            }
        }

        /// Random-walk FM: the rate is a random walk → α = −2.
        #[test]
        fn random_walk_fm_is_identified(seed in any::<u64>()) {
            let rate = cumsum(&SplitMix(seed).white(N_RATE));
            let phase = cumsum(&rate);
            for m in [1, 2, 4] {
                for stat in [Stat::Oadev, Stat::Hdev] {
                    let id = identify(&phase, m, stat);
                    prop_assert_eq!(id.alpha, -2, "m={} {} {:?}", m, stat, id);
                }
            }
        }

        /// White PM: i.i.d. phase samples → α = 2.
        #[test]
        fn white_pm_is_identified(seed in any::<u64>()) {
            let phase = SplitMix(seed).white(N_RATE);
            for m in [1, 2, 4, 8, 16] {
                for stat in [Stat::Adev, Stat::Ohdev] {
                    let id = identify(&phase, m, stat);
                    prop_assert_eq!(id.alpha, 2, "m={} {} {:?}", m, stat, id);
                }
            }
        }
    }

    /// Fraction of `seeds` series for which the B1 fallback finds `want`.
    fn b1_hit_rate(make: impl Fn(&mut SplitMix) -> Vec<f64>, m: usize, want: i32) -> f64 {
        let seeds = 200u64;
        let mut hits = 0;
        for seed in 0..seeds {
            let phase = make(&mut SplitMix(seed));
            let id = identify(&phase, m, Stat::Oadev);
            assert_eq!(id.method, NoiseIdMethod::B1Ratio, "{id:?}");
            assert!(id.b1.is_some());
            hits += usize::from(id.alpha == want);
        }
        hits as f64 / seeds as f64
    }

    #[test]
    fn b1_fallback_below_thirty_points() {
        // 200 rate samples at m = 10: 21 decimated phase points (< 30), 20
        // averages. B1 is a coarse statistic on so few averages: the right
        // noise must still win clearly over 200 seeded series.
        let wfm = b1_hit_rate(|g| cumsum(&g.white(200)), 10, 0);
        let rwfm = b1_hit_rate(|g| cumsum(&cumsum(&g.white(200))), 10, -2);
        let wpm = b1_hit_rate(|g| g.white(201), 10, 2);
        assert!(wfm > 0.6, "white FM hit rate {wfm}");
        assert!(rwfm > 0.6, "random-walk FM hit rate {rwfm}");
        assert!(wpm > 0.6, "white PM hit rate {wpm}");
    }

    #[test]
    fn b1_theory_limits() {
        // Barnes' B1 at μ = −1 is 1 for every N; at μ = 1 it is N/2; μ = 2
        // N(N+1)/6; μ = −2 (N² − 1)/(1.5·N(N − 1)) (AllanTools' b1_theory).
        for n in [4.0, 20.0, 1000.0] {
            assert!((b1_theory(n, -1) - 1.0).abs() < 1e-14);
            assert!((b1_theory(n, 1) - n / 2.0).abs() < 1e-12 * n);
            assert!((b1_theory(n, 2) - n * (n + 1.0) / 6.0).abs() < 1e-12 * n * n);
            let want = (n * n - 1.0) / (1.5 * n * (n - 1.0));
            assert!((b1_theory(n, -2) - want).abs() < 1e-14);
        }
        assert_eq!(mu_to_alpha(-1), 0);
        assert_eq!(mu_to_alpha(1), -2);
        assert_eq!(mu_to_alpha(3), -4);
    }

    /// R(n) as first written, one estimator after the other: the
    /// reference for the fused pass.
    fn modified_to_allan_ratio_in_turn(x: &[f64], m: usize) -> Option<f64> {
        let n = x.len();
        let terms_mod = n.checked_sub(3 * m)?.checked_add(1)?;
        if terms_mod == 0 {
            return None;
        }
        let second = |i: usize| x[i + 2 * m] - 2.0 * x[i + m] + x[i];
        let terms_avar = n - 2 * m;
        let avar = (0..terms_avar).map(|i| second(i).powi(2)).sum::<f64>() / terms_avar as f64;
        let mut window: f64 = (0..m).map(second).sum();
        let mut mvar = window * window;
        for j in 1..terms_mod {
            window += second(j + m - 1) - second(j - 1);
            mvar += window * window;
        }
        let mf = m as f64;
        let mvar = mvar / (terms_mod as f64 * mf * mf);
        let rn = mvar / avar;
        (rn.is_finite() && avar > 0.0).then_some(rn)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// The fused pass gives R(n) bit for bit, at every factor.
        #[test]
        fn fused_rn_equals_rn_in_turn(seed in any::<u64>(), len in 1usize..300, kind in 0usize..2) {
            let white = SplitMix(seed).white(len);
            let x = if kind == 0 { white } else { cumsum(&white) };
            for m in 1..=len {
                let a = modified_to_allan_ratio(&x, m);
                let b = modified_to_allan_ratio_in_turn(&x, m);
                prop_assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits), "m={}", m);
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(48))]

        /// Wherever the staged identification settles a phase-noise reading
        /// without R(n), it is what capping the full identification gives,
        /// for every ceiling, on white PM, white FM and random-walk FM at
        /// ordinary and extreme magnitudes (where R(n) may be undefined).
        #[test]
        fn settling_without_rn_equals_capping_the_full_identification(
            seed in any::<u64>(),
            len in 5usize..400,
            kind in 0usize..3,
            scale in prop_oneof![Just(1.0), Just(1e60), Just(1e150), Just(1e154), Just(1e-160), Just(0.0)],
        ) {
            let white = SplitMix(seed).white(len);
            let base = match kind {
                0 => white,
                1 => cumsum(&white),
                _ => cumsum(&cumsum(&white)),
            };
            let data: Vec<f64> = base.iter().map(|v| v * scale).collect();
            let max_abs = data.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            for m in 1..=data.len() / 2 {
                for stat in [Stat::Oadev, Stat::Hdev] {
                    let full = identify_finite(&data, m, stat);
                    let b1 = match identify_finite_staged(&data, m, stat) {
                        Staged::Final(id) => {
                            prop_assert_eq!(id, full, "m={} {}", m, stat);
                            continue;
                        }
                        Staged::PhaseNoise { b1 } => b1,
                    };
                    prop_assert_eq!(split_phase_noise(&data, m, b1), full);
                    for ceiling in [None, Some(-4), Some(-2), Some(-1), Some(0), Some(1), Some(2)] {
                        let Some(quick) = capped_without_rn(ceiling, &data, m, b1, || max_abs) else {
                            continue;
                        };
                        let mut ids = vec![full];
                        if let Some(c) = ceiling {
                            let acf = NoiseId { method: NoiseIdMethod::Lag1Acf, ..NoiseId::assumed(c) };
                            ids.insert(0, acf);
                        }
                        cap_by_shorter_tau(&mut ids);
                        let capped = ids[ids.len() - 1];
                        prop_assert_eq!((quick.alpha, quick.method), (capped.alpha, capped.method),
                            "m={} {} ceiling {:?}", m, stat, ceiling);
                    }
                }
            }
        }
    }

    #[test]
    fn rn_is_shown_defined_only_where_it_is() {
        let x = cumsum(&SplitMix(3).white(300));
        let max_abs = x.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        for m in [1, 5, 20, 70] {
            assert!(rn_is_defined(&x, m, max_abs), "m={m}");
            assert!(modified_to_allan_ratio(&x, m).is_some());
        }
        // Too large to vouch for; constant (R(n) undefined); too short.
        assert!(!rn_is_defined(&x, 5, 1e60));
        assert!(!rn_is_defined(&[2.0; 100], 5, 2.0));
        assert!(modified_to_allan_ratio(&[2.0; 100], 5).is_none());
        assert!(!rn_is_defined(&x[..20], 7, max_abs));
    }

    #[test]
    fn modified_to_allan_ratio_is_one_at_m1_and_small_for_white_pm() {
        let x = SplitMix(7).white(4000);
        let r1 = modified_to_allan_ratio(&x, 1).expect("rn");
        assert!((r1 - 1.0).abs() < 1e-12);
        let r10 = modified_to_allan_ratio(&x, 10).expect("rn");
        assert!((r10 - 0.1).abs() < 0.02, "{r10}");
    }

    #[test]
    fn defaults_and_degenerate_inputs() {
        let assumed = NoiseId::assumed(DEFAULT_ALPHA);
        assert_eq!(assumed.method, NoiseIdMethod::Assumed);
        assert_eq!(assumed.alpha, 0);
        let x = lcg_series("wfm");
        assert_eq!(identify(&x, 0, Stat::Adev), assumed);
        assert_eq!(identify(&[], 1, Stat::Adev), assumed);
        assert_eq!(identify(&x, 5000, Stat::Adev), assumed);
        assert_eq!(identify(&x, 300, Stat::Adev), assumed); // 3 averages
        assert_eq!(identify(&vec![1.5; 100], 1, Stat::Adev), assumed);
        let linear: Vec<f64> = (0..100).map(|i| i as f64).collect();
        assert_eq!(identify(&linear, 2, Stat::Hdev), assumed);
        let mut gap = x.clone();
        gap[10] = f64::NAN;
        assert_eq!(identify(&gap, 1, Stat::Adev), assumed);
        gap[10] = f64::INFINITY;
        assert_eq!(identify(&gap, 1, Stat::Adev), assumed);
        assert_eq!(NoiseIdMethod::Lag1Acf.to_string(), "acf");
    }

    #[test]
    fn never_panics_on_short_series() {
        let x = lcg_series("wfm");
        for len in 0..45 {
            for m in 1..50 {
                for stat in Stat::ALL {
                    let id = identify(&x[..len], m, stat);
                    let lo = if matches!(stat, Stat::Hdev | Stat::Ohdev | Stat::Htotdev) {
                        -4
                    } else {
                        -2
                    };
                    assert!((lo..=2).contains(&id.alpha), "{len} {m} {stat}: {id:?}");
                }
            }
        }
        // Alternating phase: r1 = −1 exactly.
        let alt: Vec<f64> = (0..64).map(|i| if i % 2 == 0 { 1.0 } else { -1.0 }).collect();
        let id = identify(&alt, 1, Stat::Adev);
        assert!((-2..=2).contains(&id.alpha), "{id:?}");
    }
}
