//! Chi-squared confidence intervals for Allan-family deviations.
//!
//! An Allan-family variance estimate σ̂² with ν equivalent degrees of freedom
//! is modelled as σ̂² ≈ σ²·χ²_ν/ν (NIST SP 1065, eq. 45). The two-sided
//! interval of confidence `c` for the true σ² is then
//!
//! ```text
//! ν·σ̂² / χ²((1+c)/2, ν)  ≤  σ²  ≤  ν·σ̂² / χ²((1−c)/2, ν)
//! ```
//!
//! which is what Stable32 prints as "Min Sigma" / "Max Sigma" and AllanTools
//! returns from `ci.confidence_interval`.
//!
//! The chi-squared quantile is computed here rather than taken from `statrs`:
//! `statrs` 0.19's `ChiSquared::inverse_cdf` is off by up to 1.6e-7 relative
//! at small degrees of freedom (k = 0.5, p = 0.025; 1.3e-10 at k = 1.3,
//! p = 0.975) and fails in the far tails (p = 1e-10), while a few EDF are
//! common at long τ. [`chi2_quantile`] solves P(k/2, x/2) = p by Halley steps
//! on an incomplete gamma function whose prefactor `x^a e^{−x}/Γ(a)` is
//! evaluated as `−a·(λ − 1 − ln λ)` plus the Stirling series, which keeps it
//! exact to a few ulps for the large k of short τ on long recordings.

use std::f64::consts::PI;

use statrs::function::erf::erfc_inv;
use statrs::function::gamma::ln_gamma;

/// The "one sigma" confidence level erf(1/√2) = 0.682 689 492 137 085 85,
/// AllanTools' `ONE_SIGMA_CI`. Stable32 rounds it to 0.683.
pub const ONE_SIGMA: f64 = 0.682_689_492_137_085_9;

/// Two-sided confidence interval `(dev_lo, dev_hi)` of a deviation `dev`
/// estimated with `edf` equivalent degrees of freedom (NIST SP 1065, eq. 45):
///
/// ```text
/// dev_lo = dev·√(edf / χ²((1+c)/2, edf)),   dev_hi = dev·√(edf / χ²((1−c)/2, edf))
/// ```
///
/// as AllanTools' `ci.confidence_interval` for `c ≥ 0.5` (AllanTools folds a
/// level below one half onto `1 − c`; here `c` always means the probability
/// the interval covers the true value).
///
/// Degenerate inputs never panic:
/// * `edf` NaN or ≤ 0, `confidence` outside (0, 1), or `dev` NaN → `(NaN, NaN)`;
/// * `edf = +∞` (a noiseless estimate) → `(dev, dev)`.
pub fn chi2_interval(dev: f64, edf: f64, confidence: f64) -> (f64, f64) {
    chi2_interval_from(dev, edf, confidence, interval_quantiles)
}

/// The chi-squared quantiles [`chi2_interval`] scales by, upper then lower,
/// for `edf` at `confidence`.
pub(crate) fn interval_quantiles(edf: f64, confidence: f64) -> (f64, f64) {
    let p_hi = 0.5 * (1.0 + confidence);
    let p_lo = 0.5 * (1.0 - confidence);
    (chi2_quantile(p_hi, edf), chi2_quantile(p_lo, edf))
}

/// [`chi2_interval`] with its quantiles from `quantiles` (called as
/// [`interval_quantiles`] is), so that a curve can reuse them where its
/// points share an EDF: the non-overlapping statistics' EDF depends on the
/// number of terms, and with every τ on the grid thousands of points share
/// a few hundred values.
pub(crate) fn chi2_interval_from(
    dev: f64,
    edf: f64,
    confidence: f64,
    quantiles: impl FnOnce(f64, f64) -> (f64, f64),
) -> (f64, f64) {
    if dev.is_nan() || edf.is_nan() || edf <= 0.0 || !(confidence > 0.0 && confidence < 1.0) {
        return (f64::NAN, f64::NAN);
    }
    if edf.is_infinite() {
        return (dev, dev);
    }
    let (chi2_hi, chi2_lo) = quantiles(edf, confidence);
    (dev * (edf / chi2_hi).sqrt(), dev * (edf / chi2_lo).sqrt())
}

