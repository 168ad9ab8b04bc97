"""AllanTools 2024.6's ``allantools.allantools`` module: the statistics,
the conversions and the tau grid functions.

The eleven statistics imutherm computes (adev, oadev, mdev, tdev, hdev,
ohdev, totdev, mtotdev, ttotdev, htotdev, theo1) run on imutherm's engine,
on AllanTools' tau grid ("octave", "decade", "all", "log10" or taus in
seconds, each rounded to whole samples, up to AllanTools' own limits rather
than imutherm's stop ratio), with AllanTools' simple error bars
(``errs = devs / sqrt(ns)``, ``devs / sqrt(N - m)`` for Theo1). Like
AllanTools, Theo1's taus are m/rate although its variance is normalised for
0.75 m/rate (NIST SP 1065 eq. 30); ``imutherm.theo1`` reports the latter.

Gaps differ: NaN samples inside the data are skipped by adev, oadev, mdev,
tdev, hdev and ohdev and refused by the others, where AllanTools returns
NaN deviations. An infinite sample gives NaN deviations, as in AllanTools,
with a warning.

The other names (PDEV, GRADEV, MTIE, TIE rms, the Groslambert codeviation,
the three-cornered hat, psd2allan, the conversions and the tau grid functions) are
computed here from their published definitions, cited at each function.
"""

import warnings

import numpy as np

from .. import _imutherm
from .._samples import as_samples
from . import ci

#: The AllanTools release whose interface this module follows.
__version__ = "2024.06"

#: The statistics computed by imutherm's engine.
ENGINE_STATISTICS = ("adev", "oadev", "mdev", "tdev", "hdev", "ohdev",
                     "totdev", "mtotdev", "ttotdev", "htotdev", "theo1")


def tau_generator(data, rate, taus=None, v=False, even=False, maximum_m=-1):
    """The averaging factors of ``taus`` on ``data``: ``(data, m, taus)``.

    ``taus`` is "octave" (the default, also for None or an empty list),
    "decade" (1, 2, 4, 10, 20, 40, ...), "all", "log10" (about ten per
    decade) or taus in seconds, each rounded to a whole number of samples;
    factors below 1, at or beyond ``len(data)`` or beyond ``maximum_m`` are
    left out, duplicates merged, and with ``even`` only even factors kept
    (Theo1). A ``rate`` of 0 raises ``RuntimeError``, as in AllanTools."""
    data = np.asarray(data)
    m = _factors(len(data), rate, taus, even=even, maximum_m=maximum_m)
    if v:
        print("tau_generator:", m)
    return data, m, m / float(rate)


def _factors(length, rate, taus, even=False, maximum_m=-1):
    """:func:`tau_generator`'s averaging factors on ``length`` samples."""
    if rate == 0:
        raise RuntimeError("rate is 0: the sample rate must be positive")
    tau0 = 1.0 / rate
    if taus is None or (isinstance(taus, list) and len(taus) == 0):
        taus = "octave"
    if isinstance(taus, str):
        if taus == "all":
            taus = tau0 * np.linspace(1.0, length, length)
        elif taus == "octave":
            top = int(np.floor(np.log2(length)))
            taus = tau0 * np.logspace(0, top, top + 1, base=2.0)
        elif taus == "log10":
            top = np.log10(length)
            taus = tau0 * np.logspace(0, top, int(10 * top), base=10.0)
        elif taus == "decade":
            top = int(np.floor(np.log10(length)))
            taus = [f * tau0 * 10.0 ** k for k in range(top + 1) for f in (1.0, 2.0, 4.0)]
        else:
            raise ValueError(f"taus: unknown grid {taus!r} (expected octave, decade, all, log10 "
                             "or seconds)")
    m = np.round(np.atleast_1d(np.asarray(taus, dtype=np.float64)) * float(rate))
    limit = length if maximum_m == -1 else maximum_m
    m = np.unique(m[(m < length) & (m > 0) & (m <= limit)])
    if len(m) == 0:
        warnings.warn(f"no tau of {taus!r} fits {length} samples at {rate} Hz", RuntimeWarning,
                      stacklevel=3)
    if even:
        m = m[m % 2 == 0]
    return m


