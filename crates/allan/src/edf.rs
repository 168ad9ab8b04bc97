//! Equivalent degrees of freedom (EDF) of Allan-family variance estimates.
//!
//! A variance estimate with ν equivalent degrees of freedom behaves like
//! σ²·χ²_ν/ν; ν sets the width of the confidence interval
//! ([`crate::confidence::chi2_interval`]) and depends on the statistic, the
//! averaging factor m, the record length and the power-law noise type α
//! (S_y(f) ∝ f^α of the *rate* noise: 2 white PM, 1 flicker PM, 0 white FM,
//! −1 flicker FM, −2 random-walk FM, −3 flicker-walk FM, −4 random-run FM).
//!
//! Sources, by statistic:
//! * ADEV, OADEV, MDEV, TDEV, HDEV, OHDEV — C. A. Greenhall and W. J. Riley,
//!   "Uncertainty of stability variances based on finite differences",
//!   Proc. 35th PTTI Meeting, 2003 ([`greenhall_edf`]): exact for Gaussian
//!   power-law noise, with the paper's tables 1–3 for long records.
//! * TOTDEV — NIST SP 1065 (Riley 2008), Table 7: ν = b·(N/m) − c.
//! * MTOTDEV, TTOTDEV — NIST SP 1065, Table 8: ν = b·(N/m) − c.
//! * HTOTDEV — NIST SP 1065's Htot fit (after Howe et al., "A total estimator
//!   of the Hadamard function used for GPS operations", PTTI 2000):
//!   ν = (N/m)/(b0 + b1·m/N) for m ≥ 16 and α ∈ {0, −1, −2}; elsewhere the
//!   OHDEV Greenhall EDF, see [`edf_for`].
//! * Theo1 — NIST SP 1065's Theo1 EDF formulas (after D. A. Howe and
//!   T. K. Peppler, "Estimation of very long-term frequency stability using a
//!   special-purpose statistic", Proc. 2003 FCS/EFTF).

use crate::Stat;

/// Greenhall & Riley's `Jmax`: the largest number of covariance terms summed
/// exactly before the tabulated large-record approximations take over.
const J_MAX: usize = 100;

/// Greenhall & Riley (2003) EDF of a variance built from `d`-th differences
/// of phase (Sec. 3 of the paper, the "combined" algorithm).
///
/// * `alpha` — exponent of the rate (frequency) noise, S_y ∝ f^α, −4..=2;
/// * `d` — order of the phase difference: 1 (first-difference variance),
///   2 (Allan / modified Allan), 3 (Hadamard);
/// * `m` — averaging factor, τ = m·τ0;
/// * `n_phase` — number of phase points;
/// * `overlapping` — stride 1 (true, "OADEV", "OHDEV") or stride m (false);
/// * `modified` — the modified variance (phase averaged over m points first),
///   as in AllanTools' `edf_greenhall`.
///
/// The estimator is modelled as M = 1 + ⌊S(N − L)/m⌋ summands (L = m/F + m·d,
/// filter factor F = 1 modified / m unmodified, stride factor S = m
/// overlapped / 1 not) whose covariances follow from the generalized
/// autocovariance of the power-law noise, eqs. (7)–(9); 1/ν is the sum of
/// squared correlations, eq. (10) (`BasicSum`). Four cases follow the paper's
/// Sec. 3.6: modified variances (Table 1), unmodified with α ≤ 0 (Table 2),
/// flicker PM (Tables 2 and 3) and white PM (closed form).
///
/// The branch between the tabulated and the exact-sum approximations is
/// taken as AllanTools does (tables when `r = M/S > d + 1`); AllanTools'
/// gaps are filled from the paper: white PM with `⌈r⌉ ≤ d` (AllanTools
/// raises) uses the paper's exact finite sum, and α = −4 unmodified uses
/// Table 2's (1.302, 0.535) row (AllanTools' lookup rejects that row).
///
/// `None` when `alpha + 2d ≤ 1` (the variance does not converge for that
/// noise), when an argument is out of range, or when the record is shorter
/// than one term (N < L).
pub fn greenhall_edf(
    alpha: i32,
    d: u32,
    m: usize,
    n_phase: usize,
    overlapping: bool,
    modified: bool,
) -> Option<f64> {
    if !(-4..=2).contains(&alpha) || !(1..=3).contains(&d) || m == 0 {
        return None;
    }
    if alpha + 2 * d as i32 <= 1 {
        return None;
    }
    // Filter length L = m/F + m·d in phase samples, with F = 1 or m.
    let head = if modified { m } else { 1 };
    let l = m.checked_mul(d as usize)?.checked_add(head)?;
    if n_phase < l {
        return None;
    }
    // M = 1 + ⌊S(N − L)/m⌋ summands: S = m overlapped, 1 otherwise.
    let big_m = if overlapping {
        1 + (n_phase - l)
    } else {
        1 + (n_phase - l) / m
    };
    let mf = m as f64;
    let df = f64::from(d);
    let s = if overlapping { mf } else { 1.0 };
    let big_mf = big_m as f64;
    let j = big_mf.min((df + 1.0) * s);
    let r = big_mf / s;
    let j_max = J_MAX as f64;
    let beyond_tables = r > df + 1.0;

    let inv_edf = if modified {
        // Case 1: modified variances, F = 1 (Table 1).
        if j <= j_max {
            basic_sum(j, big_mf, s, 1.0, alpha, d) / (big_mf * sz(0.0, 1.0, alpha, d).powi(2))
        } else if beyond_tables {
            let (a0, a1) = table1(alpha, d)?;
            (a0 - a1 / r) / r
        } else {
            let m_prime = j_max / r;
            basic_sum(j_max, j_max, m_prime, 1.0, alpha, d) / (j_max * sz(0.0, 1.0, alpha, d).powi(2))
        }
    } else if alpha <= 0 {
        // Case 2: unmodified variances, white FM and redder (Table 2).
        if j <= j_max {
            // For long filters the F → ∞ limit avoids the cancellation of
            // second differences of s_w on a fine grid.
            let f = if mf * (df + 1.0) <= j_max {
                mf
            } else {
                f64::INFINITY
            };
            basic_sum(j, big_mf, s, f, alpha, d) / (big_mf * sz(0.0, f, alpha, d).powi(2))
        } else if beyond_tables {
            let (a0, a1) = table2(alpha, d)?;
            (a0 - a1 / r) / r
        } else {
            let m_prime = j_max / r;
            basic_sum(j_max, j_max, m_prime, f64::INFINITY, alpha, d)
                / (j_max * sz(0.0, f64::INFINITY, alpha, d).powi(2))
        }
    } else if alpha == 1 {
        // Case 3: unmodified variances, flicker PM (Tables 2 and 3).
        if j <= j_max {
            basic_sum(j, big_mf, s, mf, 1, d) / (big_mf * sz(0.0, mf, 1, d).powi(2))
        } else {
            let (b0, b1) = table3(d)?;
            let norm = (b0 + b1 * mf.ln()).powi(2);
            if beyond_tables {
                let (a0, a1) = table2(1, d)?;
                (a0 - a1 / r) / (norm * r)
            } else {
                let m_prime = j_max / r;
                basic_sum(j_max, j_max, m_prime, m_prime, 1, d) / (norm * j_max)
            }
        }
    } else {
        // Case 4: unmodified variances, white PM.
        let k = r.ceil();
        if k <= df {
            // Exact: only the K − 1 nearest summands overlap.
            let c0 = binomial(2 * d, d);
            let mut sum = 0.0;
            let mut kk = 1u32;
            while f64::from(kk) < k {
                sum += (1.0 - f64::from(kk) / r) * binomial(2 * d, d - kk).powi(2);
                kk += 1;
            }
            (1.0 + 2.0 * sum / (c0 * c0)) / big_mf
        } else {
            let a0 = binomial(4 * d, 2 * d) / binomial(2 * d, d).powi(2);
            let a1 = 0.5 * df;
            (a0 - a1 / r) / big_mf
        }
    };
    let edf = 1.0 / inv_edf;
    (edf.is_finite() && edf > 0.0).then_some(edf)
}

