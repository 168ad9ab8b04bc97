"""imutherm: Allan-family stability statistics with confidence intervals.

Every statistic of the ``imutherm adev`` command, on NumPy arrays::

    >>> import numpy as np, imutherm
    >>> gyro = np.random.default_rng(0).standard_normal(100_000) * 1e-3  # rad/s at 100 Hz
    >>> c = imutherm.oadev(gyro, rate=100.0)
    >>> float(c.taus[0]), round(float(c.devs[0] / 1e-3), 2)
    (0.01, 1.0)

The samples are rate data by default (``data_type="freq"``: a gyro's or an
accelerometer's output); pass ``data_type="phase"`` for integrated data. A
contiguous float64 array is read in place, never copied, and the
computation runs with the GIL released on all cores.

``imutherm.allantools`` is a drop-in for AllanTools' functions, which take
phase data by default.
"""

import json
import os
import warnings

import numpy as np

from . import _imutherm
from ._curve import Curve
from ._recording import Channel, Recording
from ._tcal import TcalModel, tcal_fit
from ._errors import names_the_file
from ._samples import as_samples, as_taus, in_samples
from . import allantools  # noqa: E402  (imutherm.allantools after a plain import imutherm)

ImuthermError = _imutherm.ImuthermError

#: The version of imutherm this package was built from.
__version__ = _imutherm.__version__

#: Every statistic, as the command line names them.
STATISTICS = ("adev", "oadev", "mdev", "tdev", "hdev", "ohdev",
              "totdev", "mtotdev", "ttotdev", "htotdev", "theo1")

__all__ = ["__version__", "allantools", "Channel", "Curve", "ImuthermError", "Recording", "STATISTICS", "analyze", "noise_terms",
           "read", "simulate", "TcalModel", "tcal_fit", *STATISTICS]


def analyze(stat, y, rate=1.0, taus="octave", data_type="freq", confidence=0.683):
    """Computes the statistic ``stat`` (one of :data:`STATISTICS`) of ``y``.

    ``taus`` is "octave" (1, 2, 4, ... samples), "decade" (1, 2, 4, 10, 20,
    ...), "all", "many" (50 per decade), or a sequence of taus in seconds,
    each rounded to a whole number of samples. Taus beyond Stable32's stop
    ratio (N/4 for oadev, N/2 for totdev, ...) are left out.

    NaN samples are gaps: adev, oadev, mdev, tdev, hdev and ohdev skip the
    terms across them (with a warning, as the command line notes them), the
    total statistics and theo1 raise :class:`ImuthermError`.

    Returns a :class:`Curve`. Raises ``TypeError`` for non-numeric samples,
    ``ValueError`` for empty or multi-dimensional ones and
    :class:`ImuthermError` (a ``ValueError``) for everything the command line
    refuses, with its message.

    >>> imutherm.analyze("mdev", np.ones(100) + np.arange(100) % 2).taus
    array([ 1.,  2.,  4.,  8., 16.])
    """
    data = as_samples(y)
    try:
        note = _imutherm.long_run_note(str(stat), len(data), float(rate), as_taus(taus), str(data_type),
                                       float(confidence))
        if note:
            # As the command line says it, before the work starts.
            warnings.warn(note, RuntimeWarning, stacklevel=3)
        fields = _imutherm.analyze(str(stat), data, float(rate), as_taus(taus), str(data_type),
                                   float(confidence))
    except ImuthermError as e:
        raise ImuthermError(in_samples(str(e), data_type)) from None
    curve = Curve(fields)
    if curve.nan_samples:
        warnings.warn(f"{curve.nan_samples} NaN samples treated as gaps (terms across them skipped)",
                      RuntimeWarning, stacklevel=3)
    return curve


def _statistic(stat, summary):
    def compute(y, rate=1.0, taus="octave", data_type="freq", confidence=0.683):
        return analyze(stat, y, rate=rate, taus=taus, data_type=data_type, confidence=confidence)

    compute.__name__ = compute.__qualname__ = stat
    compute.__doc__ = f"""{summary}

    ``imutherm.{stat}(y, rate=1.0, taus="octave", data_type="freq", confidence=0.683)``
    is ``imutherm.analyze("{stat}", ...)``: see :func:`analyze` for the
    arguments, the gaps and the errors. Returns a :class:`Curve`.

    >>> c = imutherm.{stat}(np.random.default_rng(2).standard_normal(4096))
    >>> c.stat
    '{stat}'
    """
    return compute