def tau_reduction(ms, rate, n_per_decade):
    """At most ``n_per_decade`` of the averaging factors ``ms`` per decade:
    a factor is kept when ``n_per_decade * log10`` of the next one rounds to
    another integer (the last factor is dropped). Returns ``(ms, taus)``."""
    ms = np.asarray(ms, dtype=np.int64)
    slot = np.rint(n_per_decade * np.log10(ms))
    keep = slot[1:] != slot[:-1]
    ms = ms[:-1][keep]
    return ms, ms / float(rate)


def remove_small_ns(taus, devs, deverrs, ns):
    """The points with more than one term (``ns > 1``); ``deverrs`` is an
    array or a ``[lower, upper]`` pair. Raises ``UserWarning`` when none
    is left, as AllanTools does."""
    keep = np.asarray(ns) > 1
    if isinstance(deverrs, list):
        if len(deverrs) > 2:
            raise ValueError("deverrs: an array or a [lower, upper] pair")
        errs = [np.asarray(deverrs[0])[keep], np.asarray(deverrs[1])[keep]]
    else:
        errs = np.asarray(deverrs)[keep]
    if not keep.any():
        raise UserWarning("no tau has more than one term")
    return np.asarray(taus)[keep], np.asarray(devs)[keep], errs, np.asarray(ns)[keep]


def trim_data(x):
    """``x`` without its leading and trailing NaN samples."""
    x = np.asarray(x)
    valid = np.flatnonzero(~np.isnan(x))
    if len(valid) == 0:
        raise IndexError("trim_data: every sample is NaN")
    return x[valid[0]:valid[-1] + 1]


def frequency2phase(freqdata, rate):
    """Phase (time error, s) from fractional frequency ``freqdata``:
    x_0 = 0, x_{i+1} = x_i + (y_i - mean y) / rate (NIST SP 1065 eq. 2,
    the frequency offset removed), after trimming NaN edges; N + 1 points."""
    y = trim_data(np.asarray(freqdata, dtype=np.float64))
    y = y - np.nanmean(y)
    return np.concatenate(([0.0], np.cumsum(y) / float(rate)))


def phase2frequency(phase, rate):
    """Fractional frequency from phase: y_i = (x_{i+1} - x_i) * rate
    (NIST SP 1065 eq. 3); N - 1 points."""
    return rate * np.diff(phase)


def phase2radians(phasedata, v0):
    """Phase in seconds to radians at the nominal frequency ``v0`` Hz."""
    return 2.0 * np.pi * v0 * np.asarray(phasedata, dtype=np.float64)


def frequency2fractional(frequency, mean_frequency=-1):
    """Frequencies in Hz to fractional frequency (f - f0) / f0, with f0
    ``mean_frequency`` or, when -1, the mean of ``frequency``. Returns a
    list, as AllanTools does."""
    mu = np.mean(frequency) if mean_frequency == -1 else mean_frequency
    return [(f - mu) / mu for f in frequency]


def input_to_phase(data, rate, data_type):
    """``data`` as phase: itself, or integrated by :func:`frequency2phase`."""
    if data_type == "phase":
        return data
    if data_type == "freq":
        return frequency2phase(data, rate)
    raise ValueError(f"unknown data_type: {data_type} (expected phase or freq)")


def _check(data_type, rate):
    if data_type not in ("phase", "freq"):
        raise ValueError(f"unknown data_type: {data_type} (expected phase or freq)")
    if rate == 0:
        raise RuntimeError("rate is 0: the sample rate must be positive")
    rate = float(rate)
    if not (np.isfinite(rate) and rate > 0):
        raise ValueError(f"invalid sample rate {rate} Hz: it must be positive and finite")
    return rate


def _engine_grid(stat, n_phase, rate, taus):
    """AllanTools' grid for ``stat`` on a phase series of ``n_phase``
    points (for HTOTDEV, on the frequency series)."""
    if stat == "htotdev":
        return _factors(n_phase - 1, rate, taus, maximum_m=(n_phase - 1) / 3.0)
    if stat in ("mtotdev", "ttotdev"):
        return _factors(n_phase, rate, taus, maximum_m=n_phase / 3.0)
    return _factors(n_phase, rate, taus, even=(stat == "theo1"))