/// The EDF of `stat` at averaging factor `m` on `n_phase` phase points, for
/// power-law rate noise of exponent `alpha` (see the module documentation for
/// the sources):
///
/// | statistic | EDF |
/// | --- | --- |
/// | ADEV | Greenhall, d = 2, non-overlapped |
/// | OADEV | Greenhall, d = 2, overlapped |
/// | MDEV, TDEV | Greenhall, d = 2, modified, overlapped |
/// | HDEV | Greenhall, d = 3, non-overlapped |
/// | OHDEV | Greenhall, d = 3, overlapped |
/// | TOTDEV | SP 1065 Table 7, b·N/m − c, α ∈ {0, −1, −2}; for α = 2, 1 the SP 1065 "simple" AVAR formulas, as AllanTools' `edf_totdev` |
/// | MTOTDEV, TTOTDEV | SP 1065 Table 8, b·N/m − c, α ∈ −2..=2 (AllanTools' `edf_mtotdev`) |
/// | HTOTDEV | m ≥ 16 and α ∈ {0, −1, −2}: (N/m)/(b0 + b1·m/N) with (b0, b1) = (0.559, 1.004) WFM, (0.868, 1.140) FFM, (0.938, 1.696) RWFM (SP 1065, Howe et al. 2000); otherwise the OHDEV Greenhall EDF |
/// | Theo1 | SP 1065 Theo1 formulas in N and r = 0.75·m, α ∈ −2..=2 (`m` is the Theo1 averaging factor, τ = 0.75·m·τ0) |
///
/// For HTOTDEV below m = 16, and for the PM noises and α = −3, −4 where the
/// Htot fit does not exist, the OHDEV EDF is a conservative stand-in: HTOTDEV
/// is at least as efficient as OHDEV. On PHASE.DAT, Stable32 1.60's HTOTDEV
/// intervals imply 10–40 % more EDF than OHDEV's at m = 1…8 (its small-m
/// rule is not published), and its m ≥ 16 white-FM intervals match the fit
/// above to 0.2 %. The flicker and random-walk FM rows of the fit have no
/// Stable32 output in the reference data to be checked against.
///
/// `None` when the combination is invalid (for the difference-based
/// statistics α + 2d ≤ 1; α outside a table's rows) or the result is not a
/// finite positive number (too few points).
pub fn edf_for(stat: Stat, alpha: i32, m: usize, n_phase: usize) -> Option<f64> {
    let edf = match stat {
        Stat::Adev => greenhall_edf(alpha, 2, m, n_phase, false, false),
        Stat::Oadev => greenhall_edf(alpha, 2, m, n_phase, true, false),
        Stat::Mdev | Stat::Tdev => greenhall_edf(alpha, 2, m, n_phase, true, true),
        Stat::Hdev => greenhall_edf(alpha, 3, m, n_phase, false, false),
        Stat::Ohdev => greenhall_edf(alpha, 3, m, n_phase, true, false),
        Stat::Totdev => totdev_edf(alpha, m, n_phase),
        Stat::Mtotdev | Stat::Ttotdev => mtotdev_edf(alpha, m, n_phase),
        Stat::Htotdev => htotdev_edf(alpha, m, n_phase),
        Stat::Theo1 => theo1_edf(alpha, m, n_phase),
    }?;
    (edf.is_finite() && edf > 0.0).then_some(edf)
}

/// TOTDEV: NIST SP 1065 Table 7, ν = b·(N/m) − c with N phase points, for
/// white, flicker and random-walk FM; the PM noises use the SP 1065 "simple"
/// AVAR approximations as AllanTools does (TOTDEV is not meant for them).
fn totdev_edf(alpha: i32, m: usize, n_phase: usize) -> Option<f64> {
    if m == 0 {
        return None;
    }
    let ratio = n_phase as f64 / m as f64;
    let (b, c) = match alpha {
        0 => (1.50, 0.0),
        -1 => (1.17, 0.22),
        -2 => (0.93, 0.36),
        2 | 1 => return simple_avar_edf(alpha, m, n_phase),
        _ => return None,
    };
    Some(b * ratio - c)
}

/// MTOTDEV and TTOTDEV: NIST SP 1065 Table 8, ν = b·(N/m) − c.
fn mtotdev_edf(alpha: i32, m: usize, n_phase: usize) -> Option<f64> {
    if m == 0 {
        return None;
    }
    let (b, c) = match alpha {
        2 => (1.90, 2.10),
        1 => (1.20, 1.40),
        0 => (1.10, 1.20),
        -1 => (0.85, 0.50),
        -2 => (0.75, 0.31),
        _ => return None,
    };
    Some(b * (n_phase as f64 / m as f64) - c)
}

/// HTOTDEV: the SP 1065 / Howe et al. fit ν = (N/m)/(b0 + b1·m/N) for
/// m ≥ 16 and the FM noises it was fitted on; the OHDEV Greenhall EDF
/// elsewhere (see [`edf_for`]).
fn htotdev_edf(alpha: i32, m: usize, n_phase: usize) -> Option<f64> {
    let coefficients = match alpha {
        0 => Some((0.559, 1.004)),
        -1 => Some((0.868, 1.140)),
        -2 => Some((0.938, 1.696)),
        _ => None,
    };
    match coefficients {
        Some((b0, b1)) if m >= 16 && n_phase > 0 => {
            let t = n_phase as f64 / m as f64;
            Some(t / (b0 + b1 / t))
        }
        _ => greenhall_edf(alpha, 3, m, n_phase, true, false),
    }
}

/// Theo1: the SP 1065 EDF formulas (Howe & Peppler 2003) in N phase points
/// and r = 0.75·m.
fn theo1_edf(alpha: i32, m: usize, n_phase: usize) -> Option<f64> {
    if m == 0 {
        return None;
    }
    let n = n_phase as f64;
    let r = 0.75 * m as f64;
    let edf = match alpha {
        2 => (0.86 * (n + 1.0) * (n - 4.0 * r / 3.0) / (n - r)) * (r / (r + 1.14)),
        1 => ((4.798 * n * n - 6.374 * n * r + 12.387 * r) / ((r + 36.6).sqrt() * (n - r))) * (r / (r + 0.3)),
        0 => {
            let r15 = r.powf(1.5);
            ((4.1 * n + 0.8) / r - (3.1 * n + 6.5) / n) * (r15 / (r15 + 5.2))
        }
        -1 => {
            let r3 = r.powi(3);
            ((2.0 * n * n - 1.3 * n * r - 3.5 * r) / (n * r)) * (r3 / (r3 + 2.3))
        }
        -2 => {
            let u = 4.4 * n - 1.0;
            ((4.4 * n - 2.0) / (2.9 * r)) * ((u * u - 8.6 * r * u + 11.4 * r * r) / (u - 2.0).powi(2))
        }
        _ => return None,
    };
    Some(edf)
}

