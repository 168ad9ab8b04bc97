"""Equivalent degrees of freedom, confidence intervals and noise
identification, under AllanTools 2024.6's names.

Greenhall's EDF and the total-deviation tables are imutherm's engine
(crates/allan/src/edf.rs); the chi-squared quantiles too
(crates/allan/src/confidence.rs). The simple EDF approximations, the B1 and
R(n) ratios and the lag-1 autocorrelation identification are written here
from their publications, cited at each function.
"""

import math

import numpy as np

from .. import _imutherm

#: The probability of a normal variable within one standard deviation:
#: erf(1 / sqrt(2)), the default confidence of AllanTools' intervals.
ONE_SIGMA_CI = math.erf(1.0 / math.sqrt(2.0))


def confidence_interval(dev, edf, ci=ONE_SIGMA_CI):
    """The two-sided interval ``(dev_lo, dev_hi)`` of a deviation ``dev``
    with ``edf`` degrees of freedom at confidence ``ci``:
    var * edf / chi2(1 - (1 - ci)/2, edf) ... var * edf / chi2((1 - ci)/2, edf)
    (NIST SP 1065 eq. 45)."""
    tail = min(abs(ci), abs(ci - 1.0)) / 2.0
    var = dev * dev
    lo = float(edf) * var / _imutherm.chi2_quantile(1.0 - tail, float(edf))
    hi = float(edf) * var / _imutherm.chi2_quantile(tail, float(edf))
    return np.sqrt(lo), np.sqrt(hi)


_GREENHALL = {"adev": (2, False, False), "oadev": (2, True, False), "mdev": (2, True, True),
              "tdev": (2, True, True), "hdev": (3, False, False), "ohdev": (3, True, False)}


def confidence_interval_noiseID(x, dev, af, dev_type="adev", data_type="phase",
                                ci=ONE_SIGMA_CI):
    """The interval of ``dev`` at averaging factor ``af`` of ``x``, with the
    noise identified by :func:`autocorr_noise_id` (up to two differences,
    three for the Hadamard deviations) and Greenhall's EDF for
    ``dev_type`` (adev, oadev, mdev, tdev, hdev or ohdev; others raise
    ``NotImplementedError``). Returns ``(dev_lo, dev_hi)``."""
    if dev_type not in _GREENHALL:
        raise NotImplementedError(f"confidence_interval_noiseID: no EDF for {dev_type!r} "
                                  f"(expected one of {', '.join(_GREENHALL)})")
    d, overlapping, modified = _GREENHALL[dev_type]
    alpha = autocorr_noise_id(x, int(af), data_type=data_type, dmin=0, dmax=d)[0]
    edf = edf_greenhall(alpha=alpha, d=d, m=af, N=len(x), overlapping=overlapping,
                        modified=modified)
    return confidence_interval(dev, edf, ci)


def edf_greenhall(alpha, d, m, N, overlapping=False, modified=False, verbose=False):
    """Equivalent degrees of freedom of a difference-based variance (Greenhall
    & Riley 2003, "Uncertainty of stability variances based on finite
    differences", 35th PTTI): noise ``alpha`` (+2 ... -4), difference order
    ``d`` (1, 2 Allan, 3 Hadamard), averaging factor ``m``, ``N`` phase
    points, overlapping or not, modified or not. Requires alpha + 2d > 1
    (``AssertionError`` otherwise, as in AllanTools)."""
    if not alpha + 2 * d > 1:
        raise AssertionError(f"edf_greenhall: alpha + 2 d = {alpha + 2 * d} must exceed 1 "
                             "(the variance does not converge for this noise)")
    edf = _imutherm.greenhall_edf(int(alpha), int(d), int(m), int(N), bool(overlapping),
                                  bool(modified))
    if edf is None:
        raise ValueError(f"edf_greenhall: no EDF for alpha={alpha}, d={d}, m={m}, N={N} "
                         "(the record is shorter than one term)")
    if verbose:
        print(f"edf_greenhall: alpha={alpha} d={d} m={m} N={N} edf={edf}")
    return edf