def _deviation(stat, data, rate, data_type, taus):
    rate = _check(data_type, rate)
    y = as_samples(data, "data")
    n_phase = len(y) + 1 if data_type == "freq" else len(y)
    m = _engine_grid(stat, n_phase, rate, taus)
    factors = m.astype(np.int64).tolist()
    try:
        devs, ns = _imutherm.estimates(stat, y, rate, data_type, factors)
    except _imutherm.ImuthermError as e:
        # The engine refuses an infinite sample; AllanTools' arithmetic turns
        # it into NaN (or inf) deviations. Found on the refusal rather than
        # by a scan of every call's data, which would cost a pass.
        if "is infinite" not in str(e):
            raise
        infinite = np.isinf(y)
        warnings.warn(f"data: {int(infinite.sum())} infinite samples (first at "
                      f"{int(np.argmax(infinite))}): the deviations are NaN", RuntimeWarning,
                      stacklevel=3)
        _, ns = _imutherm.estimates(stat, np.where(infinite, 0.0, y), rate, data_type, factors)
        devs = np.full(len(factors), np.nan)
    ns = ns.astype(np.float64)
    if stat == "theo1":
        errs = devs / np.sqrt(n_phase - m)
    else:
        errs = devs / np.sqrt(ns)
    return remove_small_ns(m / rate, devs, errs, ns)


def _dropin(stat, summary):
    def compute(data, rate=1.0, data_type="phase", taus=None):
        return _deviation(stat, data, rate, data_type, taus)

    compute.__name__ = compute.__qualname__ = stat
    compute.__doc__ = f"""{summary}

    AllanTools' ``{stat}(data, rate=1.0, data_type="phase", taus=None)``,
    computed by imutherm's engine: returns ``(taus, devs, errs, ns)``, NumPy
    arrays. ``data_type`` defaults to "phase" as in AllanTools; pass "freq"
    for rate data.
    """
    return compute


adev = _dropin("adev", "Non-overlapped Allan deviation.")
oadev = _dropin("oadev", "Overlapping Allan deviation.")
mdev = _dropin("mdev", "Modified Allan deviation.")
tdev = _dropin("tdev", "Time deviation.")
hdev = _dropin("hdev", "Hadamard deviation.")
ohdev = _dropin("ohdev", "Overlapping Hadamard deviation.")
totdev = _dropin("totdev", "Total deviation.")
mtotdev = _dropin("mtotdev", "Modified total deviation (no bias correction).")
ttotdev = _dropin("ttotdev", "Time total deviation (no bias correction).")
htotdev = _dropin("htotdev", "Hadamard total deviation (no bias correction).")
theo1 = _dropin("theo1", "Theo1 deviation (no bias correction), at taus m/rate as AllanTools labels them.")


def _phase_and_factors(data, rate, data_type, taus, **grid):
    rate = _check(data_type, rate)
    phase = np.asarray(input_to_phase(np.asarray(data, dtype=np.float64), rate, data_type),
                       dtype=np.float64)
    _, m, taus_used = tau_generator(phase, rate, taus, **grid)
    return phase, m.astype(np.int64), taus_used, rate


def _second_differences(phase, m):
    """x_{i+2m} - 2 x_{i+m} + x_i for every i (NIST SP 1065 eq. 9)."""
    n = len(phase) - 2 * m
    if n <= 0:
        return np.empty(0)
    return phase[2 * m:] - 2.0 * phase[m:m + n] + phase[:n]


