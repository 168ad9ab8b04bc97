"""The fleet's view of its table: each row judged against the limits,
each term's spread over the fleet, robust outliers flagged, and the units
ranked (out of limits first, then outliers, then the rest)."""

import math

import numpy as np

from . import units

#: Terms that are positive and spread multiplicatively (a density, an RMS):
#: screened on their logarithm, where a unit's scatter is symmetric.
LOG_TERMS = {"white_noise", "bias_instability", "rate_random_walk", "tcal_residual_rms",
             "held_out_bias_rms"}
#: Below this many units a median and a MAD say little: no outlier screen.
MIN_UNITS = 5
#: MAD to standard deviation for normal data (Iglewicz and Hoaglin's
#: modified z-score, "How to Detect and Handle Outliers", 1993, eq. 2.1).
MAD_TO_Z = 0.6745
STATUS_ORDER = {"fail": 0, "error": 1, "outlier": 2, "pass": 3}


def judge(rows, limits):
    """Adds ``status``, ``reasons``, ``outlier``, ``flagged``, the ``z_*``
    columns and the unit's ``rank`` to every row (in place); returns the
    rows sorted worst unit first."""
    for r in rows:
        r["reasons"] = []
        if r.get("error"):
            r["reasons"].append(f"error: {r['error']}")
            continue
        _limits(r, limits.for_channel(r["channel"]))
        _run_checks(r, limits)
    _outliers(rows, limits)
    for r in rows:
        failed = bool(r["reasons"])
        if r.get("error"):
            r["status"] = "error"
        elif any(not x.startswith("outlier") for x in r["reasons"]):
            r["status"] = "fail"
        else:
            r["status"] = "outlier" if failed else "pass"
        r["outlier"] = any(x.startswith("outlier") for x in r["reasons"])
        r["flagged"] = r["status"] != "pass"
        r["reasons"] = "; ".join(r["reasons"]) or None
    return _rank(rows)


def _limits(r, limits):
    if dead(r):
        r["reasons"].append(f"dead axis: the output is constant over {r.get('samples')} samples")
    elif r.get("noise_error"):
        r["reasons"].append(f"noise terms: {r['noise_error']}")
    for metric, (lo, hi) in limits.items():
        v = r.get(metric)
        if v is None or (isinstance(v, float) and math.isnan(v)):
            continue
        size = abs(v) if metric == "tcal_slope" else v
        unit = units.of(metric, r.get("si_unit"))
        if hi is not None and size > hi:
            r["reasons"].append(f"{metric} {_g(size)} > {_g(hi)} {unit} (limit)")
        if lo is not None and size < lo:
            r["reasons"].append(f"{metric} {_g(size)} < {_g(lo)} {unit} (limit)")


def dead(r):
    """Whether the row's channel is a dead axis (its static output never
    changes): it has no noise terms and no place in the fleet's spread."""
    return r.get("static_spread") == 0.0


def _run_checks(r, limits):
    """The reader's problems the limits do not allow, and the runs against
    the ``[run]`` table: their length, rate and temperature range."""
    for text, kind in zip(r.get("problems") or [], r.get("problem_kinds") or []):
        if not limits.allows(kind):
            r["reasons"].append(f"reader: {text}")
    run = limits.run
    for role in ("static", "thermal"):
        lo = run.get(f"{role}_duration_min")
        got = r.get(f"{role}_duration_s")
        if lo is not None and (got is None or got < lo):
            r["reasons"].append(f"{role} run {_g(got)} s < {_g(lo)} s (limit)")
        rate = r.get(f"{role}_rate_hz")
        if run.get("rate_min") is not None and (rate is None or rate < run["rate_min"]):
            r["reasons"].append(f"{role} run's rate {_g(rate)} Hz < {_g(run['rate_min'])} Hz (limit)")
        if run.get("rate_max") is not None and (rate is None or rate > run["rate_max"]):
            r["reasons"].append(f"{role} run's rate {_g(rate)} Hz > {_g(run['rate_max'])} Hz (limit)")
    t0, t1 = r.get("tcal_t_min_c"), r.get("tcal_t_max_c")
    span = None if t0 is None or t1 is None else t1 - t0
    if run.get("temperature_span_min") is not None and (span is None
                                                        or span < run["temperature_span_min"]):
        r["reasons"].append(f"temperature model fitted over {_g(span)} °C < "
                            f"{_g(run['temperature_span_min'])} °C (limit)")
    want = run.get("fit_range")
    if want is not None and (span is None or t0 > want[0] or t1 < want[1]):
        got = "nothing" if span is None else f"{t0:.1f}–{t1:.1f} °C"
        r["reasons"].append(f"temperature model fitted over {got}, not covering "
                            f"{want[0]:g}–{want[1]:g} °C (limit)")


def robust_z(values):
    """Modified z-scores of ``values`` (NaN where a value is missing, or
    every one NaN when the MAD is zero)."""
    x = np.asarray(values, dtype=float)
    ok = np.isfinite(x)
    if ok.sum() < MIN_UNITS:
        return np.full(len(x), np.nan)
    med = np.median(x[ok])
    mad = np.median(np.abs(x[ok] - med))
    if mad == 0:
        return np.full(len(x), np.nan)
    return MAD_TO_Z * (x - med) / mad


def _outliers(rows, limits):
    by_channel = {}
    for r in rows:
        # A dead axis's figures are the sensor's absence, not a spread.
        if not r.get("error") and not dead(r):
            by_channel.setdefault((r["channel"], r.get("instance")), []).append(r)
    for term in limits.outlier_terms:
        for group in by_channel.values():
            values = [_scale(term, r.get(term)) for r in group]
            z = robust_z(values)
            finite = [v for v in values if math.isfinite(v)]
            centre = float(np.median(finite)) if finite else math.nan
            for r, zi in zip(group, z):
                r[f"z_{term}"] = None if math.isnan(zi) else float(zi)
                if abs(zi) > limits.z_max:
                    median = 10 ** centre if term in LOG_TERMS else centre
                    r["reasons"].append(f"outlier: {term} {_g(r[term])} is robust z {zi:+.1f} "
                                        f"from the fleet's median {_g(median)} "
                                        f"{units.of(term, r.get('si_unit'))}")


def _scale(term, v):
    if v is None or not isinstance(v, (int, float)) or not math.isfinite(v):
        return math.nan
    if term in LOG_TERMS:
        return math.log10(v) if v > 0 else math.nan
    return float(v)


def _rank(rows):
    worst = {}
    for r in rows:
        zs = [abs(v) for k, v in r.items() if k.startswith("z_") and v is not None]
        key = (STATUS_ORDER[r["status"]], -max(zs, default=0.0))
        worst[r["unit"]] = min(worst.get(r["unit"], key), key)
    order = sorted(worst, key=lambda u: (worst[u], u))
    rank = {u: i + 1 for i, u in enumerate(order)}
    for r in rows:
        r["rank"] = rank[r["unit"]]
    return sorted(rows, key=lambda r: (r["rank"], r.get("instance") or 0, r.get("channel") or ""))


def _g(x):
    if x is None:
        return "none"
    return f"{x:.3g}" if isinstance(x, (int, float)) else str(x)
