#!/usr/bin/env python3
"""Variants of the least-squares cubic on the logs of compare.py, each
judged as compare.py judges a parameter file: the error against the true
bias over the held-out run's 1 °C bins, level removed, offset evaluated in
float32 as PX4's `calc_thermal_offsets_3D` does.

    variants.py WORK SEEDS…     (WORK as compare.py left it)

Prints per variant and per IMU/axis the median over the seeds of its error
over PX4's (from WORK/seedN/rows.json), and how many seed × axis pairs are
below PX4's. The variants measure what could move the fit off the
least-squares floor:
  ols      every sample on its logged temperature (imutherm's fit);
  smooth5, smooth30  the temperature averaged over 5 s and 30 s before the
           fit (errors in variables: noise in T attenuates the slope);
  f64      ols with the offset in double instead of float32;
  tref35, tref_lo  TREF at 35 °C and at TMIN instead of the middle;
  q2       a quadratic (what a lower order costs where the truth is cubic);
  truth    the true bias itself, a file no fit can better: its error is 0,
           and its residual spread on the held-out run is the floor of that
           figure (the held-out run's own noise).
The second table is the same for the residual spread (standard deviation
of the corrected 1 °C bin means of the held-out run, as compare.py).
"""

import json
import statistics
import sys
from pathlib import Path

import numpy as np
from pyulog import ULog

RATE_HZ = 200


def smooth(t, seconds):
    w = int(seconds * RATE_HZ)
    c = np.cumsum(np.concatenate([[0.0], t]))
    out = t.copy()
    h = w // 2
    # A centred moving average; the ends keep their raw values.
    out[h:len(t) - h] = (c[w:] - c[:-w])[: len(t) - 2 * h] / w if len(t) > w else t[h:len(t) - h]
    return out


def offset(coef, tref, lo, hi, temp, f32=True):
    """calc_thermal_offsets_3D's offset for one axis."""
    dt = np.float32 if f32 else np.float64
    t = np.clip(temp.astype(dt), dt(lo), dt(hi))
    d = (t - dt(tref)).astype(dt)
    c = [dt(v) for v in coef]
    return (c[0] + c[1] * d + c[2] * d * d + c[3] * d * d * d).astype(np.float64)


def bin_std(temp, values):
    keys = np.floor(temp).astype(int)
    return float(np.std([values[keys == k].mean() for k in np.unique(keys)]))


def error(coef, tref, lo, hi, temp, truth_c, t_mid, f32=True):
    """Std over the 1 °C bins of (offset − true bias) on the held-out run."""
    dt = np.float32 if f32 else np.float64
    t = np.clip(temp.astype(dt), dt(lo), dt(hi))
    d = (t - dt(tref)).astype(dt)
    c = [dt(v) for v in coef]
    off = (c[0] + c[1] * d + c[2] * d * d + c[3] * d * d * d).astype(np.float64)
    x = temp - t_mid
    true = truth_c[0] + truth_c[1] * x + truth_c[2] * x**2 + truth_c[3] * x**3
    keys = np.floor(temp).astype(int)
    e = off - true
    return float(np.std([e[keys == k].mean() for k in np.unique(keys)]))


def fit(temp_fit, y, tref, order):
    c = np.polyfit(temp_fit - tref, y, order)[::-1]
    return list(c) + [0.0] * (4 - len(c))


def main():
    work = Path(sys.argv[1])
    seeds = [int(s) for s in sys.argv[2:]]
    ratios, spreads = {}, {}
    for seed in seeds:
        d = work / f"seed{seed}"
        truth = json.loads((d / "truth.json").read_text())
        peer = json.loads((d / "rows.json").read_text())["px4"]
        held = {(x.name, x.multi_id): x.data for x in ULog(str(d / "cooling.ulg")).data_list}
        for x in ULog(str(d / "heating.ulg")).data_list:
            if x.name not in ("sensor_gyro", "sensor_accel"):
                continue
            sensor = "gyro" if x.name == "sensor_gyro" else "accel"
            temp = x.data["temperature"].astype(np.float64)
            lo, hi = temp.min(), temp.max()
            mid = 0.5 * (lo + hi)
            h = held[(x.name, x.multi_id)]
            htemp = h["temperature"].astype(np.float64)
            smoothed = {5: smooth(temp, 5), 30: smooth(temp, 30)}
            for a, axis in enumerate("xyz"):
                y = x.data[axis].astype(np.float64)
                tc = truth["instances"][x.multi_id][sensor][a]
                judge = lambda coef, tref=mid, f32=True: error(coef, tref, lo, hi, htemp, tc, truth["t_mid_c"], f32)
                errs = {
                    "ols": judge(fit(temp, y, mid, 3)),
                    "smooth5": judge(fit(smoothed[5], y, mid, 3)),
                    "smooth30": judge(fit(smoothed[30], y, mid, 3)),
                    "f64": judge(fit(temp, y, mid, 3), f32=False),
                    "tref35": judge(fit(temp, y, 35.0, 3), tref=35.0),
                    "tref_lo": judge(fit(temp, y, lo, 3), tref=lo),
                    "q2": judge(fit(temp, y, mid, 2)),
                }
                key = f"{x.multi_id} {sensor}_{axis}"
                for name, e in errs.items():
                    ratios.setdefault(name, {}).setdefault(key, []).append((e, peer[key][1]))
                raw = h[axis].astype(np.float32).astype(np.float64)
                dh = htemp - truth["t_mid_c"]
                true = tc[0] + tc[1] * dh + tc[2] * dh**2 + tc[3] * dh**3
                for name, corr in (("ols", raw - offset(fit(temp, y, mid, 3), mid, lo, hi, htemp)),
                                   ("truth", raw - true)):
                    spreads.setdefault(name, {}).setdefault(key, []).append((bin_std(htemp, corr), peer[key][0]))
    keys = sorted(next(iter(ratios.values())))
    for title, table in (("error", ratios), ("residual spread", spreads)):
        print(f"seeds {seeds}: median over seeds of the variant's {title} / median of PX4's")
        print_table(keys, table)


def print_table(keys, table):
    print(f"{'variant':<9} " + " ".join(f"{k:>13}" for k in keys) + "  pairs below  geo mean")
    for name, per in table.items():
        cells = []
        below, logs = 0, []
        for k in keys:
            e = [v[0] for v in per[k]]
            p = [v[1] for v in per[k]]
            cells.append(statistics.median(e) / statistics.median(p))
            below += sum(a < b for a, b in zip(e, p))
            logs += [np.log(a / b) for a, b in zip(e, p)]
        print(f"{name:<9} " + " ".join(f"{c:>13.3f}" for c in cells)
              + f"  {below:>4}/{len(logs):<4}  {np.exp(np.mean(logs)):.3f}")


if __name__ == "__main__":
    main()