def calc_hdev_phase(phase, rate, mj, stride):
    """One Hadamard deviation point: ``(dev, err, n)`` with third
    differences x_{i+3m} - 3x_{i+2m} + 3x_{i+m} - x_i taken every
    ``stride`` samples (NIST SP 1065 eq. 18 for stride m, eq. 20 for 1)."""
    mj, stride = int(mj), int(stride)
    x = np.asarray(phase, dtype=np.float64)
    n_all = len(x) - 3 * mj
    if n_all <= 0:
        return 0.0, 0.0, 0
    d = (x[3 * mj:] - 3.0 * x[2 * mj:2 * mj + n_all] + 3.0 * x[mj:mj + n_all] - x[:n_all])[::stride]
    n = len(d)
    dev = np.sqrt(np.sum(d * d) / (6.0 * n)) / mj * rate
    return dev, dev / np.sqrt(n), n


def calc_mtotdev_phase(phase, rate, m):
    """One MTOTDEV point ``(dev, err, n)`` by imutherm's engine (NIST SP
    1065 eq. 27)."""
    phase = as_samples(phase, "phase")
    devs, ns = _imutherm.estimates("mtotdev", phase, float(rate), "phase", [int(m)])
    n = int(ns[0])
    dev = float(devs[0])
    return dev, dev / np.sqrt(n) if n else 0.0, n


def calc_htotdev_freq(freq, m):
    """One HTOTDEV point ``(dev, err, n)`` of fractional frequency ``freq``
    at unit rate, by imutherm's engine (NIST SP 1065 eq. 29)."""
    freq = as_samples(freq, "freq")
    devs, ns = _imutherm.estimates("htotdev", freq, 1.0, "freq", [int(m)])
    n = int(ns[0])
    dev = float(devs[0])
    return dev, dev / np.sqrt(n) if n else 0.0, n


def pdev(data, rate=1.0, data_type="phase", taus=None):
    """Parabolic deviation (Vernotte et al. 2015, "The parabolic variance
    (PVAR)", Metrologia 53; estimator of Vernotte et al. 2020 eq. 8): at
    m = 1 it equals ADEV; for m > 1

        PVAR(m tau0) = 72 / (M m^4 (m tau0)^2) sum_{i=0}^{M-1}
                       [ sum_{k=0}^{m-1} ((m-1)/2 - k) (x_{i+k} - x_{i+k+m}) ]^2,

    M = N - 2m. Returns ``(taus, devs, errs, ns)``, errs = dev / sqrt(M)."""
    phase, ms, taus_used, rate = _phase_and_factors(data, rate, data_type, taus)
    devs = np.zeros(len(ms))
    ns = np.zeros(len(ms))
    tau0 = 1.0 / rate
    for j, m in enumerate(ms):
        if m == 1:
            d = _second_differences(phase, 1)
            n = max(len(d), 1)
            devs[j] = np.sqrt(np.sum(d * d) / (2.0 * n)) * rate
            ns[j] = n
            continue
        big_m = len(phase) - 2 * m
        if big_m < 1:
            continue
        w = (m - 1) / 2.0 - np.arange(m)
        diff = phase[:big_m + m - 1 + 1][:len(phase) - m] - phase[m:]
        # The inner sum at every i is a correlation of the differences with w.
        inner = np.correlate(diff[:big_m + m - 1], w, mode="valid")[:big_m]
        devs[j] = np.sqrt(72.0 * np.sum(inner * inner) / (big_m * m ** 4 * (m * tau0) ** 2))
        ns[j] = big_m
    errs = np.divide(devs, np.sqrt(ns), out=np.zeros_like(devs), where=ns > 0)
    return remove_small_ns(taus_used, devs, errs, ns)


def calc_pdev_phase(phase, rate, mj):
    """One PDEV point ``(dev, err, n)`` (see :func:`pdev`)."""
    taus, devs, errs, ns = pdev(phase, rate=rate, taus=[int(mj) / rate])
    return devs[0], errs[0], ns[0]


def calc_adev_phase(phase, rate, mj, stride):
    """One Allan deviation point ``(dev, err, n)`` of second differences
    taken every ``stride`` samples (NIST SP 1065 eq. 7 for stride m,
    eq. 9 for 1)."""
    d = _second_differences(np.asarray(phase, dtype=np.float64), int(mj))[::int(stride)]
    n = max(len(d), 1)
    dev = np.sqrt(np.sum(d * d) / (2.0 * n)) / mj * rate
    return dev, dev / np.sqrt(n), n