/// The `p`-quantile of the chi-squared distribution with `k` degrees of
/// freedom (`k` real and positive): the `x` with `P(k/2, x/2) = p`, `P` the
/// regularized lower incomplete gamma function.
///
/// Accurate to a few 1e-15 relative: checked against SciPy's `chi2.ppf` for
/// k from 0.5 to 1e5 and p from 1e-10 to 1 − 1e-10 (worst 3e-15), and against
/// 40-digit mpmath solutions at k = 1e7 and 1e9 (where SciPy itself is off by
/// up to 1.4e-7). Below p = 1e-10 the accuracy falls with the depth of the
/// tail, as the incomplete gamma function's prefactor exp(a·ln x − x −
/// lnΓ(a)) loses digits: 3e-11 at p = 1e-300 and k = 100 against mpmath.
/// The start is the Wilson–Hilferty cube (or the small-x
/// series `x ≈ 2·(p·Γ(k/2+1))^{2/k}` in the lower tail of small k), refined by
/// bracketed Halley steps on `P` below the median and on the upper function
/// `Q` above it, so that both tails keep their relative accuracy. For
/// k > 1e10 the Wilson–Hilferty value itself is returned: its relative error
/// there is below 1e-14 for 1e-10 ≤ p ≤ 1 − 1e-10 (it falls as k^(−3/2)).
///
/// Edge values: `p ≤ 0` → 0 (and 0 when the quantile lies below the smallest
/// positive double, as for p = 1e-3 at k = 0.01); `p ≥ 1` → +∞; `p` or `k`
/// NaN, or `k ≤ 0` → NaN.
pub fn chi2_quantile(p: f64, k: f64) -> f64 {
    if p.is_nan() || k.is_nan() || k <= 0.0 {
        return f64::NAN;
    }
    if p <= 0.0 {
        return 0.0;
    }
    if p >= 1.0 {
        return f64::INFINITY;
    }
    if k.is_infinite() {
        return f64::INFINITY;
    }
    let wh = wilson_hilferty(p, k);
    if k > 1e10 {
        return wh;
    }
    2.0 * gamma_quantile(p, 0.5 * k, 0.5 * wh, Confirm::WhenCheap)
}

/// Whether [`gamma_quantile`] evaluates the function once more after a
/// Halley step whose remaining error is estimated to be below resolution.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Confirm {
    /// Only below a = 50, where an evaluation is cheap.
    WhenCheap,
    /// Always: the reference for the shortcut in tests.
    #[cfg(test)]
    Always,
}

/// Wilson–Hilferty approximation of the chi-squared quantile:
/// `k·(1 − 2/(9k) + z·√(2/(9k)))³`, `z` the standard normal quantile.
fn wilson_hilferty(p: f64, k: f64) -> f64 {
    let z = -std::f64::consts::SQRT_2 * erfc_inv(2.0 * p);
    let v = 2.0 / (9.0 * k);
    let c = 1.0 - v + z * v.sqrt();
    k * c * c * c
}

