"""A drop-in for AllanTools' deviation functions, computed by imutherm.

``from imutherm import allantools as at`` in place of ``import allantools
as at``: the same function names, the same arguments (``data``, ``rate``,
``data_type``, ``taus``) and the same return tuple ``(taus, devs, errs,
ns)``, on the same tau grid ("octave", "decade", "all", "log10" or taus in
seconds, each rounded to whole samples, up to AllanTools' own limits rather
than imutherm's stop ratio), with AllanTools' simple error bars
(``errs = devs / sqrt(ns)``, ``devs / sqrt(N - m)`` for Theo1).

**The one difference from the main API:** as in AllanTools, ``data_type``
defaults to ``"phase"``. Gyro or accelerometer rates are ``"freq"`` data::

    >>> import numpy as np
    >>> from imutherm import allantools as at
    >>> rate = np.random.default_rng(0).standard_normal(10_000)
    >>> taus, devs, errs, ns = at.oadev(rate, rate=100.0, data_type="freq", taus="octave")
    >>> taus[:3]
    array([0.01, 0.02, 0.04])

Like AllanTools, Theo1's taus are m/rate although its variance is
normalised for 0.75 m/rate (NIST SP 1065 eq. 30); ``imutherm.theo1`` reports
the latter. For intervals from the identified noise type, use
``imutherm.oadev`` and its siblings, which return a :class:`imutherm.Curve`.

Gaps differ too: NaN samples inside the data are skipped by adev, oadev,
mdev, tdev, hdev and ohdev and refused by the others, where AllanTools
returns NaN deviations.
"""

import numpy as np

from . import _imutherm
from ._samples import as_samples

__all__ = ["adev", "oadev", "mdev", "tdev", "hdev", "ohdev",
           "totdev", "mtotdev", "ttotdev", "htotdev", "theo1"]


def _grid(length, rate, taus, maximum_m=None, even=False):
    """AllanTools' ``tau_generator``: the averaging factors of ``taus`` on a
    series of ``length`` points (allantools.py, tau_generator, 2024.6)."""
    tau0 = 1.0 / rate
    if taus is None or (isinstance(taus, list) and len(taus) == 0):
        taus = "octave"
    if isinstance(taus, str):
        if taus == "all":
            taus = tau0 * np.linspace(1.0, length, length)
        elif taus == "octave":
            maxn = np.floor(np.log2(length))
            taus = tau0 * np.logspace(0, int(maxn), int(maxn + 1), base=2.0)
        elif taus == "log10":
            maxn = np.log10(length)
            taus = tau0 * np.logspace(0, maxn, int(10 * maxn), base=10.0)
        elif taus == "decade":
            maxn = int(np.floor(np.log10(length)))
            taus = [f * tau0 * 10.0 ** k for k in range(maxn + 1) for f in (1.0, 2.0, 4.0)]
        else:
            raise ValueError(f"taus: unknown grid {taus!r} (expected octave, decade, all, log10 or seconds)")
    m = np.round(np.asarray(taus, dtype=np.float64) * rate)
    limit = length if maximum_m is None else maximum_m
    m = np.unique(m[(m < length) & (m > 0) & (m <= limit)])
    if even:
        m = m[m % 2 == 0]
    return m


def _deviation(stat, data, rate, data_type, taus):
    if data_type not in ("phase", "freq"):
        raise ValueError(f"unknown data_type: {data_type} (expected phase or freq)")
    rate = float(rate)
    if not (np.isfinite(rate) and rate > 0):
        raise ValueError(f"invalid sample rate {rate} Hz: it must be positive and finite")
    y = as_samples(data, "data")
    # The length AllanTools' tau grid is built on: the phase series, or for
    # HTOTDEV the frequency series.
    n_phase = len(y) + 1 if data_type == "freq" else len(y)
    if stat == "htotdev":
        n_freq = n_phase - 1
        m = _grid(n_freq, rate, taus, maximum_m=n_freq / 3.0)
    elif stat in ("mtotdev", "ttotdev"):
        m = _grid(n_phase, rate, taus, maximum_m=n_phase / 3.0)
    else:
        m = _grid(n_phase, rate, taus, even=(stat == "theo1"))
    devs, ns = _imutherm.estimates(stat, y, rate, data_type, m.astype(np.int64).tolist())
    ns = ns.astype(np.float64)
    keep = ns > 1  # AllanTools' remove_small_ns
    m, devs, ns = m[keep], devs[keep], ns[keep]
    if stat == "theo1":
        errs = devs / np.sqrt(n_phase - m)
    else:
        errs = devs / np.sqrt(ns)
    return m / rate, devs, errs, ns


def _dropin(stat, summary):
    def compute(data, rate=1.0, data_type="phase", taus=None):
        return _deviation(stat, data, rate, data_type, taus)

    compute.__name__ = compute.__qualname__ = stat
    compute.__doc__ = f"""{summary}

    AllanTools' ``{stat}(data, rate=1.0, data_type="phase", taus=None)``:
    returns ``(taus, devs, errs, ns)``, NumPy arrays. ``data_type`` defaults
    to "phase" as in AllanTools; pass "freq" for rate data.
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