def calc_gcodev_phase(phase_1, phase_2, rate, mj, stride):
    """One Groslambert codeviation point ``(dev, err, n)``: the Allan
    covariance of the second differences of both series (Lantz et al.
    2019, arXiv:1904.05849, eq. 5), as sqrt(|cov|) (its sign is lost, as in
    AllanTools)."""
    mj, stride = int(mj), int(stride)
    d1 = _second_differences(np.asarray(phase_1, dtype=np.float64), mj)[::stride]
    d2 = _second_differences(np.asarray(phase_2, dtype=np.float64), mj)[::stride]
    n = min(len(d1), len(d2))
    if n == 0:
        return 0.0, 0.0, 0
    s = np.sum(d1[:n] * d2[:n])
    dev = np.sqrt(abs(s) / (2.0 * n)) / mj * rate
    return dev, dev / np.sqrt(n), n


def gcodev(data_1, data_2, rate=1.0, data_type="phase", taus=None):
    """Groslambert codeviation (Allan covariance) of two synchronous
    measurements AB and BC, which estimates the noise of the clock they
    share (Vernotte et al. 2016; Lantz et al. 2019): overlapping second
    differences (stride 1). Returns ``(taus, devs, errs, ns)``."""
    phase_1, ms, taus_used, rate = _phase_and_factors(data_1, rate, data_type, taus)
    phase_2, _, _, _ = _phase_and_factors(data_2, rate, data_type, taus)
    out = np.array([calc_gcodev_phase(phase_1, phase_2, rate, m, 1) for m in ms]).reshape(-1, 3)
    return remove_small_ns(taus_used, out[:, 0], out[:, 1], out[:, 2])


def calc_gradev_phase(data, rate, mj, stride, confidence, noisetype):
    """One gap-resistant ADEV point ``(dev, [err_lo, err_hi], n)``: the
    second differences not touching a NaN sample (Sesia et al. 2008,
    "Estimating the Allan variance in the presence of long periods of
    missing data and outliers", Metrologia 45), with the chi-squared
    interval at ``confidence`` for the EDF of :func:`ci.edf_simple`."""
    mj = int(mj)
    phase = np.asarray(data, dtype=np.float64)
    d = _second_differences(phase, mj)[::int(stride)]
    n = int(np.count_nonzero(~np.isnan(d)))
    n_valid = int(np.count_nonzero(~np.isnan(phase)))
    dev = np.sqrt(np.nansum(d * d) / (2.0 * max(n, 1))) / mj * rate
    alpha = {"wp": 2, "wf": 0, "fp": -2}.get(noisetype)
    if n > 1:
        edf = ci.edf_simple(n_valid, mj, alpha)
        err = ci.confidence_interval(dev, edf, ci=confidence)
    else:
        err = [0, 0]
    return dev, err, n


def gradev(data, rate=1.0, data_type="phase", taus=None, ci=0.9, noisetype="wp"):
    """Gap-resistant overlapping Allan deviation (Sesia et al. 2008): NaN
    samples are gaps, skipped term by term. Returns ``(taus, devs, [lo, hi],
    ns)``, where ``lo`` and ``hi`` bound the deviation at confidence ``ci``
    for the noise ``noisetype`` ("wp", "wf" or "fp": white PM, white FM,
    flicker PM)."""
    if data_type == "freq":
        warnings.warn("gradev: phase data is preferred (a gap in frequency data shifts the "
                      "phase after it)", RuntimeWarning, stacklevel=2)
    rate = _check(data_type, rate)
    phase = np.asarray(input_to_phase(np.asarray(data, dtype=np.float64), rate, data_type),
                       dtype=np.float64)
    _, ms, taus_used = tau_generator(phase, rate, taus)
    devs = np.zeros(len(ms))
    lo = np.zeros(len(ms))
    hi = np.zeros(len(ms))
    ns = np.zeros(len(ms))
    for j, m in enumerate(ms):
        devs[j], (lo[j], hi[j]), ns[j] = calc_gradev_phase(phase, rate, m, 1, ci, noisetype)
    return remove_small_ns(taus_used, devs, [lo, hi], ns)


