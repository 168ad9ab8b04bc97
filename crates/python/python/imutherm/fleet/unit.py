"""One unit, analysed exactly as a person would by hand with the public
API: :func:`imutherm.read` the static run, :func:`imutherm.noise_terms`
of each inertial channel, :func:`imutherm.tcal_fit` on the thermal runs
(each IMU instance on its own), :meth:`TcalModel.export` for the
firmware, :meth:`TcalModel.evaluate` on the held-out run. Nothing here
judges: the limits and the fleet's spread are applied to the whole table
afterwards, so that changing a limit never means analysing again.

Runs on a Dask worker: it takes plain values, returns plain rows, and
writes the unit's model and parameter files atomically.
"""

import json
import os

import numpy as np

import imutherm

from .files import write_atomic

#: The noise terms of the table, in the names of ``imutherm noise --json``.
TERMS = ("white_noise", "bias_instability", "rate_random_walk")
INERTIAL = ("acceleration", "angular_rate")
PARAMS_SUFFIX = {"px4": "px4.params", "ardupilot": "ardupilot.parm"}


def analyse(unit, settings, units_dir):
    """The rows of ``unit``, one per instance and channel; a unit that
    cannot be analysed is one row holding its error."""
    try:
        rows = []
        for instance in unit.instances:
            rows.extend(_instance(unit, instance, settings, units_dir))
        return rows
    except Exception as e:  # noqa: BLE001 (any failure of a unit is its row, never the run's)
        return [error_row(unit, e)]


def error_row(unit, error):
    """The row of a unit that could not be analysed."""
    message = str(error) or type(error).__name__
    return {"unit": unit.id, "instance": None, "channel": None,
            "error": f"{type(error).__name__}: {message}"}


def _stem(unit, instance):
    return unit.id if instance is None else f"{unit.id}.i{instance}"


def _instance(unit, instance, settings, units_dir):
    reading = dict(rate=settings.get("rate"), instance=instance)
    static = imutherm.read(unit.static, **reading)
    model = imutherm.tcal_fit(unit.thermal, order=settings.get("order", "auto"),
                              firmware=unit.firmware, **reading)
    stem = _stem(unit, instance)
    model_file = os.path.join(units_dir, f"{stem}.tcal.json")
    write_atomic(model_file, model.to_json())
    model.name = model_file
    params_file = None
    if unit.firmware is not None:
        params_file = os.path.join(units_dir, f"{stem}.{PARAMS_SUFFIX[unit.firmware]}")
        write_atomic(params_file, model.export(unit.firmware, instance=instance))
    held = {}
    if unit.held_out is not None:
        doc = model.evaluate(unit.held_out, export=unit.firmware, params=params_file, **reading)
        held = {r["channel"]: r for r in doc["rows"]}
    rows = []
    for name in static.channels:
        channel = static.channel(name)
        if channel.quantity not in INERTIAL:
            continue
        row = {"unit": unit.id, "instance": instance, "channel": name, "si_unit": channel.unit,
               "static_file": unit.static, "samples": int(len(channel.data)),
               "model_file": model_file, "params_file": params_file, "firmware": unit.firmware,
               "error": None}
        row.update(_noise(channel.data, static.rate, settings))
        row.update(_temperature_model(model, name))
        if name in held:
            row["held_out_bias_rms_before"] = held[name]["bias_rms_before"]
            row["held_out_bias_rms"] = held[name]["bias_rms_after"]
            row["held_out_bias_rms_as_loaded"] = held[name].get("bias_rms_as_loaded")
        rows.append(row)
    return rows


def _noise(data, rate, settings):
    """The noise terms with their intervals, as ``imutherm noise`` shows
    them. A constant output (a dead axis) has none: said, not computed."""
    finite = data[np.isfinite(data)]
    out = {"static_spread": float(np.ptp(finite)) if len(finite) else None, "noise_error": None}
    try:
        terms = imutherm.noise_terms(data, rate=rate, confidence=settings.get("confidence", 0.95))
    except ValueError as e:
        out["noise_error"] = str(e)
        return out
    for name in TERMS:
        t = terms["terms"][name]
        interval = t.get(t["how"], {}) if t["how"] in ("fit", "slope") else {}
        out[name] = t["value"]
        out[f"{name}_lo"] = interval.get("lo")
        out[f"{name}_hi"] = t["value"] if t["how"] == "upper_bound" else interval.get("hi")
        out[f"{name}_how"] = t["how"]
    return out


def _temperature_model(model, name):
    c = model.channels.get(name)
    if c is None:
        return {}
    coeffs = [float(x) for x in c["coefficients"]]
    # The mean slope over the fitted range, in the channel's unit per degC:
    # the polynomial is in u = (T - centre)/scale (thermal::tcal::ChannelModel).
    doc = json.loads(model.to_json())
    u = [(t - doc["centre_c"]) / doc["scale_c"] for t in (model.t_min, model.t_max)]
    p = [float(np.polynomial.polynomial.polyval(x, coeffs)) for x in u]
    span = model.t_max - model.t_min
    return {"tcal_order": int(c["order"]), "tcal_coefficients": coeffs,
            "tcal_centre_c": doc["centre_c"], "tcal_scale_c": doc["scale_c"],
            "tcal_t_ref_c": model.t_ref, "tcal_t_min_c": model.t_min, "tcal_t_max_c": model.t_max,
            "tcal_slope": (p[1] - p[0]) / span if span > 0 else None,
            "tcal_residual_rms": float(c["residual_rms"])}
