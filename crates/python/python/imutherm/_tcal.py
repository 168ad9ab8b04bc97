"""The temperature compensation of ``imutherm tcal``: a fitted model, applied
to recordings, evaluated and exported for PX4 or ArduPilot."""

import json
import os

from . import _imutherm
from ._errors import names_the_file


READ_FLAGS = ("rate", "units", "topic", "instance", "temp_topic")


def _runs(runs, given):
    """The runs' paths, the reading flags for all of them (those given, else
    those the recordings among the runs were read with, which must agree, as
    one set of flags reads every run on the command line), and whether every
    IMU instance was asked for (``instance="all"``, ``--instance all``)."""
    if isinstance(runs, (str, os.PathLike)) or hasattr(runs, "channels"):
        runs = [runs]
    paths, seen = [], []
    for r in runs:
        path = getattr(r, "file", r)
        if path is None:
            raise ValueError("a recording made in memory has no file: the model keeps each run's "
                             "digest, so fit and evaluate on files (imutherm.read's, or paths)")
        paths.append(os.fspath(path))
        if hasattr(r, "read_options"):
            seen.append(r.read_options)
    reading = dict(given)
    if all(v is None for v in given.values()) and seen:
        if any(s != seen[0] for s in seen[1:]):
            raise ValueError("the recordings were read with different options (rate, units, "
                             "topic, ...): give the ones to read every run with")
        reading = dict(seen[0])
    reading["rate"] = None if reading["rate"] is None else float(reading["rate"])
    reading["units"] = _units(reading["units"])
    every = isinstance(reading["instance"], str) and reading["instance"].strip().lower() == "all"
    reading["instance"] = None if reading["instance"] is None or every else int(reading["instance"])
    return paths, reading, every


def _units(units):
    if isinstance(units, dict):
        return [f"{k}={v}" for k, v in units.items()]
    if isinstance(units, str):
        return [units]
    return list(units or [])


@names_the_file(path_arg=(0, "runs"))
def tcal_fit(runs, channels=None, order="auto", tref=None, bin_width=1.0, rate_term=False,
             firmware=None, rate=None, units=None, topic=None, instance=None, temp_topic=None):
    """Fits the bias over temperature of the runs, as ``imutherm tcal fit``:
    ``runs`` are paths (or :class:`Recording` objects read from files),
    ``channels`` names or groups (``"gyro"``, ``"accel"``; all inertial
    channels by default), ``order`` an integer or ``"auto"``
    (cross-validated), ``tref`` the reference temperature (the range's
    middle by default), ``bin_width`` in degrees C, ``rate_term`` a dT/dt
    term, ``firmware`` (``"px4"`` or ``"ardupilot"``: ``--for``, a cubic at
    most, checked against the export); ``rate``, ``units``, ``topic``,
    ``instance`` and ``temp_topic`` as in :func:`imutherm.read`, for every
    run (by default those the recordings given were read with).

    ``instance="all"`` fits every IMU instance of a flight controller's log
    (PX4 ULog, ArduPilot DataFlash) into one model, as ``imutherm tcal fit
    LOG --instance all``; it is the default with ``firmware`` on a log of
    several IMUs (and no ``topic``), as ``--for`` is. Such a model holds
    each instance's own fit (:attr:`TcalModel.instances`) and exports to
    one parameter file covering them all.

    Returns a :class:`TcalModel`; ``model.save(path)`` writes the same file
    as ``imutherm tcal fit -o path``. Warnings of the export for
    ``firmware`` are in ``model.warnings``.

    >>> model = imutherm.tcal_fit(["cool.txt"], firmware="px4")      # doctest: +SKIP
    >>> model.save("model.json")                                      # doctest: +SKIP
    >>> print(model.export("px4"))                                    # doctest: +SKIP
    """
    paths, reading, every = _runs(runs, dict(rate=rate, units=units, topic=topic, instance=instance,
                                             temp_topic=temp_topic))
    if isinstance(channels, str):
        channels = [channels]
    if order == "auto" or order is None:
        order = None
    else:
        order = int(order)
    text, warnings = _imutherm.tcal_fit(paths, list(channels or []), order,
                                        None if tref is None else float(tref), float(bin_width),
                                        bool(rate_term), firmware, reading, every)
    return TcalModel(text, warnings=warnings)