def tierms(data, rate=1.0, data_type="phase", taus=None):
    """Time interval error, RMS: sqrt(mean((x_{i+m} - x_i)^2)) over the
    N - m pairs (ITU-T G.810, definition 4.5.13). The error bars are 0:
    AllanTools gives none. Returns ``(taus, devs, errs, ns)``."""
    phase, ms, taus_used, rate = _phase_and_factors(data, rate, data_type, taus)
    devs = np.array([np.sqrt(np.mean((phase[m:] - phase[:-m]) ** 2)) for m in ms])
    ns = (len(phase) - ms).astype(np.float64)
    return remove_small_ns(taus_used, devs, np.zeros(len(ms)), ns)


def _window_extremes(phase, widths):
    """For each window width in ``widths`` (ascending), the largest
    max - min of ``phase`` over the windows of that many samples, by a
    doubling table: the extreme of a window of w samples is that of two
    windows of 2^k <= w samples covering it."""
    out = []
    level, hi, lo = 1, phase.copy(), phase.copy()
    for w in widths:
        while 2 * level <= w:
            hi = np.maximum(hi[:-level], hi[level:])
            lo = np.minimum(lo[:-level], lo[level:])
            level *= 2
        count = len(phase) - w + 1
        shift = w - level
        span = (np.maximum(hi[:count], hi[shift:shift + count])
                - np.minimum(lo[:count], lo[shift:shift + count]))
        out.append(np.max(span))
    return np.array(out)


def mtie(data, rate=1.0, data_type="phase", taus=None):
    """Maximum time interval error: the largest peak-to-peak phase within a
    window of m + 1 samples, over all windows (ITU-T G.810 eq. 4-9).
    Returns ``(taus, devs, errs, ns)``, errs = dev / sqrt(N - m)."""
    phase, ms, taus_used, rate = _phase_and_factors(data, rate, data_type, taus)
    devs = _window_extremes(phase, [int(m) + 1 for m in ms]) if len(ms) else np.empty(0)
    ns = (len(phase) - ms).astype(np.float64)
    return remove_small_ns(taus_used, devs, devs / np.sqrt(ns), ns)


def mtie_rolling_window(a, window):
    """A read-only view of the windows of ``window`` consecutive samples of
    ``a`` along its last axis (one row per start). ``ValueError`` when
    ``window`` is below 1 or longer than ``a``."""
    if window < 1:
        raise ValueError("`window` must be at least 1.")
    if window > a.shape[-1]:
        raise ValueError("`window` is too long.")
    return np.lib.stride_tricks.sliding_window_view(a, window, axis=-1)


def mtie_phase_fast(phase, rate=1.0, data_type="phase", taus=None):
    """MTIE of the first 2^K samples over windows of 2^k samples
    (k = 1 ... K), by the doubling table of Bregni ("Fast algorithms for
    TVAR and MTIE computation", IEEE Trans. Instrum. Meas. 46, 1997): the
    extremes of a window of 2^k samples are those of its two halves.
    ``rate``, ``data_type`` and ``taus`` are ignored, and the window of
    2^k samples is labelled tau = 2^(k-1) samples, as in AllanTools, whose
    own test marks this function unfinished; :func:`mtie` is the reference.
    Returns ``(taus, devs, errs, ns)``, errs 0."""
    phase = np.asarray(phase, dtype=np.float64)
    k_max = int(np.floor(np.log2(len(phase))))
    phase = phase[:2 ** k_max]
    widths = [2 ** k for k in range(1, k_max + 1)]
    devs = _window_extremes(phase, widths)
    taus_used = np.array([2.0 ** (k - 1) for k in range(1, k_max + 1)])
    ns = np.array([len(phase) - w + 1 for w in widths], dtype=np.float64)
    return remove_small_ns(taus_used, devs, np.zeros(len(devs)), ns)


