#!/usr/bin/env python3
"""imutherm's PX4 temperature calibration against PX4's own script, on the
same logs, each parameter file applied to a held-out run as PX4 applies it.

    compare.py [SEEDS…]        (default 1 2 3)

Environment: PX4_CALDATA, the path of the PX4 script to run (a copy of
PX4-Autopilot's Tools/process_sensor_caldata.py, fetched or installed at
bench time, never kept here); IMUTHERM, the imutherm binary (default
`imutherm` on PATH); PYTHON, an interpreter with numpy, scipy, pyulog
(default: this one); WORK, where the logs go (default a temporary folder).

Per seed: make_logs.py writes a 45 min heating ULog (fitted) and a cooling
one (held out) with two IMUs of known cubic bias; PX4's script and
`imutherm tcal fit --instance N --for px4` + `tcal export --instance N`
each give a parameter file; each is applied to the held-out run here, by
this script's own transcription of PX4's
src/modules/temperature_compensation/TemperatureCompensation.cpp
(`set_sensor_id`: the set whose TC_x{n}_ID is the sensor's device id;
`calc_thermal_offsets_3D`: T held within [TMIN, TMAX], dT = T − TREF,
offset = X0 + X1·dT + X2·dT² + X3·dT³ in float32; corrected = raw − offset,
src/lib/sensor_calibration/Gyroscope.hpp `Correct`). ENABLE is reported,
and the sets are applied as if it were 1 (PX4's script does not write it).

Printed per instance and axis, median over the seeds: the residual spread
(standard deviation over the held-out run's 1 °C bins of the corrected
bin means) and the error against the true bias (standard deviation over
those bins of offset − true bias); the level (the bin means' mean) is left
out of both, since PX4 keeps the accelerometer's level apart.
"""

import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
from pyulog import ULog

HERE = Path(__file__).resolve().parent


def params(path):
    out = {}
    for line in Path(path).read_text().splitlines():
        f = line.split("\t")
        if line.startswith("#") or len(f) < 5:
            continue
        out[f[2]] = int(f[3]) if f[4].strip() == "6" else np.float32(float(f[3]))
    return out


def offsets(p, letter, device_id, temp):
    """calc_thermal_offsets_3D for the set PX4 picks, or None."""
    n = next((n for n in range(4) if p.get(f"TC_{letter}{n}_ID") == device_id), None)
    if n is None:
        return None
    s = f"TC_{letter}{n}"
    t = np.clip(temp.astype(np.float32), p[f"{s}_TMIN"], p[f"{s}_TMAX"])
    d = (t - p[f"{s}_TREF"]).astype(np.float32)
    d2 = (d * d).astype(np.float32)
    d3 = (d2 * d).astype(np.float32)
    return [(p[f"{s}_X0_{a}"] + p[f"{s}_X1_{a}"] * d + p[f"{s}_X2_{a}"] * d2 + p[f"{s}_X3_{a}"] * d3)
            .astype(np.float32) for a in range(3)]


def bins(temp, values):
    keys = np.floor(temp).astype(int)
    return np.array([values[keys == k].mean() for k in np.unique(keys)]), np.array(
        [temp[keys == k].mean() for k in np.unique(keys)])


def judge(pfile, log, truth):
    p = params(pfile)
    rows = {}
    for d in ULog(str(log)).data_list:
        if d.name not in ("sensor_gyro", "sensor_accel"):
            continue
        letter = "G" if d.name == "sensor_gyro" else "A"
        temp = d.data["temperature"].astype(np.float64)
        dev = int(d.data["device_id"][0])
        off = offsets(p, letter, dev, temp)
        tr = truth["instances"][d.multi_id]["gyro" if letter == "G" else "accel"]
        for a, axis in enumerate("xyz"):
            raw = d.data[axis].astype(np.float32)
            corr = raw - off[a] if off is not None else raw
            means, tbin = bins(temp, corr.astype(np.float64))
            o = off[a].astype(np.float64) if off is not None else np.zeros_like(temp)
            c = tr[a]
            dT = temp - truth["t_mid_c"]
            true_bias = c[0] + c[1] * dT + c[2] * dT**2 + c[3] * dT**3
            err, _ = bins(temp, o - true_bias)
            rows[(d.multi_id, f"{'gyro' if letter == 'G' else 'accel'}_{axis}")] = (
                float(np.std(means)), float(np.std(err)), off is not None)
    enabled = {k: p.get(k) == 1 for k in ("TC_G_ENABLE", "TC_A_ENABLE")}
    return rows, enabled


def main():
    seeds = [int(s) for s in sys.argv[1:]] or [1, 2, 3]
    peer = os.environ.get("PX4_CALDATA")
    if not peer or not Path(peer).is_file():
        sys.exit("set PX4_CALDATA to a copy of PX4-Autopilot's Tools/process_sensor_caldata.py")
    imutherm = os.environ.get("IMUTHERM", "imutherm")
    python = os.environ.get("PYTHON", sys.executable)
    work = Path(os.environ.get("WORK") or tempfile.mkdtemp(prefix="tcal_peers_"))
    results = {}
    for seed in seeds:
        d = work / f"seed{seed}"
        subprocess.run([python, str(HERE / "make_logs.py"), str(seed), str(d)], check=True)
        truth = json.loads((d / "truth.json").read_text())
        subprocess.run([python, peer, str(d / "heating.ulg")], check=True, stdout=subprocess.DEVNULL)
        ours = d / "imutherm.params"
        with open(ours, "w") as out:
            for n in range(len(truth["ids"])):
                model = d / f"imu{n}.json"
                subprocess.run([imutherm, "tcal", "fit", str(d / "heating.ulg"), "--instance", str(n), "--for",
                                "px4", "--overwrite", "-o", str(model)], check=True, stderr=subprocess.DEVNULL)
                subprocess.run([imutherm, "tcal", "export", str(model), "--firmware", "px4", "--instance", str(n)],
                               check=True, stdout=out, stderr=subprocess.DEVNULL)
        for name, pfile in (("px4", d / "heating.ulg.params"), ("imutherm", ours)):
            rows, enabled = judge(pfile, d / "cooling.ulg", truth)
            results.setdefault(name, []).append(rows)
            print(f"seed {seed} {name}: ENABLE {enabled}", file=sys.stderr)
    keys = sorted(results["px4"][0])
    print(f"{'IMU':>3} {'axis':<8} {'spread PX4':>11} {'imutherm':>11} {'ratio':>6}   "
          f"{'error PX4':>11} {'imutherm':>11} {'ratio':>6}")
    for k in keys:
        med = lambda name, i: statistics.median(r[k][i] for r in results[name])
        sp, si, ep, ei = med("px4", 0), med("imutherm", 0), med("px4", 1), med("imutherm", 1)
        print(f"{k[0]:>3} {k[1]:<8} {sp:>11.3e} {si:>11.3e} {si / sp:>6.2f}   {ep:>11.3e} {ei:>11.3e} {ei / ep:>6.2f}")


if __name__ == "__main__":
    main()