def edf_totdev(N, m, alpha):
    """EDF of TOTDEV: b N/m - c of NIST SP 1065 Table 7 for white, flicker and
    random-walk FM (alpha 0, -1, -2), :func:`edf_simple` otherwise."""
    alpha = int(alpha)
    if alpha in (0, -1, -2):
        return _imutherm.edf_for("totdev", alpha, int(m), int(N))
    return edf_simple(N, m, alpha)


def edf_mtotdev(N, m, alpha):
    """EDF of MTOTDEV: b N/m - c of NIST SP 1065 Table 8 (alpha +2 ... -2;
    ``AssertionError`` otherwise, as in AllanTools)."""
    if alpha not in (2, 1, 0, -1, -2):
        raise AssertionError(f"edf_mtotdev: alpha = {alpha} is not one of 2, 1, 0, -1, -2")
    return _imutherm.edf_for("mtotdev", int(alpha), int(m), int(N))


def edf_simple(N, m, alpha):
    """EDF of the Allan variance by the simple approximations of NIST SP
    1065 Table 5 (Howe, Allan & Barnes 1981), N phase points, averaging
    factor m; an unknown ``alpha`` gives N - 1 with a printed note."""
    N, m = float(N), float(m)
    if alpha == 2:
        return (N + 1.0) * (N - 2.0 * m) / (2.0 * (N - m))
    if alpha == 1:
        return np.exp(np.sqrt(np.log((N - 1.0) / (2.0 * m))
                              * np.log((2.0 * m + 1.0) * (N - 1.0) / 4.0)))
    if alpha == 0:
        return (3.0 * (N - 1.0) / (2.0 * m) - 2.0 * (N - 2.0) / N) * 4.0 * m * m / (4.0 * m * m + 5.0)
    if alpha == -1:
        if m == 1:
            return 2.0 * (N - 2.0) / (2.3 * N - 4.9)
        return 5.0 * N * N / (4.0 * m * (N + 3.0 * m))
    if alpha == -2:
        return ((N - 2.0) / (m * (N - 3.0) ** 2)
                * ((N - 1.0) ** 2 - 3.0 * m * (N - 1.0) + 4.0 * m * m))
    print(f"edf_simple: noise alpha={alpha} not recognised; N - 1 degrees of freedom")
    return N - 1.0


def detrend(x, deg=1):
    """``x`` less its least-squares polynomial of degree ``deg`` in the
    sample index."""
    t = np.arange(len(x))
    return np.asarray(x, dtype=np.float64) - np.polyval(np.polyfit(t, x, deg), t)


def lag1_acf(x, detrend_deg=1):
    """The lag-1 autocorrelation of ``x`` about its mean:
    sum (x_n - mu)(x_{n+1} - mu) / sum (x_n - mu)^2 (Riley & Greenhall 2004,
    eq. 2). ``detrend_deg`` is kept for AllanTools' signature; ``x`` is
    used as given."""
    x = np.asarray(x, dtype=np.float64)
    c = x - np.mean(x)
    return np.dot(c[:-1], c[1:]) / np.dot(c, c)