adev = _statistic("adev", "Non-overlapped Allan deviation (NIST SP 1065 eq. 6/7).")
oadev = _statistic("oadev", "Overlapped Allan deviation (NIST SP 1065 eq. 9/11).")
mdev = _statistic("mdev", "Modified Allan deviation (NIST SP 1065 eq. 14/15).")
tdev = _statistic("tdev", "Time deviation, tau*MDEV/sqrt(3) (NIST SP 1065 eq. 16).")
hdev = _statistic("hdev", "Non-overlapped Hadamard deviation (NIST SP 1065 eq. 17/18).")
ohdev = _statistic("ohdev", "Overlapped Hadamard deviation (NIST SP 1065 eq. 19/20).")
totdev = _statistic("totdev", "Total deviation (NIST SP 1065 eq. 25).")
mtotdev = _statistic("mtotdev", "Modified total deviation (NIST SP 1065 eq. 27), no bias correction.")
ttotdev = _statistic("ttotdev", "Time total deviation (NIST SP 1065 eq. 28), no bias correction.")
htotdev = _statistic("htotdev", "Hadamard total deviation (NIST SP 1065 eq. 29), no bias correction.")
theo1 = _statistic("theo1", "Theo1 deviation (NIST SP 1065 eq. 30) at tau = 0.75 m/rate, no bias correction.")


def noise_terms(y, rate=1.0, confidence=0.95, quantity=None):
    """The IEEE Std 952 noise terms of rate samples ``y`` at ``rate`` Hz, as
    ``imutherm noise`` reads them: from the selected noise model, each with
    its interval (at 95 % by default, as on the command line), or its upper
    bound where the model does not hold it.

    Returns a dict: ``"curve"`` (the octave OADEV points it was read from,
    NumPy arrays as in :class:`Curve`) and ``"terms"``, keyed by term name
    (quantization, white noise, bias instability, rate random walk, rate
    ramp), each with ``symbol``, ``slope`` and ``fit`` (both the model's:
    ``value``, ``lo``, ``hi``, or ``value`` None and the ``reason``),
    ``bound``, ``kept`` (in the model as a value, or dropped), and
    ``value``, ``how`` ("fit", "upper_bound" or "none") and ``note``: the
    estimate ``imutherm noise`` shows, with its JSON's names.

    The model itself, with the fields and numbers of ``imutherm noise
    --json`` (schema imutherm.noise/1):

    * ``"model"`` -- ``label`` ("N + K"), ``fits``, ``chi2``, ``dof``,
      ``chi2_reduced``, ``p_value``, ``criterion``, the τ it leaves out or
      leaves the measured interval at, ``evidence`` (per process, how much
      worse the criterion is without it), ``candidates``, its
      ``gauss_markov`` terms (``sigma`` and ``tau_c`` with intervals) and
      each term's ``bounds``;
    * ``"verdict"`` -- "fits", "does_not_fit" (p below 0.01) or
      "no_candidate_fits" (then every term is a bound, none a value); where
      it is not "fits", ``model["defeat"]`` names where the best candidate
      parts from the curve: ``candidate``, ``process`` (the one whose line
      exceeds the measured deviation, or None for a misfit), ``tau``,
      ``ratio`` (measured over the model's deviation there), ``sigmas`` and
      ``text``; None where the model fits;
    * ``"state_space"`` -- the model as white noise, random-walk and
      first-order Gauss-Markov states;
    * with ``quantity`` "angular_rate" (``y`` in rad/s) or "acceleration"
      (m/s²): ``"filters"``, PX4 EKF2's and ArduPilot EKF3's parameters,
      each with its unit, formula and source, and ``"kalibr"``, Kalibr's
      ``*_noise_density`` and ``*_random_walk``; both None without it.

    >>> t = imutherm.noise_terms(np.random.default_rng(3).standard_normal(100_000), rate=100.0)
    >>> sorted(t["terms"])[:2]
    ['bias_instability', 'quantization']
    >>> t["model"]["label"], t["verdict"]
    ('N', 'fits')
    """
    fields = _imutherm.noise_terms(as_samples(y), float(rate), float(confidence),
                                   None if quantity is None else str(quantity))
    fields["curve"]["noise_id"] = np.asarray(fields["curve"]["noise_id"], dtype=str)
    fields.update(json.loads(fields.pop("details")))
    return fields