/// SP 1065's simple AVAR EDF approximations for white and flicker PM (after
/// Stein 1985), used by AllanTools' `edf_totdev` for those noises.
fn simple_avar_edf(alpha: i32, m: usize, n_phase: usize) -> Option<f64> {
    let n = n_phase as f64;
    let m = m as f64;
    match alpha {
        2 => Some((n + 1.0) * (n - 2.0 * m) / (2.0 * (n - m))),
        1 => {
            let a = (n - 1.0) / (2.0 * m);
            let b = (2.0 * m + 1.0) * (n - 1.0) / 4.0;
            Some((a.ln() * b.ln()).sqrt().exp())
        }
        _ => None,
    }
}

/// Generalized autocovariance s_w(t) of continuous power-law noise with
/// exponent α, Greenhall & Riley eq. (7). Only its shape matters: every EDF
/// is a ratio of squared covariances.
fn sw(t: f64, alpha: i32) -> f64 {
    let t = t.abs();
    let log_or_zero = |p: i32| if t == 0.0 { 0.0 } else { t.powi(p) * t.ln() };
    match alpha {
        2 => -t,
        1 => log_or_zero(2),
        0 => t.powi(3),
        -1 => -log_or_zero(4),
        -2 => -t.powi(5),
        -3 => log_or_zero(6),
        _ => t.powi(7),
    }
}

/// s_x(t) of the phase filtered by the modified/unmodified pre-filter of
/// factor F, eq. (8); F = ∞ is the limit s_w(t; α + 2).
fn sx(t: f64, f: f64, alpha: i32) -> f64 {
    if f.is_infinite() {
        return sw(t, alpha + 2);
    }
    let h = 1.0 / f;
    f * f * (2.0 * sw(t, alpha) - sw(t - h, alpha) - sw(t + h, alpha))
}

/// s_z(t) of the d-th difference, eq. (9):
/// Σ_{k=−d..d} (−1)^k C(2d, d+k) s_x(t + k).
fn sz(t: f64, f: f64, alpha: i32, d: u32) -> f64 {
    let di = d as i32;
    let mut sum = binomial(2 * d, d) * sx(t, f, alpha);
    for k in 1..=di {
        let c = binomial(2 * d, d - k as u32);
        let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
        sum += sign * c * (sx(t - f64::from(k), f, alpha) + sx(t + f64::from(k), f, alpha));
    }
    sum
}

/// BasicSum(J, M, S, F, α, d), eq. (10):
/// s_z(0)² + (1 − J/M)·s_z(J/S)² + 2·Σ_{j=1}^{J−1} (1 − j/M)·s_z(j/S)².
fn basic_sum(j: f64, big_m: f64, s: f64, f: f64, alpha: i32, d: u32) -> f64 {
    let mut sum = sz(0.0, f, alpha, d).powi(2) + (1.0 - j / big_m) * sz(j / s, f, alpha, d).powi(2);
    let terms = j as usize;
    for i in 1..terms {
        let i = i as f64;
        sum += 2.0 * (1.0 - i / big_m) * sz(i / s, f, alpha, d).powi(2);
    }
    sum
}

/// Binomial coefficient C(n, k) as f64 (small arguments only).
fn binomial(n: u32, k: u32) -> f64 {
    if k > n {
        return 0.0;
    }
    let k = k.min(n - k);
    (0..k).fold(1.0, |acc, i| acc * f64::from(n - i) / f64::from(i + 1))
}

/// Row index of α in Greenhall & Riley's tables (α = 2 first).
fn table_row(alpha: i32) -> Option<usize> {
    (-4..=2).contains(&alpha).then(|| (2 - alpha) as usize)
}

/// Greenhall & Riley Table 1: (a0, a1) for modified variances, columns d = 1..3.
fn table1(alpha: i32, d: u32) -> Option<(f64, f64)> {
    const T: [[Option<(f64, f64)>; 3]; 7] = [
        [
            Some((2.0 / 3.0, 1.0 / 3.0)),
            Some((7.0 / 9.0, 0.5)),
            Some((22.0 / 25.0, 2.0 / 3.0)),
        ],
        [Some((0.840, 0.345)), Some((0.997, 0.616)), Some((1.141, 0.843))],
        [Some((1.079, 0.368)), Some((1.033, 0.607)), Some((1.184, 0.848))],
        [None, Some((1.048, 0.534)), Some((1.180, 0.816))],
        [None, Some((1.302, 0.535)), Some((1.175, 0.777))],
        [None, None, Some((1.194, 0.703))],
        [None, None, Some((1.489, 0.702))],
    ];
    T[table_row(alpha)?][(d as usize).checked_sub(1)?]
}

/// Greenhall & Riley Table 2: (a0, a1) for unmodified variances.
fn table2(alpha: i32, d: u32) -> Option<(f64, f64)> {
    const T: [[Option<(f64, f64)>; 3]; 7] = [
        [
            Some((1.5, 0.5)),
            Some((35.0 / 18.0, 1.0)),
            Some((231.0 / 100.0, 1.5)),
        ],
        [Some((78.6, 25.2)), Some((790.0, 410.0)), Some((9950.0, 6520.0))],
        [
            Some((2.0 / 3.0, 1.0 / 6.0)),
            Some((2.0 / 3.0, 1.0 / 3.0)),
            Some((7.0 / 9.0, 0.5)),
        ],
        [None, Some((0.852, 0.375)), Some((0.997, 0.617))],
        [None, Some((1.079, 0.368)), Some((1.033, 0.607))],
        [None, None, Some((1.053, 0.553))],
        [None, None, Some((1.302, 0.535))],
    ];
    T[table_row(alpha)?][(d as usize).checked_sub(1)?]
}