def autocorr_noise_id(x, af, data_type="phase", dmin=0, dmax=2):
    """The power-law noise of ``x`` at averaging factor ``af`` by the lag-1
    autocorrelation (Riley & Greenhall 2004, "Power law noise
    identification using the lag 1 autocorrelation", 18th EFTF, sec. 3):
    phase data decimated by ``af`` with its quadratic removed, frequency data
    averaged over ``af`` with its line removed; differenced until
    delta = r1 / (1 + r1) < 0.25 (at least ``dmin``, at most ``dmax``
    times). Returns ``(alpha_int, alpha, d, delta)``, alpha = -2 (delta + d),
    plus 2 for phase data, and alpha_int = -round(2 delta) - 2 d (plus 2).
    Fewer than 30 points after decimation raise ``NotImplementedError``."""
    x = np.asarray(x, dtype=np.float64)
    af = int(af)
    if data_type == "phase":
        z = detrend(x[::af] if af > 1 else x, deg=2)
        shift = 2
    elif data_type == "freq":
        usable = len(x) - len(x) % af
        z = detrend(x[:usable].reshape(-1, af).mean(axis=1), deg=1)
        shift = 0
    else:
        raise ValueError(f"unknown data_type: {data_type} (expected phase or freq)")
    if len(z) < 30:
        raise NotImplementedError(f"autocorr_noise_id: {len(z)} points at af={af}; the lag-1 "
                                  "identification needs 30")
    d = 0
    while True:
        r1 = lag1_acf(z)
        delta = r1 / (1.0 + r1)
        if d >= dmin and (delta < 0.25 or d >= dmax):
            alpha = -2.0 * (delta + d) + shift
            alpha_int = int(-np.round(2.0 * delta) - 2.0 * d) + shift
            return alpha_int, alpha, d, delta
        z = np.diff(z)
        d += 1


def rn(x, af, rate):
    """R(n) = MVAR / AVAR of phase ``x`` at averaging factor ``af`` (Howe,
    Beard, Greenhall & Riley 2000, "A total estimator of the Hadamard
    function used for GPS operations", the R(n) noise test; NIST SP 1065
    sec. 5.6)."""
    from . import allantools as at
    tau = af / rate
    adev = at.adev(x, taus=[tau], data_type="phase", rate=rate)[1][0]
    mdev = at.mdev(x, taus=[tau], data_type="phase", rate=rate)[1][0]
    return (mdev / adev) ** 2


def rn_theory(af, b):
    """R(n) expected for phase-PSD exponent ``b``: 1/af for white PM
    (b = 0), the flicker-PM ratio with f_h = 1 / (2 tau0) for b = -1 (NIST
    SP 1065 Table 4 for AVAR, Bernier 1987 for MVAR), 1 otherwise."""
    if b == 0:
        return 1.0 / af
    if b == -1:
        avar = (1.038 + 3.0 * np.log(np.pi * af)) / (4.0 * np.pi ** 2)
        mvar = 3.0 * np.log(256.0 / 27.0) / (8.0 * np.pi ** 2)
        return mvar / avar
    return 1.0


def rn_boundary(af, b_hi):
    """The decision boundary between R(n) of ``b_hi`` and ``b_hi - 1``: their
    geometric mean."""
    return np.sqrt(rn_theory(af, b_hi) * rn_theory(af, b_hi - 1))


def b1(x, af, rate):
    """Barnes' B1 ratio of phase ``x`` at averaging factor ``af``: the
    sample variance of af-averages of the frequency over their Allan
    variance (Barnes 1969, NBS Tech. Note 375; NIST SP 1065 sec. 5.6)."""
    from . import allantools as at
    adev = at.adev(x, taus=[af * rate], data_type="phase", rate=rate)[1][0]
    y = np.diff(np.asarray(x, dtype=np.float64))
    usable = len(y) - len(y) % af
    means = y[:usable].reshape(-1, af).mean(axis=1)
    return np.var(means, ddof=1) / adev ** 2


def b1_theory(N, mu):
    """Expected B1 for N averages and tau exponent ``mu`` of the Allan
    variance (Barnes 1969, eq. 73): N(1 - N^mu) / (2(N - 1)(1 - 2^mu)),
    with its limits at mu = 2, 1, 0, -1 and the white-PM value at mu = -2."""
    N = float(N)
    if mu == 2:
        return N * (N + 1.0) / 6.0
    if mu == 1:
        return N / 2.0
    if mu == 0:
        return N * np.log(N) / (2.0 * (N - 1.0) * np.log(2.0))
    if mu == -1:
        return 1.0
    if mu == -2:
        return (N * N - 1.0) / (1.5 * N * (N - 1.0))
    return N * (1.0 - N ** mu) / (2.0 * (N - 1.0) * (1.0 - 2.0 ** mu))


