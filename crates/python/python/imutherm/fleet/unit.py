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
#: The checks of :func:`imutherm.read` (``Recording.checks``) carried per
#: run: a static run must neither move nor hold a dead or clipped channel;
#: a thermal (or held-out) run is read for its reader problems and dead
#: or clipped channels only,
#: since its bias drifts with temperature, which the motion check would
#: take for movement.
STATIC_CHECKS = ("stuck", "saturated", "accel_norm", "motion")
THERMAL_CHECKS = ("stuck", "saturated")
#: Width of the bias-over-temperature bins of the unit page, degrees C
#: (``tcal fit``'s default bin width).
BIN_C = 1.0


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
    # Read here for what the reader found in them; the fit reads the same
    # files with the same options.
    thermal = [imutherm.read(p, **reading) for p in unit.thermal]
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
    held, runs = {}, [("static", static, STATIC_CHECKS)] + [("thermal", t, THERMAL_CHECKS)
                                                          for t in thermal]
    if unit.held_out is not None:
        runs.append(("held_out", imutherm.read(unit.held_out, **reading), THERMAL_CHECKS))
        doc = model.evaluate(unit.held_out, export=unit.firmware, params=params_file, **reading)
        held = {r["channel"]: r for r in doc["rows"]}
    facts = _run_facts(static, thermal)
    rows = []
    for name in static.channels:
        channel = static.channel(name)
        if channel.quantity not in INERTIAL:
            continue
        row = {"unit": unit.id, "instance": instance, "channel": name, "si_unit": channel.unit,
               "static_file": unit.static, "samples": int(len(channel.data)),
               "model_file": model_file, "params_file": params_file, "firmware": unit.firmware,
               "error": None}
        row.update(facts)
        row.update(_problems(name, runs))
        row.update(_noise(channel.data, static.rate, settings))
        row.update(_temperature_model(model, name))
        row.update(_bias_over_temperature(model, name, thermal))
        if name in held:
            row["held_out_bias_rms_before"] = held[name]["bias_rms_before"]
            row["held_out_bias_rms"] = held[name]["bias_rms_after"]
            row["held_out_bias_rms_as_loaded"] = held[name].get("bias_rms_as_loaded")
        rows.append(row)
    return rows


def _run_facts(static, thermal):
    """What the run checks of the limits compare: each run's length, rate
    and, for the thermal runs, the temperature they cover."""
    temps = [t.temperature for t in thermal if t.temperature is not None]
    temps = np.concatenate(temps) if temps else np.array([])
    temps = temps[np.isfinite(temps)]
    rates = [t.rate for t in thermal if t.rate]
    return {"static_duration_s": static.duration, "static_rate_hz": static.rate,
            "thermal_duration_s": sum(t.duration or 0.0 for t in thermal) if thermal else None,
            "thermal_rate_hz": min(rates) if rates else None,
            "thermal_t_low_c": float(temps.min()) if len(temps) else None,
            "thermal_t_high_c": float(temps.max()) if len(temps) else None}


def _problems(channel, runs):
    """The reader's problems and the channel checks of each run, as
    sentences (``problems``) and, one for each, ``role:kind``
    (``problem_kinds``, what the limits may allow). A check that names a
    channel belongs to that channel's row only."""
    text, kinds = [], []
    for role, rec, checks in runs:
        where = os.path.basename(rec.file or role)
        for p in rec.problems:
            if p.get("channel") not in (None, channel):
                continue
            line = f" line {p['line']}" if p.get("line") is not None else ""
            text.append(f"{role} {where}{line}: {p['kind']}: {p['message']}")
            kinds.append(f"{role}:{p['kind']}")
        if rec.problems_unlisted:
            text.append(f"{role} {where}: {rec.problems_unlisted} more problems not listed")
            kinds.append(f"{role}:unlisted")
        for c in rec.checks:
            if c["kind"] not in checks or c.get("channel") not in (None, channel) and \
                    c["kind"] != "motion":
                continue
            text.append(f"{role} {where}: {c['kind']}: {c['message']}")
            kinds.append(f"{role}:{c['kind']}")
    return {"problems": text, "problem_kinds": kinds}


def _noise(data, rate, settings):
    """The noise terms with their intervals, as ``imutherm noise`` shows
    them, and the OADEV curve they are read from. A constant output (a
    dead axis) has none: its terms are null with ``how = dead``, never
    the round-off a fit would find in it."""
    finite = data[np.isfinite(data)]
    out = {"static_spread": float(np.ptp(finite)) if len(finite) else None, "noise_error": None,
           "adev_tau_s": None, "adev": None}
    if out["static_spread"] == 0.0:
        for name in TERMS:
            out.update({name: None, f"{name}_lo": None, f"{name}_hi": None, f"{name}_how": "dead"})
        return out
    try:
        terms = imutherm.noise_terms(data, rate=rate, confidence=settings.get("confidence", 0.95))
    except ValueError as e:
        out["noise_error"] = str(e)
        return out
    out.update(_curve(terms.get("curve") or {}))
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


def _curve(curve):
    """The OADEV points of ``noise_terms``' curve, for the unit page."""
    taus, devs = curve.get("taus"), curve.get("devs")
    if taus is None or devs is None:
        return {}
    return {"adev_tau_s": [float(t) for t in taus], "adev": [float(d) for d in devs]}


def _bias_over_temperature(model, name, thermal):
    """The channel's mean over 1 degree C bins of its thermal runs (the
    bias before compensation) and what the model leaves of it (after)."""
    c = model.channels.get(name)
    pairs = [(t.temperature, t.channels.get(name)) for t in thermal]
    pairs = [(tc, y) for tc, y in pairs if tc is not None and y is not None]
    if c is None or not pairs:
        return {}
    temp = np.concatenate([p[0] for p in pairs])
    y = np.concatenate([p[1] for p in pairs])
    ok = np.isfinite(temp) & np.isfinite(y)
    temp, y = temp[ok], y[ok]
    if not len(temp):
        return {}
    k = np.floor(temp / BIN_C).astype(np.int64)
    centres, before = [], []
    for b in np.unique(k):
        sel = k == b
        centres.append(float(np.mean(temp[sel])))
        before.append(float(np.mean(y[sel])))
    doc = json.loads(model.to_json())
    u = (np.array(centres) - doc["centre_c"]) / doc["scale_c"]
    fitted = np.polynomial.polynomial.polyval(u, [float(x) for x in c["coefficients"]])
    return {"bias_t_c": centres, "bias_before": before,
            "bias_after": [float(v) for v in np.array(before) - fitted]}