def three_cornered_hat_phase(phasedata_ab, phasedata_bc, phasedata_ca, rate, taus, function):
    """Clock A's deviation from three pairwise phase comparisons:
    sigma_A^2 = (sigma_AB^2 + sigma_CA^2 - sigma_BC^2) / 2, negative
    variances clamped to 0 (Gray & Allan 1974; Riley, "Handbook of frequency
    stability analysis", NIST SP 1065 section 12.3). ``function`` is one of
    this module's deviations. Returns ``(taus, devs, errs, ns)``, errs a
    list."""
    t_ab, d_ab, _, n_ab = function(phasedata_ab, data_type="phase", rate=rate, taus=taus)
    _, d_bc, _, _ = function(phasedata_bc, data_type="phase", rate=rate, taus=taus)
    _, d_ca, _, _ = function(phasedata_ca, data_type="phase", rate=rate, taus=taus)
    if not len(d_ab) == len(d_bc) == len(d_ca):
        raise ValueError("the three comparisons give different tau grids: give them equal lengths")
    var_a = np.clip(0.5 * (d_ab ** 2 + d_ca ** 2 - d_bc ** 2), 0.0, None)
    dev_a = np.sqrt(var_a)
    return t_ab, dev_a, [d / np.sqrt(n) for d, n in zip(dev_a, n_ab)], n_ab


def psd2allan(S_y, f=1.0, kind="adev", base=2):
    """ADEV or MDEV from a one-sided fractional-frequency PSD ``S_y`` at
    frequencies 0, df, 2 df, ... (``f`` the vector or df): the integrals

        AVAR(tau) = 2 int S_y(f) sin^4(pi f tau) / (pi f tau)^2 df,
        MVAR(tau) = 2 int S_y(f) sin^6(pi f tau) / (pi f tau)^4 df

    (NIST SP 1065 eq. 65 and Rutman 1978 for MVAR with its m^2 sin^2(pi f
    tau0) term approximated for large m), by Simpson's rule on the PSD
    interpolated four times finer. tau runs over powers of ``base`` of
    tau0 = 1 / f_max (all multiples when ``base`` <= 1). Returns
    ``(taus, devs)``."""
    if not isinstance(S_y, np.ndarray):
        raise ValueError("S_y must be a NumPy array")
    if isinstance(f, np.ndarray):
        df = f[1] - f[0]
    elif np.isscalar(f):
        df = f
    else:
        raise ValueError("f must be a NumPy array of frequencies or the step df")
    oversampling = 4
    f0 = np.arange(S_y.size) * oversampling * df
    fine = np.arange(df, (S_y.size - 1) * oversampling * df + df, df)
    fine = fine[fine <= f0[-1]]
    s_fine = _cubic_interpolation(f0, S_y, fine)
    fine = fine / oversampling
    tau0 = 1.0 / np.max(fine)
    n = 1.0 / df / tau0 / 2.0
    if base > 1:
        m = np.unique(np.round(np.append(base ** np.arange(np.floor(np.log(n) / np.log(base))), n)))
    else:
        m = np.arange(1, n)
    taus_used = m * tau0
    exponent = 1.0 if kind[0].lower() == "a" else 2.0
    x = np.pi * np.outer(taus_used, fine)
    integrand = s_fine * np.abs(np.sin(x) ** (exponent + 1.0) / x ** exponent) ** 2.0
    integrand = np.concatenate((np.zeros((len(m), 1)), integrand), axis=1)
    grid = np.concatenate(([0.0], fine))
    return taus_used, np.sqrt(2.0 * _simpson(integrand, grid))


def _cubic_interpolation(x, y, at):
    """The cubic spline through (x, y) at ``at``: SciPy's ``interp1d``
    (kind "cubic"), which psd2allan is defined with."""
    interpolate = _scipy("interpolate")
    return interpolate.interp1d(x, y, kind="cubic")(at)


def _simpson(y, x):
    """Simpson's rule along the last axis: SciPy's ``simpson``."""
    return _scipy("integrate").simpson(y, x=x)


def _scipy(module):
    import importlib
    try:
        return importlib.import_module(f"scipy.{module}")
    except ImportError as e:
        raise ImportError("psd2allan needs SciPy: pip install scipy (or imutherm[allantools])") from e