def b_to_mu(b):
    """The Allan-variance tau exponent mu of phase-PSD exponent ``b``
    (alpha = b + 2; mu = -alpha - 1, limited to -2 for PM noise)."""
    a = b + 2
    if not -4 <= a <= 2:
        raise ValueError(f"b_to_mu: b = {b} outside -6 ... 0")
    return max(-a - 1, -2)


def b1_boundary(b_hi, N):
    """The decision boundary between B1 of ``b_hi`` and ``b_hi - 1``: the
    geometric mean of their expected B1."""
    lo = b1_theory(N, b_to_mu(b_hi - 1))
    hi = b1_theory(N, b_to_mu(b_hi))
    return np.sqrt(lo * hi) if lo >= -4 else 0.5 * (lo + hi)


# The steps of Greenhall & Riley's EDF algorithm, one function each as
# AllanTools offers them. They are the engine's (crates/allan/src/edf.rs:
# sw, sx, sz, basic_sum, table1-3) written again for NumPy scalars, so that
# the pieces can be looked at; edf_greenhall itself runs on the engine.

# Rows alpha = 2 ... -4, columns d = 1, 2, 3; None where the paper has no
# entry (the variance does not converge, or the case is not tabulated).
_TABLE1 = [[(2.0 / 3.0, 1.0 / 3.0), (7.0 / 9.0, 0.5), (22.0 / 25.0, 2.0 / 3.0)],
           [(0.840, 0.345), (0.997, 0.616), (1.141, 0.843)],
           [(1.079, 0.368), (1.033, 0.607), (1.184, 0.848)],
           [None, (1.048, 0.534), (1.180, 0.816)],
           [None, (1.302, 0.535), (1.175, 0.777)],
           [None, None, (1.194, 0.703)],
           [None, None, (1.489, 0.702)]]
_TABLE2 = [[(1.5, 0.5), (35.0 / 18.0, 1.0), (231.0 / 100.0, 1.5)],
           [(78.6, 25.2), (790.0, 410.0), (9950.0, 6520.0)],
           [(2.0 / 3.0, 1.0 / 6.0), (2.0 / 3.0, 1.0 / 3.0), (7.0 / 9.0, 0.5)],
           [None, (0.852, 0.375), (0.997, 0.617)],
           [None, (1.079, 0.368), (1.033, 0.607)],
           [None, None, (1.053, 0.553)],
           [None, None, (1.302, 0.535)]]
_TABLE3 = {1: (6.0, 4.0), 2: (15.23, 12.0), 3: (47.8, 40.0)}


def _table(table, alpha, d, name):
    if alpha not in range(-4, 3) or d not in (1, 2, 3):
        raise AssertionError(f"{name}: alpha = {alpha} outside +2 ... -4 or d = {d} outside 1 ... 3")
    entry = table[2 - alpha][d - 1]
    # (-1, -1) where the paper has no entry, as AllanTools marks it.
    return (-1, -1) if entry is None else entry


def greenhall_table1(alpha, d):
    """(a0, a1) of Greenhall & Riley 2003 Table 1 (modified variances);
    (-1, -1) where the table has no entry."""
    return _table(_TABLE1, alpha, d, "greenhall_table1")


def greenhall_table2(alpha, d):
    """(a0, a1) of Greenhall & Riley 2003 Table 2 (unmodified variances);
    (-1, -1) where the table has no entry. Its alpha = -4 row, which
    AllanTools' lookup refuses, is the paper's."""
    return _table(_TABLE2, alpha, d, "greenhall_table2")