/// Greenhall & Riley Table 3: (b0, b1) for flicker PM, s_z(0) ≈ b0 + b1·ln m.
fn table3(d: u32) -> Option<(f64, f64)> {
    match d {
        1 => Some((6.0, 4.0)),
        2 => Some((15.23, 12.0)),
        3 => Some((47.8, 40.0)),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::confidence::ONE_SIGMA;

    use crate::stats::mtotdev::tests::rel;

    /// AllanTools 2024.6 `ci.edf_greenhall(alpha, d, m, N, overlapping, modified)`:
    /// (alpha, d, m, N, overlapping, modified, edf). Generator:
    /// crates/allan/tests/fixtures/edf_ci_noise_id_reference.py, section "greenhall".
    /// The (m, N) pairs reach every case of Greenhall & Riley Sec. 3.6 that
    /// AllanTools implements (1.1–1.3, 2.1a/b, 2.2, 2.3, 3.1–3.3, 4.2).
    #[rustfmt::skip]
    const ALLANTOOLS_GREENHALL: &[(i32, u32, usize, usize, bool, bool, f64)] = &[
        (2, 2, 1, 1001, false, false, 514.0360545969612),
        (2, 2, 4, 1001, false, false, 128.32218006209038),
        (2, 2, 40, 1001, false, false, 12.613138686131387),
        (2, 2, 128, 100000, false, false, 401.40752144270954),
        (2, 2, 7, 50, false, false, 3.375),
        (2, 2, 1, 1001, true, false, 514.0360545969612),
        (2, 2, 4, 1001, true, false, 511.745869734452),
        (2, 2, 40, 1001, true, false, 484.47843883864823),
        (2, 2, 128, 100000, true, false, 51330.79133760766),
        (2, 2, 7, 50, true, false, 20.571428571428573),
        (2, 2, 1, 1001, true, true, 514.0360545969611),
        (2, 2, 4, 1001, true, true, 291.6747265828435),
        (2, 2, 40, 1001, true, true, 29.201351351351352),
        (2, 2, 300, 1001, true, true, 1.479786486540479),
        (2, 2, 128, 100000, true, true, 1001.444401408141),
        (2, 2, 7, 50, true, true, 6.279069767441861),
        (2, 2, 1, 1001, false, true, 514.0360545969611),
        (2, 2, 4, 1001, false, true, 127.807896559686),
        (2, 2, 40, 1001, false, true, 12.099110546378654),
        (2, 2, 300, 1001, false, true, 1.0),
        (2, 2, 128, 100000, false, true, 400.8932359525819),
        (2, 2, 7, 50, false, true, 2.8662420382165608),
        (1, 2, 1, 1001, false, false, 635.4659059507518),
        (1, 2, 4, 1001, false, false, 139.35258196646325),
        (1, 2, 40, 1001, false, false, 13.16910660718039),
        (1, 2, 300, 1001, false, false, 1.4075883363114643),
        (1, 2, 128, 100000, false, false, 416.17048162852046),
        (1, 2, 7, 50, false, false, 3.581106490060107),
        (1, 2, 1, 1001, true, false, 635.4659059507518),
        (1, 2, 4, 1001, true, false, 388.8919934830313),
        (1, 2, 40, 1001, true, false, 105.5497586146083),
        (1, 2, 300, 1001, true, false, 19.314998037067376),
        (1, 2, 128, 100000, true, false, 5325.670041301637),
        (1, 2, 7, 50, true, false, 12.011220551290702),
        (1, 2, 1, 1001, true, true, 635.4659059507518),
        (1, 2, 4, 1001, true, true, 247.57698250154644),
        (1, 2, 40, 1001, true, true, 22.75392704460205),
        (1, 2, 300, 1001, true, true, 1.175208744188808),
        (1, 2, 128, 100000, true, true, 781.2198164093528),
        (1, 2, 7, 50, true, true, 5.0142935180279915),
        (1, 2, 1, 1001, false, true, 635.4659059507518),
        (1, 2, 4, 1001, false, true, 157.9281198011347),
        (1, 2, 40, 1001, false, true, 14.860869109953533),
        (1, 2, 300, 1001, false, true, 1.0),
        (1, 2, 128, 100000, false, true, 495.57462557614275),
        (1, 2, 7, 50, false, true, 3.429755635476727),
        (0, 2, 1, 1001, false, false, 782.0302990727438),
        (0, 2, 4, 1001, false, false, 171.39103944337361),
        (0, 2, 40, 1001, false, false, 16.225352112676056),
        (0, 2, 300, 1001, false, false, 1.6),
        (0, 2, 128, 100000, false, false, 520.2223172295853),
        (0, 2, 7, 50, false, false, 4.298634008478589),
        (0, 2, 1, 1001, true, false, 782.0302990727438),
        (0, 2, 4, 1001, true, false, 306.09156823429913),
        (0, 2, 40, 1001, true, false, 35.30414816870144),
        (0, 2, 300, 1001, true, false, 3.1567167899731023),
        (0, 2, 128, 100000, true, false, 1169.625481540931),
        (0, 2, 7, 50, true, false, 7.540158130888387),
        (0, 2, 1, 1001, true, true, 782.0302990727438),
        (0, 2, 4, 1001, true, true, 239.99577218956824),
        (0, 2, 40, 1001, true, true, 21.93000656273046),
        (0, 2, 300, 1001, true, true, 1.1067859515528022),
        (0, 2, 128, 100000, true, true, 753.9650197525369),
        (0, 2, 7, 50, true, true, 4.801908535075528),
        (0, 2, 1, 1001, false, true, 782.0302990727438),
        (0, 2, 4, 1001, false, true, 194.29133029133027),
        (0, 2, 40, 1001, false, true, 18.206500956022946),
        (0, 2, 300, 1001, false, true, 1.0),
        (0, 2, 128, 100000, false, true, 609.8564010942996),
        (0, 2, 7, 50, false, true, 4.128440366972477),
        (-1, 2, 1, 1001, false, false, 895.2473612695801),
        (-1, 2, 4, 1001, false, false, 221.74587720683965),
        (-1, 2, 40, 1001, false, false, 21.350427452229617),
        (-1, 2, 300, 1001, false, false, 1.9101228630826812),
        (-1, 2, 128, 100000, false, false, 689.6679298245858),
        (-1, 2, 7, 50, false, false, 5.454866038550036),
        (-1, 2, 1, 1001, true, false, 895.2473612695801),
        (-1, 2, 4, 1001, true, false, 282.35770397054387),
        (-1, 2, 40, 1001, true, false, 27.551312732885357),
        (-1, 2, 300, 1001, true, false, 2.2459540858450913),
        (-1, 2, 128, 100000, true, false, 915.1295652449114),
        (-1, 2, 7, 50, true, false, 6.5002759586268155),
        (-1, 2, 1, 1001, true, true, 895.2473612695801),
        (-1, 2, 4, 1001, true, true, 236.75177101382894),
        (-1, 2, 40, 1001, true, true, 21.537781735062726),
        (-1, 2, 300, 1001, true, true, 1.0687377736517787),
        (-1, 2, 128, 100000, true, true, 743.0989392283384),
        (-1, 2, 7, 50, true, true, 4.639221030931459),
        (-1, 2, 1, 1001, false, true, 895.2473612695801),
        (-1, 2, 4, 1001, false, true, 222.38564248095494),
        (-1, 2, 40, 1001, false, true, 20.797461577861803),
        (-1, 2, 300, 1001, false, true, 1.0),
        (-1, 2, 128, 100000, false, true, 698.1373795977848),
        (-1, 2, 7, 50, false, true, 4.676838982406145),
        (-2, 2, 1, 1001, false, false, 762.2904904738508),
        (-2, 2, 4, 1001, false, false, 219.28903355313432),
        (-2, 2, 40, 1001, false, false, 21.432558139534883),
        (-2, 2, 300, 1001, false, false, 1.8823529411764706),
        (-2, 2, 128, 100000, false, false, 693.4321128365864),
        (-2, 2, 7, 50, false, false, 5.418950969300345),
        (-2, 2, 1, 1001, true, false, 762.2904904738508),
        (-2, 2, 4, 1001, true, false, 227.092409332942),
        (-2, 2, 40, 1001, true, false, 21.66004112195734),
        (-2, 2, 300, 1001, true, false, 1.6636560264793603),
        (-2, 2, 128, 100000, true, false, 722.512702382167),
        (-2, 2, 7, 50, true, false, 5.079219083912392),
        (-2, 2, 1, 1001, true, true, 762.2904904738508),
        (-2, 2, 4, 1001, true, true, 190.36813850366366),
        (-2, 2, 40, 1001, true, true, 17.257072985472472),
        (-2, 2, 300, 1001, true, true, 1.0347547600715254),
        (-2, 2, 128, 100000, true, true, 598.0560183285983),
        (-2, 2, 7, 50, true, true, 3.637880534061148),
        (-2, 2, 1, 1001, false, true, 762.2904904738508),
        (-2, 2, 4, 1001, false, true, 189.3736333023261),
        (-2, 2, 40, 1001, false, true, 17.729115053779985),
        (-2, 2, 300, 1001, false, true, 1.0),
        (-2, 2, 128, 100000, false, true, 594.4586287374059),
        (-2, 2, 7, 50, false, true, 4.004559829374127),
        (2, 3, 1, 1001, false, false, 432.31591923190456),
        (2, 3, 4, 1001, false, false, 107.6411494977073),
        (2, 3, 40, 1001, false, false, 10.245981018787525),
        (2, 3, 128, 100000, false, false, 337.5107759220018),
        (2, 3, 7, 50, false, false, 2.4875621890547257),
        (2, 3, 1, 1001, true, false, 432.31591923190456),
        (2, 3, 4, 1001, true, false, 429.26590566973425),
        (2, 3, 40, 1001, true, false, 392.9710243986411),
        (2, 3, 128, 100000, true, false, 43159.82090541027),
        (2, 3, 7, 50, true, false, 14.88759072402195),
        (2, 3, 1, 1001, true, true, 432.31591923190445),
        (2, 3, 4, 1001, true, true, 255.0547456984586),
        (2, 3, 40, 1001, true, true, 24.813475322929893),
        (2, 3, 128, 100000, true, true, 884.1092356478093),
        (2, 3, 7, 50, true, true, 4.686240124383058),
        (2, 3, 1, 1001, false, true, 432.31591923190445),
        (2, 3, 4, 1001, false, true, 107.20825206037921),
        (2, 3, 40, 1001, false, true, 9.81346309813463),
        (2, 3, 128, 100000, false, true, 337.0778757907867),
        (2, 3, 7, 50, false, true, 2.0671834625322996),
        (1, 3, 1, 1001, false, false, 508.61291512756253),
        (1, 3, 4, 1001, false, false, 113.89933308355373),
        (1, 3, 40, 1001, false, false, 10.545280622273339),
        (1, 3, 300, 1001, false, false, 1.0),
        (1, 3, 128, 100000, false, false, 345.7592240091664),
        (1, 3, 7, 50, false, false, 2.5833018544030186),
        (1, 3, 1, 1001, true, false, 508.61291512756253),
        (1, 3, 4, 1001, true, false, 325.94007307597525),
        (1, 3, 40, 1001, true, false, 87.06822736887413),
        (1, 3, 300, 1001, true, false, 7.431012582563186),
        (1, 3, 128, 100000, true, false, 4580.006980291005),
        (1, 3, 7, 50, true, false, 8.7372204612731),
        (1, 3, 1, 1001, true, true, 508.61291512756253),
        (1, 3, 4, 1001, true, true, 215.2150277628426),
        (1, 3, 40, 1001, true, true, 19.119807724255182),
        (1, 3, 128, 100000, true, true, 681.855688916281),
        (1, 3, 7, 50, true, true, 3.705551081098235),
        (1, 3, 1, 1001, false, true, 508.61291512756253),
        (1, 3, 4, 1001, false, true, 126.07856764121537),
        (1, 3, 40, 1001, false, true, 11.476776262718069),
        (1, 3, 128, 100000, false, true, 396.5521702600848),
        (1, 3, 7, 50, false, true, 2.341181308990867),
        (0, 3, 1, 1001, false, false, 608.5486691870012),
        (0, 3, 4, 1001, false, false, 131.08522319621642),
        (0, 3, 40, 1001, false, false, 12.099110546378654),
        (0, 3, 300, 1001, false, false, 1.0),
        (0, 3, 128, 100000, false, false, 400.8932359525819),
        (0, 3, 7, 50, false, false, 2.8989253983438767),
        (0, 3, 1, 1001, true, false, 608.5486691870012),
        (0, 3, 4, 1001, true, false, 256.7195710535575),
        (0, 3, 40, 1001, true, false, 29.169237514614995),
        (0, 3, 300, 1001, true, false, 1.4739862814595492),
        (0, 3, 128, 100000, true, false, 1001.434356772149),
        (0, 3, 7, 50, true, false, 5.49390604162409),
        (0, 3, 1, 1001, true, true, 608.5486691870012),
        (0, 3, 4, 1001, true, true, 208.69565984830342),
        (0, 3, 40, 1001, true, true, 18.404935369176584),
        (0, 3, 128, 100000, true, true, 657.0732173086233),
        (0, 3, 7, 50, true, true, 3.5449119636137283),
        (0, 3, 1, 1001, false, true, 608.5486691870012),
        (0, 3, 4, 1001, false, true, 150.79658594987063),
        (0, 3, 40, 1001, false, true, 13.657848324514989),
        (0, 3, 128, 100000, false, true, 474.4534587497551),
        (0, 3, 7, 50, false, true, 2.708994708994709),
        (-1, 3, 1, 1001, false, false, 716.1479074228866),
        (-1, 3, 4, 1001, false, false, 159.92098935808716),
        (-1, 3, 40, 1001, false, false, 14.85462554599354),
        (-1, 3, 300, 1001, false, false, 1.0),
        (-1, 3, 128, 100000, false, false, 495.3394053215543),
        (-1, 3, 7, 50, false, false, 3.444069708665853),
        (-1, 3, 1, 1001, true, false, 716.1479074228866),
        (-1, 3, 4, 1001, true, false, 239.5321669016411),
        (-1, 3, 40, 1001, true, false, 22.72993766963383),
        (-1, 3, 300, 1001, true, false, 1.1721936797341073),
        (-1, 3, 128, 100000, true, false, 781.2129880339597),
        (-1, 3, 7, 50, true, false, 4.798322346339422),
        (-1, 3, 1, 1001, true, true, 716.1479074228866),
        (-1, 3, 4, 1001, true, true, 209.42848149887442),
        (-1, 3, 40, 1001, true, true, 18.44492777754652),
        (-1, 3, 128, 100000, true, true, 659.2796217974699),
        (-1, 3, 7, 50, true, true, 3.5214874033065846),
        (-1, 3, 1, 1001, false, true, 716.1479074228866),
        (-1, 3, 4, 1001, false, true, 177.42442358227206),
        (-1, 3, 40, 1001, false, true, 16.025906489533686),
        (-1, 3, 128, 100000, false, true, 558.3327230584096),
        (-1, 3, 7, 50, false, true, 3.1320588315183433),
        (-2, 3, 1, 1001, false, false, 798.2768190078887),
        (-2, 3, 4, 1001, false, false, 195.22910302055305),
        (-2, 3, 40, 1001, false, false, 18.206500956022946),
        (-2, 3, 300, 1001, false, false, 1.0),
        (-2, 3, 128, 100000, false, false, 609.8564010942996),
        (-2, 3, 7, 50, false, false, 4.135728664167564),
        (-2, 3, 1, 1001, true, false, 798.2768190078887),
        (-2, 3, 4, 1001, true, false, 236.97551185458875),
        (-2, 3, 40, 1001, true, false, 21.90582336956828),
        (-2, 3, 300, 1001, true, false, 1.1047571556965818),
        (-2, 3, 128, 100000, true, false, 753.9574568333312),
        (-2, 3, 7, 50, true, false, 4.648603165868564),
        (-2, 3, 1, 1001, true, true, 798.2768190078887),
        (-2, 3, 4, 1001, true, true, 210.3222707305854),
        (-2, 3, 40, 1001, true, true, 18.495935383555786),
        (-2, 3, 128, 100000, true, true, 662.0592784482737),
        (-2, 3, 7, 50, true, true, 3.4970656858119384),
        (-2, 3, 1, 1001, false, true, 798.2768190078887),
        (-2, 3, 4, 1001, false, true, 197.77735904870156),
        (-2, 3, 40, 1001, false, true, 17.87131911751131),
        (-2, 3, 128, 100000, false, true, 622.3648019906329),
        (-2, 3, 7, 50, false, true, 3.5001367240907846),
        (-3, 3, 1, 1001, false, false, 824.7529586868739),
        (-3, 3, 4, 1001, false, false, 220.38813514087343),
        (-3, 3, 40, 1001, false, false, 20.68836280396534),
        (-3, 3, 300, 1001, false, false, 1.0),
        (-3, 3, 128, 100000, false, false, 693.9409152302454),
        (-3, 3, 7, 50, false, false, 4.663892145197416),
        (-3, 3, 1, 1001, true, false, 824.7529586868739),
        (-3, 3, 4, 1001, true, false, 233.27771366661557),
        (-3, 3, 40, 1001, true, false, 21.427344896546163),
        (-3, 3, 300, 1001, true, false, 1.0674059880745874),
        (-3, 3, 128, 100000, true, false, 739.5778925122193),
        (-3, 3, 7, 50, true, false, 4.489256221944154),
        (-3, 3, 1, 1001, true, true, 824.7529586868739),
        (-3, 3, 4, 1001, true, true, 206.95045857269105),
        (-3, 3, 40, 1001, true, true, 18.137118461607734),
        (-3, 3, 128, 100000, true, true, 651.4631792794241),
        (-3, 3, 7, 50, true, true, 3.3476163180343788),
        (-3, 3, 1, 1001, false, true, 824.7529586868739),
        (-3, 3, 4, 1001, false, true, 204.34229775244964),
        (-3, 3, 40, 1001, false, true, 18.47118645804756),
        (-3, 3, 128, 100000, false, true, 643.0080949001664),
        (-3, 3, 7, 50, false, true, 3.6246739023582806),
        (-4, 3, 1, 1001, false, false, 669.5903105894123),
        (-4, 3, 4, 1001, false, false, 187.80629321665032),
        (-4, 3, 40, 1001, false, false, 17.729115053779985),
        (-4, 3, 300, 1001, false, false, 1.0),
        (-4, 3, 128, 100000, false, false, 594.4586287374059),
        (-4, 3, 7, 50, false, false, 3.9954195656151725),
        (-4, 3, 1, 1001, true, false, 669.5903105894123),
        (-4, 3, 4, 1001, true, false, 188.47914744663632),
        (-4, 3, 300, 1001, true, false, 1.0340815578497065),
        (-4, 3, 7, 50, true, false, 3.5202412016321207),
        (-4, 3, 1, 1001, true, true, 669.5903105894123),
        (-4, 3, 4, 1001, true, true, 165.82004949877302),
        (-4, 3, 40, 1001, true, true, 14.460885499870272),
        (-4, 3, 128, 100000, true, true, 522.3166930805938),
        (-4, 3, 7, 50, true, true, 2.573336833282394),
        (-4, 3, 1, 1001, false, true, 669.5903105894123),
        (-4, 3, 4, 1001, false, true, 165.8883972479064),
        (-4, 3, 40, 1001, false, true, 14.982091418184787),
        (-4, 3, 128, 100000, false, true, 522.0344451456053),
        (-4, 3, 7, 50, false, true, 2.926144021351573),
    ];

    #[test]
    fn greenhall_matches_allantools() {
        let mut worst: f64 = 0.0;
        for &(alpha, d, m, n, ov, md, want) in ALLANTOOLS_GREENHALL {
            let got = greenhall_edf(alpha, d, m, n, ov, md)
                .unwrap_or_else(|| panic!("None for {alpha} {d} {m} {n} {ov} {md}"));
            let e = rel(got, want);
            worst = worst.max(e);
            assert!(
                e < 1e-9,
                "alpha={alpha} d={d} m={m} N={n} ov={ov} mod={md}: {got} vs {want} ({e:e})"
            );
        }
        assert!(worst < 1e-9);
    }

    /// White PM, unmodified, ⌈M/S⌉ ≤ d (Greenhall & Riley case 4, exact finite
    /// sum): AllanTools raises there, so the reference is its exact
    /// `edf_greenhall_simple(2, d, m, S, F=m, N)`. (d, m, N, overlapping, edf);
    /// generator section "greenhall_exact".
    #[rustfmt::skip]
    const ALLANTOOLS_WPM_EXACT: &[(u32, usize, usize, bool, f64)] = &[
        (2, 10, 31, false, 1.3846153846153844),
        (2, 10, 31, true, 10.177570093457945),
        (2, 10, 36, true, 12.0),
        (2, 3, 16, true, 6.081081081081078),
        (2, 50, 200, true, 69.23076923076924),
        (2, 1, 4, false, 1.3846153846153846),
        (3, 10, 31, false, 1.0),
        (3, 10, 31, true, 1.0),
        (3, 10, 36, true, 5.999999999999999),
        (3, 3, 16, true, 4.195205479452055),
        (3, 50, 200, true, 50.0),
        (3, 1, 4, false, 1.0),
    ];

    #[test]
    fn white_pm_short_records_match_exact_sum() {
        for &(d, m, n, ov, want) in ALLANTOOLS_WPM_EXACT {
            let got = greenhall_edf(2, d, m, n, ov, false).expect("edf");
            assert!(
                rel(got, want) < 1e-12,
                "d={d} m={m} N={n} ov={ov}: {got} vs {want}"
            );
        }
    }

    /// PHASE.DAT (1001 phase points), α = 0, AllanTools columns of the
    /// reference table "phase_dat_edf_ci_allantools_vs_stable32.txt":
    /// (stat, m, dev, edf, ci_lo, ci_hi). The AllanTools intervals there are
    /// at AllanTools' default level erf(1/√2) = 0.682 69 (its header says
    /// 0.683, Stable32's rounding; the digits match only the former).
    #[rustfmt::skip]
    const PHASE_DAT_ALPHA0: &[(Stat, usize, f64, f64, f64, f64)] = &[
        (Stat::Adev, 1, 2.9223187811e-01, 782.0303, 2.85114e-01, 2.99910e-01),
        (Stat::Adev, 2, 2.0510161559e-01, 356.32215, 1.97831e-01, 2.13237e-01),
        (Stat::Adev, 4, 1.4942714244e-01, 171.39104, 1.41970e-01, 1.58198e-01),
        (Stat::Adev, 8, 1.1013480328e-01, 84.10129, 1.02541e-01, 1.19711e-01),
        (Stat::Adev, 16, 6.2381339810e-02, 41.178943, 5.65095e-02, 7.05687e-02),
        (Stat::Adev, 32, 5.6232944726e-02, 20.294332, 4.91529e-02, 6.76321e-02),
        (Stat::Adev, 64, 3.2549905440e-02, 9.5609756, 2.71090e-02, 4.35362e-02),
        (Stat::Adev, 128, 3.3855195122e-02, 4.2352941, 2.64809e-02, 5.57371e-02),
        (Stat::Oadev, 1, 2.9223187811e-01, 782.0303, 2.85114e-01, 2.99910e-01),
        (Stat::Oadev, 2, 2.0101604217e-01, 540.68119, 1.95172e-01, 2.07419e-01),
        (Stat::Oadev, 4, 1.4479130722e-01, 306.09157, 1.39277e-01, 1.51017e-01),
        (Stat::Oadev, 8, 1.0570385008e-01, 165.98781, 1.00350e-01, 1.12017e-01),
        (Stat::Oadev, 16, 6.1914778419e-02, 86.370102, 5.76960e-02, 6.72185e-02),
        (Stat::Oadev, 32, 4.8082142621e-02, 43.351181, 4.36542e-02, 5.42038e-02),
        (Stat::Oadev, 64, 3.6237212986e-02, 21.239475, 3.17565e-02, 4.33728e-02),
        (Stat::Oadev, 128, 2.7673855821e-02, 9.5509533, 2.30463e-02, 3.70214e-02),
        (Stat::Mdev, 1, 2.9223187811e-01, 782.0303, 2.85114e-01, 2.99910e-01),
        (Stat::Mdev, 2, 1.5820719830e-01, 478.99615, 1.53334e-01, 1.63577e-01),
        (Stat::Mdev, 4, 1.0779737454e-01, 239.99577, 1.03196e-01, 1.13074e-01),
        (Stat::Mdev, 8, 7.4192200128e-02, 118.87305, 6.98143e-02, 7.95124e-02),
        (Stat::Mdev, 16, 4.1375946276e-02, 58.275185, 3.80220e-02, 4.58092e-02),
        (Stat::Mdev, 32, 3.4254980866e-02, 27.979687, 3.04660e-02, 3.99322e-02),
        (Stat::Mdev, 64, 2.7871051150e-02, 12.848469, 2.36872e-02, 3.55134e-02),
        (Stat::Mdev, 128, 1.8669328743e-02, 5.3215479, 1.48736e-02, 2.85814e-02),
        (Stat::Tdev, 1, 1.6872015349e-01, 782.0303, 1.64611e-01, 1.73153e-01),
        (Stat::Tdev, 2, 1.8268193705e-01, 478.99615, 1.77055e-01, 1.88882e-01),
        (Stat::Tdev, 4, 2.4894737283e-01, 239.99577, 2.38321e-01, 2.61134e-01),
        (Stat::Tdev, 8, 3.4267909372e-01, 118.87305, 3.22458e-01, 3.67252e-01),
        (Stat::Tdev, 16, 3.8221461953e-01, 58.275185, 3.51232e-01, 4.23167e-01),
        (Stat::Tdev, 32, 6.3286791758e-01, 27.979687, 5.62865e-01, 7.37755e-01),
        (Stat::Tdev, 64, 1.0298469686e+00, 12.848469, 8.75253e-01, 1.31224e+00),
        (Stat::Tdev, 128, 1.3796789728e+00, 5.3215479, 1.09917e+00, 2.11219e+00),
        (Stat::Hdev, 1, 2.9438832912e-01, 608.54867, 2.86301e-01, 3.03203e-01),
        (Stat::Hdev, 2, 2.0715738327e-01, 271.96597, 1.98818e-01, 2.16643e-01),
        (Stat::Hdev, 4, 1.4889796754e-01, 131.08522, 1.40494e-01, 1.59016e-01),
        (Stat::Hdev, 8, 1.1649081417e-01, 64.275463, 1.07444e-01, 1.28289e-01),
        (Stat::Hdev, 16, 5.9588687701e-02, 31.300622, 5.32954e-02, 6.88094e-02),
        (Stat::Hdev, 32, 5.4696896160e-02, 15.183551, 4.69874e-02, 6.80956e-02),
        (Stat::Hdev, 64, 3.0568640170e-02, 6.9610984, 2.48694e-02, 4.36506e-02),
        (Stat::Hdev, 128, 3.8059909299e-02, 2.866242, 2.88408e-02, 7.38188e-02),
        (Stat::Ohdev, 1, 2.9438832912e-01, 608.54867, 2.86301e-01, 3.03203e-01),
        (Stat::Ohdev, 2, 2.0124832957e-01, 451.67172, 1.94874e-01, 2.08293e-01),
        (Stat::Ohdev, 4, 1.4368033065e-01, 256.71957, 1.37738e-01, 1.50465e-01),
        (Stat::Ohdev, 8, 1.0987226371e-01, 139.70894, 1.03849e-01, 1.17082e-01),
        (Stat::Ohdev, 16, 6.0637629214e-02, 72.541436, 5.61728e-02, 6.63698e-02),
        (Stat::Ohdev, 32, 4.5095032827e-02, 37.207363, 4.06643e-02, 5.13821e-02),
        (Stat::Ohdev, 64, 3.3823708981e-02, 17.123049, 2.92718e-02, 4.14769e-02),
        (Stat::Ohdev, 128, 2.9146632236e-02, 7.1512678, 2.37612e-02, 4.13628e-02),
    ];

    #[test]
    fn phase_dat_edf_and_intervals_match_allantools() {
        for &(stat, m, dev, edf, lo, hi) in PHASE_DAT_ALPHA0 {
            let got = edf_for(stat, 0, m, 1001).expect("edf");
            // EDF printed with 8 significant digits, bounds with 6.
            assert!(rel(got, edf) < 1e-7, "{stat} m={m}: {got} vs {edf}");
            let (l, h) = crate::confidence::chi2_interval(dev, got, ONE_SIGMA);
            assert!(rel(l, lo) < 6e-6, "{stat} m={m}: lo {l} vs {lo}");
            assert!(rel(h, hi) < 6e-6, "{stat} m={m}: hi {h} vs {hi}");
        }
    }

    /// AllanTools 2024.6 `ci.edf_totdev(N, m, alpha)`: (alpha, m, N, edf);
    /// generator section "totdev".
    #[rustfmt::skip]
    const ALLANTOOLS_TOTDEV: &[(i32, usize, usize, f64)] = &[
        (2, 1, 1001, 500.499),
        (2, 16, 1001, 492.86192893401017),
        (2, 256, 1001, 328.84429530201345),
        (2, 1000, 100000, 49495.444444444445),
        (1, 1, 1001, 610.4140845416039),
        (1, 16, 1001, 262.7905446669035),
        (1, 256, 1001, 16.543703024723026),
        (1, 1000, 100000, 4137.3068046382905),
        (0, 1, 1001, 1501.5),
        (0, 16, 1001, 93.84375),
        (0, 256, 1001, 5.865234375),
        (0, 1000, 100000, 150.0),
        (-1, 1, 1001, 1170.9499999999998),
        (-1, 16, 1001, 72.97812499999999),
        (-1, 256, 1001, 4.3548828125),
        (-1, 1000, 100000, 116.78),
        (-2, 1, 1001, 930.57),
        (-2, 16, 1001, 57.823125000000005),
        (-2, 256, 1001, 3.2764453125000004),
        (-2, 1000, 100000, 92.64),
    ];

    /// AllanTools 2024.6 `ci.edf_mtotdev(N, m, alpha)`: (alpha, m, N, edf);
    /// generator section "mtotdev".
    #[rustfmt::skip]
    const ALLANTOOLS_MTOTDEV: &[(i32, usize, usize, f64)] = &[
        (2, 1, 1001, 1899.8),
        (2, 16, 1001, 116.76875),
        (2, 256, 1001, 5.329296874999999),
        (2, 1000, 100000, 187.9),
        (1, 1, 1001, 1199.8),
        (1, 16, 1001, 73.675),
        (1, 256, 1001, 3.2921875000000003),
        (1, 1000, 100000, 118.6),
        (0, 1, 1001, 1099.9),
        (0, 16, 1001, 67.61875),
        (0, 256, 1001, 3.1011718750000004),
        (0, 1000, 100000, 108.80000000000001),
        (-1, 1, 1001, 850.35),
        (-1, 16, 1001, 52.678125),
        (-1, 256, 1001, 2.8236328125),
        (-1, 1000, 100000, 84.5),
        (-2, 1, 1001, 750.44),
        (-2, 16, 1001, 46.611875),
        (-2, 256, 1001, 2.6226171875),
        (-2, 1000, 100000, 74.69),
    ];

    #[test]
    fn total_statistics_match_allantools() {
        for &(alpha, m, n, want) in ALLANTOOLS_TOTDEV {
            let got = edf_for(Stat::Totdev, alpha, m, n).expect("totdev edf");
            assert!(
                rel(got, want) < 1e-12,
                "totdev alpha={alpha} m={m}: {got} vs {want}"
            );
        }
        for &(alpha, m, n, want) in ALLANTOOLS_MTOTDEV {
            for stat in [Stat::Mtotdev, Stat::Ttotdev] {
                let got = edf_for(stat, alpha, m, n).expect("mtotdev edf");
                assert!(
                    rel(got, want) < 1e-12,
                    "{stat} alpha={alpha} m={m}: {got} vs {want}"
                );
            }
        }
        assert_eq!(edf_for(Stat::Totdev, -3, 4, 1001), None);
        assert_eq!(edf_for(Stat::Mtotdev, -4, 4, 1001), None);
    }

    #[test]
    fn htotdev_uses_fit_from_m16_and_ohdev_below() {
        // Stable32 1.60 on PHASE.DAT, white FM (allantools_phasedat/
        // phase_dat_htotdev_octave.txt): m = 32 dev 4.4644e-2 in
        // [4.0870e-2, 4.9703e-2]; m = 64 dev 3.3576e-2 in [2.9694e-2, 3.9530e-2].
        for (m, dev, lo, hi) in [
            (32, 4.4644e-2, 4.0870e-2, 4.9703e-2),
            (64, 3.3576e-2, 2.9694e-2, 3.9530e-2),
        ] {
            let edf = edf_for(Stat::Htotdev, 0, m, 1001).expect("edf");
            let want = (1001.0 / m as f64) / (0.559 + 1.004 * m as f64 / 1001.0);
            assert!(rel(edf, want) < 1e-15);
            let (l, h) = crate::confidence::chi2_interval(dev, edf, 0.683);
            assert!(rel(l, lo) < 5e-4 && rel(h, hi) < 5e-4, "m={m}: ({l}, {h})");
        }
        for (alpha, m) in [(0, 8), (2, 64), (1, 128), (-3, 32), (-4, 16)] {
            assert_eq!(
                edf_for(Stat::Htotdev, alpha, m, 1001),
                edf_for(Stat::Ohdev, alpha, m, 1001),
                "alpha={alpha} m={m}"
            );
        }
    }

    #[test]
    fn theo1_formulas() {
        // Hand evaluation of the SP 1065 formulas at N = 1001, m = 100 (r = 75).
        let (n, r): (f64, f64) = (1001.0, 75.0);
        let cases = [
            (2, 0.86 * (n + 1.0) * (n - 100.0) / (n - r) * (r / (r + 1.14))),
            (
                0,
                ((4.1 * n + 0.8) / r - (3.1 * n + 6.5) / n) * (r.powf(1.5) / (r.powf(1.5) + 5.2)),
            ),
            (
                -1,
                (2.0 * n * n - 1.3 * n * r - 3.5 * r) / (n * r) * (r.powi(3) / (r.powi(3) + 2.3)),
            ),
        ];
        for (alpha, want) in cases {
            let got = edf_for(Stat::Theo1, alpha, 100, 1001).expect("theo1 edf");
            assert!(rel(got, want) < 1e-14, "alpha={alpha}: {got} vs {want}");
        }
        for alpha in -2..=2 {
            let e = edf_for(Stat::Theo1, alpha, 100, 1001).expect("theo1 edf");
            assert!(e > 1.0 && e < 1001.0, "alpha={alpha}: {e}");
        }
        assert_eq!(edf_for(Stat::Theo1, -3, 100, 1001), None);
    }

    #[test]
    fn tables_agree_with_the_exact_sum_where_they_take_over() {
        // Overlapped estimators with (d + 1)·m just above Jmax use Greenhall &
        // Riley's Tables 1–3; the exact BasicSum of eq. (10) at the same point
        // must agree within the tables' few-percent fit accuracy.
        let n = 5000;
        for d in [2u32, 3] {
            let m = J_MAX / (d as usize + 1) + 1;
            for alpha in (2 - 2 * d as i32)..=2 {
                for modified in [false, true] {
                    let table = greenhall_edf(alpha, d, m, n, true, modified).expect("edf");
                    let head = if modified { m } else { 1 };
                    let big_m = (1 + n - head - m * d as usize) as f64;
                    let s = m as f64;
                    let j = (f64::from(d) + 1.0) * s;
                    let f = if modified {
                        1.0
                    } else if alpha <= 0 {
                        f64::INFINITY
                    } else {
                        m as f64
                    };
                    let exact = big_m * sz(0.0, f, alpha, d).powi(2) / basic_sum(j, big_m, s, f, alpha, d);
                    assert!(
                        rel(table, exact) < 0.03,
                        "alpha={alpha} d={d} modified={modified}: table {table}, exact {exact}"
                    );
                }
            }
        }
    }

    #[test]
    fn invalid_combinations_are_none() {
        assert_eq!(greenhall_edf(-2, 1, 4, 1000, true, false), None);
        assert_eq!(greenhall_edf(-3, 2, 4, 1000, true, false), None);
        assert_eq!(greenhall_edf(-5, 3, 4, 1000, true, false), None);
        assert_eq!(greenhall_edf(3, 2, 4, 1000, true, false), None);
        assert_eq!(greenhall_edf(0, 4, 4, 1000, true, false), None);
        assert_eq!(greenhall_edf(0, 2, 0, 1000, true, false), None);
        assert_eq!(greenhall_edf(0, 2, 400, 800, true, false), None);
        assert_eq!(greenhall_edf(0, 3, 300, 1001, false, true), None);
        assert_eq!(greenhall_edf(0, 2, usize::MAX, 10, true, false), None);
        for stat in Stat::ALL {
            assert_eq!(edf_for(stat, 0, 0, 1000), None, "{stat}");
            assert_eq!(edf_for(stat, 0, 5, 0), None, "{stat}");
            assert_eq!(edf_for(stat, 7, 5, 1000), None, "{stat}");
        }
        assert_eq!(edf_for(Stat::Adev, -3, 4, 1000), None);
        assert!(edf_for(Stat::Hdev, -4, 4, 1000).is_some());
    }

    #[test]
    fn edf_is_positive_and_finite_whenever_some() {
        for stat in Stat::ALL {
            for alpha in -5..=3 {
                for m in [1usize, 2, 3, 5, 16, 33, 64, 250, 999, 1000, 5000] {
                    for n in [0usize, 1, 2, 3, 7, 30, 100, 1001, 65_536] {
                        if let Some(e) = edf_for(stat, alpha, m, n) {
                            assert!(e.is_finite() && e > 0.0, "{stat} {alpha} {m} {n}: {e}");
                        }
                    }
                }
            }
        }
    }
}