/// Solves `P(a, x) = p` for `x`, starting from the chi-squared
/// Wilson–Hilferty value `start` (already halved to the gamma scale).
fn gamma_quantile(p: f64, a: f64, start: f64, confirm: Confirm) -> f64 {
    let upper = p > 0.5;
    // Target in the tail being solved: P for the lower half, Q for the upper.
    let target = if upper { 1.0 - p } else { p };

    // Lower tail of small shape: P(a, x) ≈ x^a/Γ(a+1) for small x.
    let mut x = if !upper && (a < 0.5 || start <= 0.0) {
        let log_x = (p.ln() + ln_gamma(a + 1.0)) / a;
        if log_x < f64::MIN_POSITIVE.ln() - 1.0 {
            // The quantile lies below the smallest positive double.
            return 0.0;
        }
        log_x.exp()
    } else {
        start
    };
    if !(x.is_finite() && x > 0.0) {
        x = a.max(f64::MIN_POSITIVE);
    }

    let mut lo = 0.0_f64;
    let mut hi = f64::INFINITY;
    for _ in 0..200 {
        let (pl, qu, log_density) = incomplete_gamma(a, x);
        // f(x) = tail(x) − target; f'(x) = ± density.
        let (f, sign) = if upper {
            (qu - target, -1.0)
        } else {
            (pl - target, 1.0)
        };
        if f == 0.0 {
            return x;
        }
        // Maintain the bracket: f increases with x in the lower tail and
        // decreases in the upper one.
        if (f > 0.0) == (sign > 0.0) {
            hi = hi.min(x);
        } else {
            lo = lo.max(x);
        }
        let density = log_density.exp();
        let mut next = f64::NAN;
        if density > 0.0 && density.is_finite() {
            let t = f / (sign * density);
            // Halley: f''/f' = (a − 1)/x − 1 for the gamma density; only as a
            // correction to a Newton step it does not overturn.
            let slope = (a - 1.0) / x - 1.0;
            let h = 0.5 * t * slope;
            let halley = h.abs() < 0.5;
            let step = if halley { t / (1.0 - h) } else { t };
            if step.abs() <= 4.0 * f64::EPSILON * x {
                // Below the resolution of x: converged.
                return x - step;
            }
            // Halley's error after a step e is C·e³ + O(e⁴), with
            // |C| = |3f''² − 2f'f'''|/(12f'²) = (s² + 2(a − 1)/x²)/12 for the
            // gamma density (s = f''/f' above). The step stands in for the
            // error before it and the O(e⁴) term is dropped: an estimate,
            // not a bound. It is held to a sixteenth of the resolution of x,
            // where at a ≥ 50 the dropped terms are about a hundredth of the
            // kept one, and a test compares the result with the confirmed
            // root over k = 100 to 1e10. Then evaluating the function once
            // more (O(√a) terms at large a, the whole cost) would only
            // confirm the step. Below a = 50 the evaluation is cheap and the
            // confirmed root is kept.
            if halley && a >= 50.0 && confirm == Confirm::WhenCheap {
                let c = (slope * slope + 2.0 * (a - 1.0) / (x * x)) / 12.0;
                let e = step.abs();
                let landed = x - step;
                if c * e * e * e <= f64::EPSILON * x / 16.0 && landed > lo && landed < hi {
                    #[cfg(test)]
                    tests::SHORTCUTS.with(|n| n.set(n.get() + 1));
                    return landed;
                }
            }
            next = x - step;
        }
        if !(next.is_finite() && next > lo && next < hi) {
            next = if hi.is_infinite() {
                2.0 * x.max(lo)
            } else if lo <= 0.0 {
                hi.min(x) / 1024.0
            } else {
                // Geometric bisection keeps relative resolution near 0.
                lo.sqrt() * hi.sqrt()
            };
        }
        x = next;
        if hi.is_finite() && hi - lo <= 4.0 * f64::EPSILON * hi {
            break;
        }
    }
    x
}

/// Regularized incomplete gamma functions `(P(a, x), Q(a, x), ln density)`
/// for a > 0, x > 0, where `ln density = ln(x^{a−1} e^{−x}/Γ(a))` is the log
/// of dP/dx. Series for x < a + 1, Lentz continued fraction otherwise
/// (Numerical Recipes §6.2), with the common prefactor from [`log_prefactor`].
fn incomplete_gamma(a: f64, x: f64) -> (f64, f64, f64) {
    let log_pre = log_prefactor(a, x);
    let log_density = log_pre - x.ln();
    let pre = log_pre.exp();
    const EPS: f64 = 1e-17;
    let max_iter = 1000 + (100.0 * a.sqrt()) as usize;
    if x < a + 1.0 {
        // P = x^a e^{-x}/Γ(a+1) · Σ x^n / ((a+1)…(a+n))
        let mut term = 1.0;
        let mut sum = 1.0;
        let mut ap = a;
        for _ in 0..max_iter {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * EPS {
                break;
            }
        }
        let p = pre / a * sum;
        (p, 1.0 - p, log_density)
    } else {
        // Q = x^a e^{-x}/Γ(a) · 1/(x+1−a− 1·(1−a)/(x+3−a− …))
        const TINY: f64 = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / TINY;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..max_iter {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < TINY {
                d = TINY;
            }
            c = b + an / c;
            if c.abs() < TINY {
                c = TINY;
            }
            d = 1.0 / d;
            let del = d * c;
            h *= del;
            if (del - 1.0).abs() < EPS {
                break;
            }
        }
        let q = pre * h;
        (1.0 - q, q, log_density)
    }
}