def greenhall_table3(alpha, d):
    """(b0, b1) of Greenhall & Riley 2003 Table 3, s_z(0) ~ b0 + b1 ln m for
    flicker PM (``alpha`` must be 1)."""
    if alpha != 1 or d not in _TABLE3:
        raise AssertionError(f"greenhall_table3: flicker PM (alpha = 1) only, d in 1 ... 3; got "
                             f"alpha = {alpha}, d = {d}")
    return _TABLE3[d]


def greenhall_sw(t, alpha):
    """The generalized autocovariance s_w(t) of power-law noise alpha
    (Greenhall & Riley 2003, eq. 7): -|t|, t^2 ln|t|, |t|^3, -t^4 ln|t|,
    -|t|^5, t^6 ln|t|, |t|^7 for alpha = 2 ... -4 (0 at t = 0): the sign
    alternates with the order of the generalized covariance (that of
    Brownian motion is -|t|/2). AllanTools 2024.6 gives alpha = -1 and -2
    the other sign; every EDF is a ratio of squares of s_z, which the sign
    leaves alone."""
    t = abs(t)
    if alpha not in range(-4, 3):
        raise AssertionError(f"greenhall_sw: alpha = {alpha} outside +2 ... -4")
    if alpha in (1, -1, -3):
        if t == 0:
            return 0
        power = {1: 2, -1: 4, -3: 6}[alpha]
        return (-1.0 if alpha == -1 else 1.0) * t ** power * np.log(t)
    return {2: -t, 0: t ** 3, -2: -t ** 5, -4: t ** 7}[alpha]


def greenhall_sx(t, F, alpha):
    """s_x(t) after the pre-filter of factor F (eq. 8):
    F^2 (2 s_w(t) - s_w(t - 1/F) - s_w(t + 1/F)); F infinite gives
    s_w(t; alpha + 2)."""
    if np.isinf(F):
        return greenhall_sw(t, alpha + 2)
    h = 1.0 / F
    return F * F * (2.0 * greenhall_sw(t, alpha) - greenhall_sw(t - h, alpha)
                    - greenhall_sw(t + h, alpha))


def greenhall_sz(t, F, alpha, d):
    """s_z(t) of the d-th difference (eq. 9):
    sum_{k=-d..d} (-1)^k C(2d, d + k) s_x(t + k)."""
    if d not in (1, 2, 3):
        raise AssertionError(f"greenhall_sz: d = {d} outside 1 ... 3")
    total = math.comb(2 * d, d) * greenhall_sx(t, F, alpha)
    for k in range(1, d + 1):
        total += ((-1) ** k * math.comb(2 * d, d - k)
                  * (greenhall_sx(t - k, F, alpha) + greenhall_sx(t + k, F, alpha)))
    return total


def greenhall_BasicSum(J, M, S, F, alpha, d):
    """BasicSum of eq. (10): s_z(0)^2 + (1 - J/M) s_z(J/S)^2
    + 2 sum_{j=1}^{J-1} (1 - j/M) s_z(j/S)^2."""
    total = greenhall_sz(0, F, alpha, d) ** 2 + (1.0 - J / M) * greenhall_sz(J / S, F, alpha, d) ** 2
    for j in range(1, int(J)):
        total += 2.0 * (1.0 - j / M) * greenhall_sz(j / S, F, alpha, d) ** 2
    return total


def edf_greenhall_simple(alpha, d, m, S, F, N):
    """The EDF by the exact sum (eq. 13): L = m/F + m d, M = 1 + floor(S (N -
    L) / m), J = min(M, (d + 1) S), 1/edf = BasicSum / (s_z(0)^2 M)."""
    L = m / F + m * d
    M = 1 + np.floor(S * (N - L) / m)
    J = min(M, (d + 1) * S)
    inverse = greenhall_BasicSum(J, M, S, F, alpha, d) / (greenhall_sz(0, F, alpha, d) ** 2 * M)
    return 1.0 / inverse
