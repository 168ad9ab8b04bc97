"""A drop-in for AllanTools 2024.6, computed by imutherm.

``from imutherm import allantools as at`` in place of ``import allantools
as at``: the same names, arguments, return values, exceptions and
submodules (``allantools``, ``ci``, ``dataset``, ``noise``,
``noise_kasdin``, ``plot``, ``realtime``, ``mask``). The eleven statistics
imutherm computes (adev ... theo1), Greenhall's EDF and the chi-squared
quantiles run on imutherm's engine; the rest is NumPy, written from the
published definitions cited in each function.

**The one difference from imutherm's main API:** as in AllanTools,
``data_type`` defaults to ``"phase"``. Gyro or accelerometer rates are
``"freq"`` data::

    >>> import numpy as np
    >>> from imutherm import allantools as at
    >>> rate = np.random.default_rng(0).standard_normal(10_000)
    >>> taus, devs, errs, ns = at.oadev(rate, rate=100.0, data_type="freq", taus="octave")
    >>> taus[:3]
    array([0.01, 0.02, 0.04])

SciPy is needed by ``psd2allan`` and ``noise.scipy_psd`` only, matplotlib by
``Plot`` only.
"""

from . import allantools, ci, dataset, mask, noise, noise_kasdin, plot, realtime
from .allantools import (
    __version__, adev, calc_hdev_phase, calc_htotdev_freq, calc_mtotdev_phase, frequency2fractional,
    frequency2phase, gcodev, gradev, hdev, htotdev, mdev, mtie, mtie_phase_fast, mtotdev, oadev,
    ohdev, pdev, phase2frequency, phase2radians, psd2allan, tau_generator, tau_reduction, tdev,
    theo1, three_cornered_hat_phase, tierms, totdev, trim_data, ttotdev,
)
from .ci import (
    autocorr_noise_id, confidence_interval, confidence_interval_noiseID, edf_greenhall,
    edf_mtotdev, edf_simple, edf_totdev,
)
from .dataset import Dataset
from .noise_kasdin import Noise
from .plot import Plot
from .realtime import ohdev_realtime, oadev_realtime, tdev_realtime

# AllanTools' own list, in its order.
__all__ = [
    "__version__", "adev", "oadev", "mdev", "pdev", "hdev", "ohdev", "calc_hdev_phase", "tdev",
    "totdev", "mtotdev", "calc_mtotdev_phase", "ttotdev", "htotdev", "calc_htotdev_freq", "theo1",
    "mtie", "mtie_phase_fast", "tierms", "frequency2phase", "phase2frequency", "phase2radians",
    "frequency2fractional", "three_cornered_hat_phase", "noise", "gradev", "gcodev", "trim_data",
    "edf_simple", "edf_greenhall", "edf_totdev", "edf_mtotdev", "confidence_interval",
    "confidence_interval_noiseID", "autocorr_noise_id", "Dataset", "Noise", "Plot", "psd2allan",
    "tau_generator", "tau_reduction",
]
