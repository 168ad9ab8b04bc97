"""The fleet's view of its table: each row judged against the limits,
each term's spread over the fleet, robust outliers flagged, and the units
ranked (out of limits first, then outliers, then the rest)."""

import math

import numpy as np

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
    if r.get("static_spread") == 0.0:
        r["reasons"].append(f"dead axis: the output is constant over {r.get('samples')} samples")
    elif r.get("noise_error"):
        r["reasons"].append(f"noise terms: {r['noise_error']}")
    for metric, (lo, hi) in limits.items():
        v = r.get(metric)
        if v is None or (isinstance(v, float) and math.isnan(v)):
            continue
        size = abs(v) if metric == "tcal_slope" else v
        if hi is not None and size > hi:
            r["reasons"].append(f"{metric} {_g(size)} > {_g(hi)} {r.get('si_unit', '')} (limit)")
        if lo is not None and size < lo:
            r["reasons"].append(f"{metric} {_g(size)} < {_g(lo)} {r.get('si_unit', '')} (limit)")


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
        if not r.get("error"):
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
                                        f"from the fleet's median {_g(median)} {r.get('si_unit', '')}")


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
    return f"{x:.3g}" if isinstance(x, (int, float)) else str(x)