class TcalModel:
    """A temperature-compensation model (the ``imutherm.tcal/1`` model file).

    * ``t_ref``, ``t_min``, ``t_max`` -- reference and fitted range, degrees C;
    * ``channels`` -- a dict, channel name -> its model (``order``,
      ``coefficients`` in the model file's normalised form, ``unit``,
      ``residual_rms``, ...);
    * ``to_json()`` -- the model file's text; ``save(path)`` writes it;
      ``TcalModel.load(path)`` reads one (checked as ``tcal apply`` checks
      it);
    * ``instances`` -- for a model of several IMU instances (``tcal fit
      --instance all``), a dict, instance number -> that instance's own
      :class:`TcalModel`, as imutherm reads it from the file (what ``tcal
      apply --instance N`` compensates with); empty for a model of one
      sensor. The fields above are then the first instance's, as in the
      model file;
    * ``instance`` -- the log's IMU instance the model was fitted on, or
      None.
    """

    def __init__(self, text, name=None, warnings=()):
        _imutherm.tcal_check(text)
        self._text = text
        self._doc = json.loads(text)
        #: What ``tcal eval`` and ``tcal export`` call the model in their output.
        self.name = name
        self.warnings = list(warnings)

    @classmethod
    def load(cls, path):
        """Reads a model file written by ``imutherm tcal fit`` or :meth:`save`."""
        path = os.fspath(path)
        with open(path, encoding="utf-8") as f:
            text = f.read()
        try:
            return cls(text, name=path)
        except _imutherm.ImuthermError as e:
            raise _imutherm.ImuthermError(f"{path}: {e}") from None

    def to_json(self):
        """The model file's text, as ``imutherm tcal fit`` writes it."""
        return self._text

    def save(self, path):
        """Writes the model file to ``path``; ``name`` becomes ``path``."""
        with open(path, "w", encoding="utf-8") as f:
            f.write(self._text)
        self.name = os.fspath(path)

    @property
    def t_ref(self):
        return self._doc["t_ref_c"]

    @property
    def t_min(self):
        return self._doc["t_min_c"]

    @property
    def t_max(self):
        return self._doc["t_max_c"]

    @property
    def channels(self):
        return {c["name"]: c for c in self._doc["channels"]}

    @property
    def instance(self):
        return self._doc.get("instance")

    @property
    def instances(self):
        return {n: TcalModel(text, name=self.name) for n, text in _imutherm.tcal_instances(self._text)}

    def apply(self, recording, instance=None):
        """A copy of ``recording`` with every modelled channel compensated,
        as ``imutherm tcal apply`` writes it, through the same function:
        x - (p(T) - p(T_ref)) with T clamped to the fitted range
        (``out_of_range`` counts the samples clamped); where the model has a
        lag or a hysteresis term, T is the element's temperature and the
        hysteresis is subtracted too. Needs the recording's temperature channel. A model of
        several instances compensates with the model of ``instance``
        (``tcal apply --instance N``), by default the instance the recording
        was read with."""
        import copy

        if instance is None:
            instance = getattr(recording, "read_options", {}).get("instance")
        sensor = _imutherm.tcal_sensor(self._text, self.name or "model",
                                       None if instance is None else int(instance))
        names = [c["name"] for c in json.loads(sensor)["channels"]]

        temp = recording.temperature
        if temp is None:
            raise _imutherm.ImuthermError(f"{recording.file or 'recording'}: no temperature channel")
        out = copy.copy(recording)
        out.channels = dict(recording.channels)
        out._channels = [copy.copy(c) for c in recording._channels]
        out.out_of_range = 0
        rate = recording.rate or 1.0
        for name in names:
            chans = [c for c in out._channels if c.name == name]
            if not chans:
                raise _imutherm.ImuthermError(
                    f"{recording.file or 'recording'}: the model has channel '{name}', the file does not")
            data, clamped = _imutherm.tcal_apply(sensor, name, chans[0].data, temp, float(rate))
            chans[0].data = data
            out.channels[name] = data
            out.out_of_range = max(out.out_of_range, clamped)
        out.metadata = dict(recording.metadata)
        out.metadata["entries"] = list(recording.metadata["entries"]) + [
            ("temperature_compensated_with", self.name or "model")]
        return out

    @names_the_file(path_arg=(1, "runs"))
    def evaluate(self, runs, export=None, params=None, rate=None, units=None, topic=None,
                 instance=None, temp_topic=None):
        """What ``imutherm tcal eval --json MODEL RUNS [--export FW]
        [--params FILE]`` prints, as a dict (schema
        ``imutherm.tcal-eval/1``): per run and channel, the residual bias
        over 1 degree C bins before and after (``bias_rms_*``,
        ``bias_max_*``, ``bins_*``), the ADEV minimum per 5 degree C slice,
        whether the run was held out of the fit, and with ``export`` the
        bias as the firmware applies the exported file and its verdict per
        run. The reading flags are :func:`tcal_fit`'s. A model of several
        instances judges each instance (or the one ``instance`` names) read
        as its own IMU, against its own set of the parameter file, each row
        and verdict naming its ``instance``. The export's warnings go to
        ``export_warnings``."""
        paths, reading, every = _runs(runs, dict(rate=rate, units=units, topic=topic,
                                                 instance=instance, temp_topic=temp_topic))
        text, warnings = _imutherm.tcal_eval(self._text, self.name or "model", paths, export,
                                             None if params is None else os.fspath(params), reading,
                                             every)
        self.export_warnings = list(warnings)
        return json.loads(text)

    def export(self, firmware, instance=None, device_id=None):
        """The parameter file ``imutherm tcal export MODEL --firmware
        FIRMWARE [--instance N] [--device-id ID]`` writes (``"px4"``: a
        QGroundControl ``.params`` file; ``"ardupilot"``: a ``.parm``
        file), as text. A model of several instances is written whole, each
        instance to its own set with its own device ids (PX4 ``TC_G{n}``/
        ``TC_A{n}``, ArduPilot ``INS_TCAL{n+1}``), and takes neither
        ``instance`` nor ``device_id``. The export's warnings go to
        ``export_warnings``."""
        text, warnings = _imutherm.tcal_export(self._text, self.name or "model", str(firmware),
                                               None if instance is None else int(instance),
                                               None if device_id is None else int(device_id))
        self.export_warnings = list(warnings)
        return text

    def __repr__(self):
        rows = [f"<imutherm.TcalModel {self.name or ''} {self.t_min:.1f}..{self.t_max:.1f} degC, "
                f"T_ref {self.t_ref:.2f} degC>".replace("  ", " ")]
        sensors = [json.loads(text) for _, text in _imutherm.tcal_instances(self._text)] or [self._doc]
        for doc in sensors:
            indent = "  "
            if doc.get("instance") is not None and len(sensors) > 1:
                rows.append(f"  instance {doc['instance']}: {doc['t_min_c']:.1f}..{doc['t_max_c']:.1f} "
                            f"degC, T_ref {doc['t_ref_c']:.2f} degC")
                indent = "    "
            for c in doc["channels"]:
                rows.append(f"{indent}{c['name']:<8} order {c['order']}  residual RMS "
                            f"{c['residual_rms']:.3e} {c['unit']}")
        return "\n".join(rows)