@names_the_file(path_arg=(0, "path"))
def read(path, rate=None, units=None, topic=None, instance=None, temp_topic=None,
         allow_partial=False):
    """Reads a recording as every ``imutherm`` command does: imutherm's log,
    CSV or whitespace text logs, ROS 2 (MCAP, SQLite) and ROS 1 bags, PX4
    ULog and ArduPilot DataFlash. Returns a :class:`Recording`.

    ``rate`` (Hz), ``units`` (a dict ``{column: unit}`` or a list of
    ``"COLUMN=UNIT"`` strings), ``topic``, ``instance`` and ``temp_topic``
    are the command line's ``--rate``, ``--unit``, ``--topic``,
    ``--instance`` and ``--temp-topic``. A robot log with several IMU
    streams and none chosen is refused, naming them. ``allow_partial`` is
    ``--allow-partial``: a ROS 2 bag missing some of the storage files its
    ``metadata.yaml`` lists is read from the others, each missing file a
    ``skipped_data`` problem with the messages the metadata gives it.

    Raises ``OSError`` (``FileNotFoundError``, ``PermissionError``, ...)
    when the file cannot be read and :class:`ImuthermError` (a
    ``ValueError``) when its content or an option is refused, with the
    command line's message, an option named as its keyword argument.

    >>> rec = imutherm.read("imu_34C.txt", rate=200)            # doctest: +SKIP
    >>> rec.channels["gyro_x"].mean(), rec.units["gyro_x"]      # doctest: +SKIP
    (0.0123, 'rad/s')
    >>> imutherm.read("flight.ulg", instance=1).to_pandas()     # doctest: +SKIP
    """
    if isinstance(units, dict):
        units = [f"{k}={v}" for k, v in units.items()]
    elif isinstance(units, str):
        units = [units]
    rec = Recording(_imutherm.read(os.fspath(path), None if rate is None else float(rate),
                                   list(units or []), topic,
                                   None if instance is None else int(instance), temp_topic,
                                   bool(allow_partial)))
    rec.read_options = dict(rate=rate, units=units, topic=topic, instance=instance,
                            temp_topic=temp_topic)
    return rec


def simulate(preset="mpu9250-thesis", duration=None, rate=None, profile=None, seed=None,
             unit=None, scatter=None, defect=None):
    """The recording ``imutherm simulate`` writes with the same arguments,
    sample for sample, in memory: ``preset`` (``"mpu9250-thesis"`` or
    ``"white"``), ``duration`` in seconds, ``rate`` in Hz, ``profile`` (the
    chamber temperature profile, in ``--profile``'s spelling, e.g.
    ``"ramp:20:60:7200"``) and ``seed`` override the preset's. Returns a
    :class:`Recording` whose ``metadata`` holds the true parameters.

    ``unit`` draws that unit (an id) of a production population around the
    preset, as ``--unit``: its noise terms and bias polynomials scatter by
    ``scatter`` (``"NOISE,BIAS"``, relative, ``"0.1,0.2"`` by default), the
    same board for every ``seed``; ``defect`` plants ``"noise-3x"``,
    ``"slope-5x"`` or ``"dead-axis[:CHANNEL]"``.

    >>> a = imutherm.simulate(preset="white", duration=10, unit="SN-0042", defect="noise-3x")
    >>> dict(a.metadata["entries"])["population.defect"]
    'noise-3x'

    >>> rec = imutherm.simulate(preset="white", duration=60, rate=100, seed=7)
    >>> rec.channels["gyro_x"].shape
    (6000,)
    """
    return Recording(_imutherm.simulate(str(preset),
                                        None if duration is None else float(duration),
                                        None if rate is None else float(rate),
                                        profile, None if seed is None else int(seed),
                                        None if unit is None else str(unit),
                                        None if scatter is None else str(scatter),
                                        None if defect is None else str(defect)))