/// `ln(x^a e^{−x} / Γ(a))`, accurate to a few ulps in relative terms of the
/// exponential even for large `a`: written as
/// `−a·(λ − 1 − ln λ) + ½·ln(a/2π) − s(a)` with λ = x/a and `s` the Stirling
/// remainder of ln Γ, the large terms `a ln x`, `x` and `ln Γ(a)` never
/// cancel numerically.
fn log_prefactor(a: f64, x: f64) -> f64 {
    if a < 10.0 {
        return a * x.ln() - x - ln_gamma(a);
    }
    let u = (x - a) / a;
    -a * u_minus_ln1p(u) + 0.5 * (a / (2.0 * PI)).ln() - stirling_remainder(a)
}

/// `u − ln(1 + u)` without cancellation for small |u|.
fn u_minus_ln1p(u: f64) -> f64 {
    if u.abs() > 0.5 {
        return u - u.ln_1p();
    }
    // ln(1+u) = 2·atanh(v), v = u/(2+u), u = 2v/(1−v):
    // u − ln(1+u) = 2v²/(1−v) − 2·Σ_{j≥1} v^{2j+1}/(2j+1).
    let v = u / (2.0 + u);
    let v2 = v * v;
    let mut pow = v * v2;
    let mut series = 0.0;
    let mut j = 3.0;
    while j < 80.0 {
        let t = pow / j;
        series += t;
        if t.abs() <= 1e-18 * series.abs() {
            break;
        }
        pow *= v2;
        j += 2.0;
    }
    2.0 * v2 / (1.0 - v) - 2.0 * series
}

