#!/usr/bin/env python3
"""psim's thermal-vacuum gyro: imutherm's default fit against a numpy cubic, held out by burst.

    compare.py TVCtest3_7_20.csv IMUTHERM WORK

The recording (pathfinder-for-autonomous-navigation/psim, MIT, commit
91d70ad, MATLAB/sensor_models/TVCtest3_7_20.csv) is an LSM6DSM gyro in a
cold thermal-vacuum test: 25 bursts of 250 samples at 50 Hz, one every
305 s, temperature in the LSM6DSM's raw counts (int16 as unsigned; 0 at
25 °C, 256 LSB/°C, its datasheet). Take it with
`git show 91d70ad:MATLAB/sensor_models/TVCtest3_7_20.csv` from a clone.

The odd bursts (1st, 3rd, …) are the fit's run, the even ones held out;
each is written as a text table at 50 Hz with the gaps between bursts as
NaN rows. imutherm: `tcal fit FIT` with no flags; its model is applied to
the held-out samples here as `tcal apply` does for a polynomial channel,
x − (p(T) − p(T_ref)) with T held to the fitted range (`tcal apply` cannot
write a recording without accelerometers), and refused where the fit chose
a lag, a hysteresis or a rate term, which this transcription does not
follow. The peer: numpy's `polyfit` cubic of every fitted sample on
temperature (each sample one weight), evaluated on the held-out
temperatures. Printed per axis: the RMS of what each leaves on the
held-out samples (the residual's mean over them removed, since the rate
the gyro sees is not zero), and their ratio.
"""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np

RATE_HZ = 50.0
AXES = ["gyro_x", "gyro_y", "gyro_z"]


def temp_c(raw):
    raw = raw.astype(np.int64)
    return 25.0 + np.where(raw >= 32768, raw - 65536, raw) / 256.0


def bursts(t_ms):
    starts = [0] + [i for i in range(1, len(t_ms)) if t_ms[i] - t_ms[i - 1] > 1000]
    return [(a, b) for a, b in zip(starts, starts[1:] + [len(t_ms)])]


def write(path, t_ms, data, temp, chosen):
    """The chosen bursts on one 50 Hz grid, NaN rows in the gaps."""
    t0 = t_ms[chosen[0][0]]
    lines = [f"# sample_rate_hz: {RATE_HZ:g}", ",".join(f"{a}[rad/s]" for a in AXES) + ",temp[degC]"]
    nan = ",".join(["nan"] * 4)
    slot = 0
    for a, b in chosen:
        first = int(round((t_ms[a] - t0) / 1000.0 * RATE_HZ))
        lines.extend([nan] * (first - slot))
        for i in range(a, b):
            lines.append(",".join(f"{v:.6e}" for v in data[i]) + f",{temp[i]:.6f}")
        slot = first + (b - a)
    Path(path).write_text("\n".join(lines) + "\n")


def read_table(path):
    rows = [l for l in Path(path).read_text().splitlines() if l and not l.startswith("#")]
    head = rows[0].split(",")
    vals = np.array([[float(v) for v in r.split(",")] for r in rows[1:]])
    return head, vals


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    src, imutherm, work = sys.argv[1], sys.argv[2], Path(sys.argv[3])
    work.mkdir(parents=True, exist_ok=True)
    raw = np.genfromtxt(src, delimiter=",", skip_header=1)
    t_ms, data, temp = raw[:, 0], raw[:, 4:7], temp_c(raw[:, 7])
    bs = bursts(t_ms)
    fit_b, held_b = bs[0::2], bs[1::2]
    fit, held = work / "fit.txt", work / "held.txt"
    write(fit, t_ms, data, temp, fit_b)
    write(held, t_ms, data, temp, held_b)
    model = work / "model.json"
    model.unlink(missing_ok=True)
    fit_out = subprocess.run([imutherm, "tcal", "fit", str(fit), "-o", str(model)],
                             check=True, capture_output=True, text=True)
    m = json.loads(model.read_text())
    fi = np.concatenate([np.arange(a, b) for a, b in fit_b])
    hi = np.concatenate([np.arange(a, b) for a, b in held_b])
    print(f"{len(bs)} bursts; fit on {len(fit_b)} ({len(fi)} samples, "
          f"{temp[fi].min():.2f}–{temp[fi].max():.2f} °C), held out {len(held_b)} "
          f"({len(hi)} samples, {temp[hi].min():.2f}–{temp[hi].max():.2f} °C)")
    for line in fit_out.stdout.splitlines():
        if "order" in line:
            print("imutherm:", line.strip())
    print("| axis | imutherm held-out RMS rad/s | numpy cubic held-out RMS rad/s | imutherm / cubic |")
    print("| --- | --- | --- | --- |")
    for k, axis in enumerate(AXES):
        ch = next(c for c in m["channels"] if c["name"] == axis)
        if ch.get("lag_s") or ch.get("hysteresis_term") or ch.get("rate_coefficient"):
            sys.exit(f"{model}: {axis} has a lag, hysteresis or rate term; apply it with tcal apply")
        def p_of(t):
            u = (np.clip(t, m["t_min_c"], m["t_max_c"]) - m["centre_c"]) / m["scale_c"]
            return sum(c * u ** j for j, c in enumerate(ch["coefficients"]))
        comp_k = data[hi, k] - (p_of(temp[hi]) - p_of(np.array(m["t_ref_c"])))
        ours = comp_k - comp_k.mean()
        p = np.polyfit(temp[fi], data[fi, k], 3)
        theirs = data[hi, k] - np.polyval(p, temp[hi])
        theirs = theirs - theirs.mean()
        r_o, r_c = np.sqrt(np.mean(ours ** 2)), np.sqrt(np.mean(theirs ** 2))
        print(f"| {axis} | {r_o:.4e} | {r_c:.4e} | {r_o / r_c:.3f} |")


if __name__ == "__main__":
    main()