/// Stirling remainder `ln Γ(a) − [(a − ½)·ln a − a + ½·ln 2π]` for a ≥ 10
/// (asymptotic series, Abramowitz & Stegun 6.1.41; error < 1e-17 at a = 10).
fn stirling_remainder(a: f64) -> f64 {
    let r = 1.0 / a;
    let r2 = r * r;
    r * (1.0 / 12.0
        - r2 * (1.0 / 360.0
            - r2 * (1.0 / 1260.0
                - r2 * (1.0 / 1680.0 - r2 * (1.0 / 1188.0 - r2 * (691.0 / 360_360.0 - r2 / 156.0))))))
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::stats::mtotdev::tests::rel;

    /// SciPy 1.17.1 `scipy.stats.chi2.ppf(p, k)` as (p, k, quantile), printed
    /// with repr(); generator: crates/allan/tests/fixtures/edf_ci_noise_id_reference.py,
    /// section "chi2".
    #[rustfmt::skip]
    const SCIPY_CHI2_PPF: &[(f64, f64, f64)] = &[
        (1e-10, 0.5, 1.3499395786223568e-40),
        (0.001, 0.5, 1.3499395786230753e-12),
        (0.025, 0.5, 5.273202591259991e-07),
        (0.15865525393145707, 0.5, 0.0008556197281856074),
        (0.5, 0.5, 0.0873476047057468),
        (0.8413447460685429, 0.5, 0.9642659623670375),
        (0.975, 0.5, 3.433235299960771),
        (0.999, 0.5, 8.752888515773373),
        (0.9999999999, 0.5, 38.949754531329184),
        (1e-10, 1.0, 1.570796326794896e-20),
        (0.001, 1.0, 1.5707971492624921e-06),
        (0.025, 1.0, 0.0009820691171752555),
        (0.15865525393145707, 1.0, 0.04006950463364094),
        (0.5, 1.0, 0.454936423119572),
        (0.8413447460685429, 1.0, 1.986996713315955),
        (0.975, 1.0, 5.023886187314888),
        (0.999, 1.0, 10.827566170662733),
        (0.9999999999, 1.0, 41.82145620298279),
        (1e-10, 1.3, 7.016252155184617e-16),
        (0.001, 1.3, 4.124215835985001e-05),
        (0.025, 1.3, 0.005844964263359177),
        (0.15865525393145707, 1.3, 0.10331590396681263),
        (0.5, 1.3, 0.7224479953305966),
        (0.8413447460685429, 1.3, 2.5282499263274625),
        (0.975, 1.3, 5.798739072378018),
        (0.999, 1.3, 11.819760403024947),
        (0.9999999999, 1.3, 43.21861331937424),
        (1e-10, 2.0, 2.0000000000999938e-10),
        (0.001, 2.0, 0.002001000667167068),
        (0.025, 2.0, 0.05063561596857975),
        (0.15865525393145707, 2.0, 0.3455075580468999),
        (0.5, 2.0, 1.386294361119891),
        (0.8413447460685429, 2.0, 3.6820432900185267),
        (0.975, 2.0, 7.377758908227871),
        (0.999, 2.0, 13.815510557964274),
        (0.9999999999, 2.0, 46.05170169440018),
        (1e-10, 3.7, 1.0639328667515664e-05),
        (0.001, 3.7, 0.06541446898331545),
        (0.025, 3.7, 0.39457687534151664),
        (0.15865525393145707, 3.7, 1.2344688691169152),
        (0.5, 3.7, 3.058889359041863),
        (0.8413447460685429, 3.7, 6.182150901765616),
        (0.975, 3.7, 10.618055248352459),
        (0.999, 3.7, 17.825651694608457),
        (0.9999999999, 3.7, 51.75868619887729),
        (1e-10, 10.0, 0.05233106563190542),
        (0.001, 10.0, 1.4787434638356647),
        (0.025, 10.0, 3.2469727802368413),
        (0.15865525393145707, 10.0, 5.680617711186441),
        (0.5, 10.0, 9.34181776559197),
        (0.8413447460685429, 10.0, 14.325506344521887),
        (0.975, 10.0, 20.483177350807388),
        (0.999, 10.0, 29.58829844507442),
        (0.9999999999, 10.0, 68.16761795190413),
        (1e-10, 99.5, 34.11939234519243),
        (0.001, 99.5, 61.52708616693587),
        (0.025, 99.5, 73.79141617807683),
        (0.15865525393145707, 99.5, 85.44084596727944),
        (0.5, 99.5, 98.83413326473534),
        (0.8413447460685429, 99.5, 113.55975207663366),
        (0.975, 99.5, 128.99168071113425),
        (0.999, 99.5, 148.8399433380598),
        (0.9999999999, 99.5, 216.99210086282253),
        (1e-10, 1000.5, 741.6971041437723),
        (0.001, 1000.5, 867.944542800829),
        (0.025, 1000.5, 914.7352397714009),
        (0.15865525393145707, 1000.5, 955.782395300021),
        (0.5, 1000.5, 999.8334123638368),
        (0.8413447460685429, 1000.5, 1045.2176639544823),
        (0.975, 1000.5, 1090.0528270754237),
        (0.999, 1000.5, 1144.4516340289265),
        (0.9999999999, 1000.5, 1311.8740007144684),
        (1e-10, 12345.0, 11371.597677156962),
        (0.001, 12345.0, 11865.124182466927),
        (0.025, 12345.0, 12038.928503121802),
        (0.15865525393145707, 12345.0, 12187.873726179245),
        (0.5, 12345.0, 12344.333339734065),
        (0.8413447460685429, 12345.0, 12502.126278621183),
        (0.975, 12345.0, 12654.86006450563),
        (0.999, 12345.0, 12836.274938908327),
        (0.9999999999, 12345.0, 13371.020387530429),
        (1e-10, 100000.0, 97181.37981805389),
        (0.001, 100000.0, 98623.7038163696),
        (0.025, 100000.0, 99125.37330064735),
        (0.15865525393145707, 100000.0, 99552.7878955091),
        (0.5, 100000.0, 99999.33333412347),
        (0.8413447460685429, 100000.0, 100447.2121050835),
        (0.975, 100000.0, 100878.41530566558),
        (0.999, 100000.0, 101387.69553252945),
        (0.9999999999, 100000.0, 102871.2418753302),
    ];

    /// Very large k, where SciPy's `chi2.ppf` itself drifts (1.4e-7 relative
    /// at k = 1e7, p = 1e-10): quantiles solved at 40 digits in mpmath from
    /// the power series of P(a, x); generator section "chi2_big".
    #[rustfmt::skip]
    const MPMATH_CHI2_PPF: &[(f64, f64, f64)] = &[
        (1e-10, 10000000.0, 9971577.52444181),
        (0.025, 10000000.0, 9991236.669053895),
        (0.15865525393145707, 10000000.0, 9995527.864194075),
        (0.5, 10000000.0, 9999999.333333341),
        (0.8413447460685429, 10000000.0, 10004472.135805931),
        (0.975, 10000000.0, 10008767.119557811),
        (0.9999999999, 10000000.0, 10028475.097706908),
        (1e-10, 1000000000.0, 999715538.4968599),
        (0.025, 1000000000.0, 999912349.6402636),
        (0.15865525393145707, 1000000000.0, 999955278.6404649),
        (0.5, 1000000000.0, 999999999.3333334),
        (0.8413447460685429, 1000000000.0, 1000044721.3595351),
        (0.975, 1000000000.0, 1000087654.1483482),
        (0.9999999999, 1000000000.0, 1000284514.1247824),
    ];

    #[test]
    fn chi2_quantile_matches_mpmath_for_huge_k() {
        for &(p, k, want) in MPMATH_CHI2_PPF {
            let got = chi2_quantile(p, k);
            assert!(
                rel(got, want) < 1e-13,
                "p={p} k={k}: got {got:e}, mpmath {want:e}"
            );
        }
    }

    thread_local! {
        /// Quantiles returned by the unconfirmed step on this thread.
        pub(super) static SHORTCUTS: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
    }

    /// Distance in units in the last place between two positive doubles.
    fn ulps(a: f64, b: f64) -> u64 {
        a.to_bits().abs_diff(b.to_bits())
    }

    /// The Halley step taken without the confirming evaluation lands where
    /// the confirmed iteration does, within three ulps, from k = 100 to 1e10
    /// and p from 1e-10 to 1 − 1e-10 (1771 quantiles), and it is taken. The
    /// worst pairs, at p = 1e-10 and k = 126 and 141, are one and two ulps
    /// either side of mpmath's root. In
    /// the far lower tail (p = 1e-100 and 1e-300, 322 more), where
    /// `incomplete_gamma` is accurate to about 1e-11 and the root with it,
    /// the two agree to that accuracy: the confirmed root there is up to
    /// 3e-11 from mpmath's (k = 100, p = 1e-300), the unconfirmed one 2e-11.
    #[test]
    fn the_unconfirmed_step_is_the_confirmed_root() {
        let mut worst = 0;
        let (mut count, before) = (0, SHORTCUTS.with(|n| n.get()));
        for i in 0..=160 {
            let k = 10f64.powf(2.0 + 8.0 * f64::from(i) / 160.0);
            for p in [
                1e-300,
                1e-100,
                1e-10,
                1e-3,
                0.025,
                0.158_655_253_931_457_07,
                0.3,
                0.5,
                0.7,
                0.841_344_746_068_542_9,
                0.975,
                0.999,
                1.0 - 1e-10,
            ] {
                let start = 0.5 * wilson_hilferty(p, k);
                let quick = gamma_quantile(p, 0.5 * k, start, Confirm::WhenCheap);
                let sure = gamma_quantile(p, 0.5 * k, start, Confirm::Always);
                assert!(quick > 0.0 && sure > 0.0, "p={p} k={k}: {quick} {sure}");
                if p < 1e-10 {
                    // The function itself is known to about 1e-11 there,
                    // and the confirmed root is no closer to the truth.
                    assert!(rel(quick, sure) <= 1e-10, "p={p} k={k}: {quick} vs {sure}");
                } else {
                    worst = worst.max(ulps(quick, sure));
                }
                count += 1;
            }
        }
        let taken = SHORTCUTS.with(|n| n.get()) - before;
        assert_eq!(count, 2093);
        assert!(worst <= 3, "worst {worst} ulps");
        // Most quantiles take it: a test of the shortcut that never fired
        // would test nothing.
        assert!(
            taken > count / 2,
            "the unconfirmed step was taken {taken} times in {count}"
        );
    }

    #[test]
    fn chi2_quantile_matches_scipy() {
        let mut worst: f64 = 0.0;
        for &(p, k, want) in SCIPY_CHI2_PPF {
            let got = chi2_quantile(p, k);
            let e = rel(got, want);
            worst = worst.max(e);
            assert!(e < 1e-12, "p={p} k={k}: got {got:e}, scipy {want:e}, rel {e:e}");
        }
        assert!(worst < 1e-12, "worst {worst:e}");
    }

    #[test]
    fn chi2_quantile_edges() {
        assert_eq!(chi2_quantile(0.0, 3.0), 0.0);
        assert_eq!(chi2_quantile(-1.0, 3.0), 0.0);
        assert_eq!(chi2_quantile(1.0, 3.0), f64::INFINITY);
        assert!(chi2_quantile(f64::NAN, 3.0).is_nan());
        assert!(chi2_quantile(0.5, 0.0).is_nan());
        assert!(chi2_quantile(0.5, -2.0).is_nan());
        assert!(chi2_quantile(0.5, f64::NAN).is_nan());
        // k = 2: exponential with mean 2, x = −2 ln(1−p).
        for p in [1e-300_f64, 1e-12, 0.1, 0.5, 0.9, 1.0 - 1e-12] {
            let want = -2.0 * (-p).ln_1p();
            assert!(rel(chi2_quantile(p, 2.0), want) < 1e-13, "p={p}");
        }
        // Huge k answers the Wilson–Hilferty value, ≈ k.
        let q = chi2_quantile(0.5, 1e12);
        assert!(rel(q, 1e12) < 1e-11);
    }

    #[test]
    fn chi2_quantile_is_monotone_and_finite_on_odd_inputs() {
        let ks = [1e-300, 1e-5, 0.01, 0.1, 0.5, 3.0, 1e3, 1e8, 2e10, 1e300];
        let ps = [1e-300, 1e-100, 1e-16, 1e-3, 0.3, 0.5, 0.7, 0.999, 1.0 - 1e-16];
        for k in ks {
            let mut last = 0.0;
            for p in ps {
                let q = chi2_quantile(p, k);
                assert!(q.is_finite() && q >= 0.0, "p={p} k={k}: {q}");
                assert!(q >= last, "p={p} k={k}: {q} < {last}");
                last = q;
            }
        }
    }

    #[test]
    fn incomplete_gamma_is_consistent_across_branches() {
        for a in [0.25, 1.0, 7.5, 12.0, 500.0, 5e4] {
            for xf in [0.5, 0.99, 1.0, 1.01, 2.0] {
                let x = a * xf;
                let (p, q, _) = incomplete_gamma(a, x);
                assert!((p + q - 1.0).abs() < 1e-14, "a={a} x={x}");
                assert!((0.0..=1.0).contains(&p));
            }
        }
    }

    /// AllanTools 2024.6 `ci.confidence_interval(dev, edf, ci)` as
    /// (dev, edf, ci, lo, hi); generator section "ci".
    #[rustfmt::skip]
    const ALLANTOOLS_CI: &[(f64, f64, f64, f64, f64)] = &[
        (0.29223187811, 782.0303, 0.683, 0.2851099391324045, 0.2999152966845259),
        (0.29223187811, 782.0303, 0.6826894921370859, 0.2851144907798555, 0.299910344494585),
        (0.29223187811, 782.0303, 0.9, 0.28060194067900135, 0.3049551900625441),
        (0.29223187811, 782.0303, 0.95, 0.27844018960654593, 0.3074717702388051),
        (0.29223187811, 782.0303, 0.99, 0.27429497009048265, 0.3124906496077131),
        (0.033855195122, 4.2352941, 0.683, 0.02647591818658808, 0.05575396170283421),
        (0.033855195122, 4.2352941, 0.6826894921370859, 0.026480904878640812, 0.05573712783465115),
        (0.033855195122, 4.2352941, 0.9, 0.0221807716881548, 0.07755259195299738),
        (0.033855195122, 4.2352941, 0.95, 0.020502230907316215, 0.09312182709332018),
        (0.033855195122, 4.2352941, 0.99, 0.01780375524690108, 0.13954917914716566),
        (1.0, 1.3, 0.683, 0.716835877031267, 3.549977422577684),
        (1.0, 1.3, 0.6826894921370859, 0.7170702000924581, 3.5472196877138553),
        (1.0, 1.3, 0.9, 0.5348294393748623, 8.735419343608424),
        (1.0, 1.3, 0.95, 0.47348354724430075, 14.913540091801021),
        (1.0, 1.3, 0.99, 0.3847950013224608, 51.475690454753014),
        (0.0025, 54321.0, 0.683, 0.002492444798320983, 0.0025076242859834114),
        (0.0025, 54321.0, 0.6826894921370859, 0.0024924496419430264, 0.002507619393113194),
        (0.0025, 54321.0, 0.9, 0.002487591094494005, 0.002512543354111669),
        (0.0025, 54321.0, 0.95, 0.0024852226871543465, 0.002514955328327013),
        (0.0025, 54321.0, 0.99, 0.0024806046143345207, 0.0025196805424862272),
    ];

    #[test]
    fn interval_matches_allantools() {
        for &(dev, edf, c, lo, hi) in ALLANTOOLS_CI {
            let (l, h) = chi2_interval(dev, edf, c);
            assert!(
                rel(l, lo) < 1e-12,
                "dev={dev} edf={edf} c={c}: lo {l:e} vs {lo:e}"
            );
            assert!(
                rel(h, hi) < 1e-12,
                "dev={dev} edf={edf} c={c}: hi {h:e} vs {hi:e}"
            );
        }
    }

    #[test]
    fn interval_on_phase_dat_table() {
        // Reference table "phase_dat_edf_ci_allantools_vs_stable32.txt": OADEV
        // of PHASE.DAT, AllanTools columns dev, edf, CI_at (6 digits), at
        // AllanTools' default level erf(1/√2).
        let rows = [
            (2.0101604217e-01, 540.68119, 1.95172e-01, 2.07419e-01),
            (6.1914778419e-02, 86.370102, 5.76960e-02, 6.72185e-02),
            (2.7673855821e-02, 9.5509533, 2.30463e-02, 3.70214e-02),
        ];
        for (dev, edf, lo, hi) in rows {
            let (l, h) = chi2_interval(dev, edf, ONE_SIGMA);
            assert!(rel(l, lo) < 6e-6 && rel(h, hi) < 6e-6, "{l} {h} vs {lo} {hi}");
        }
    }

    #[test]
    fn interval_degenerate_inputs() {
        assert!(chi2_interval(1.0, 0.0, 0.683).0.is_nan());
        assert!(chi2_interval(1.0, -3.0, 0.683).1.is_nan());
        assert!(chi2_interval(1.0, f64::NAN, 0.683).0.is_nan());
        assert!(chi2_interval(f64::NAN, 10.0, 0.683).0.is_nan());
        assert!(chi2_interval(1.0, 10.0, 1.0).0.is_nan());
        assert!(chi2_interval(1.0, 10.0, 0.0).0.is_nan());
        assert_eq!(chi2_interval(2.0, f64::INFINITY, 0.9), (2.0, 2.0));
        assert_eq!(chi2_interval(0.0, 10.0, 0.9), (0.0, 0.0));
        let (lo, hi) = chi2_interval(1.0, 0.3, 0.95);
        assert!(lo > 0.0 && lo < 1.0 && hi > 1.0 && hi.is_finite());
    }
}
