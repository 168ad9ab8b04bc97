#!/usr/bin/env python3
"""imutherm's temperature calibration against PX4's and ArduPilot's own
scripts, on the same logs, each parameter file applied to a held-out run as
the firmware applies it.

    compare.py [SEEDS…]        (default 1 2 3)
    compare.py --pool [SEEDS…] (the tables again from WORK/seedN/rows.json)
    compare.py --floor SEEDS…  (adds the true bias's own file to those rows)

Environment: PX4_CALDATA, the path of the PX4 script to run (a copy of
PX4-Autopilot's Tools/process_sensor_caldata.py, fetched or installed at
bench time, never kept here); AP_TEMPCAL, the same for ArduPilot's
Tools/scripts/tempcal_IMU.py (run with --no-graph --outfile; pymavlink and
matplotlib needed), the ArduPilot half left out when unset; IMUTHERM, the imutherm binary (default
`imutherm` on PATH); PYTHON, an interpreter with numpy, scipy, pyulog
(default: this one; pymavlink too for the ArduPilot half); WORK, where the logs go (default a temporary folder;
logs and the peer's file already there are reused; each seed's figures are
left in WORK/seedN/rows.json); DROP_LOGS=1 removes a seed's four logs (about
200 MB) once its figures are written, for runs of many seeds.

Per seed: make_logs.py writes a 45 min heating ULog (fitted) and a cooling
one (held out) with two IMUs of known cubic bias; PX4's script and
`imutherm tcal fit --for px4` (every instance in one model) + `tcal export`
each give a parameter file; each is applied to the held-out run here, by
this script's own transcription of PX4's
src/modules/temperature_compensation/TemperatureCompensation.cpp
(`set_sensor_id`: the set whose TC_x{n}_ID is the sensor's device id;
`calc_thermal_offsets_3D`: T held within [TMIN, TMAX], dT = T − TREF,
offset = X0 + X1·dT + X2·dT² + X3·dT³ in float32; corrected = raw − offset,
src/lib/sensor_calibration/Gyroscope.hpp `Correct`). ENABLE is reported,
and the sets are applied as if it were 1 (PX4's script does not write it).

The ArduPilot half does the same on the DataFlash logs (IMU at 25 Hz) with
`tempcal_IMU.py` and `imutherm tcal fit --for ardupilot` + `tcal export
--firmware ardupilot` (set N+1 for IMU N), each file applied by this script's
transcription of libraries/AP_InertialSensor/AP_InertialSensor_tempcal.cpp
(`correct_sensor`: nothing unless INS_TCALn_ENABLE is 1; T held within
[TMIN, TMAX]; v −= poly(T − 35) and v += poly(CALTEMP − 35), with
`polynomial_eval` (C1 + (C2 + C3·d)·d)·d·1e-6 in float; set n for the
IMU of index n − 1). CALTEMP only moves the level, which is left out.

A third file sets the floor: the plain least-squares cubic through every
sample of the fitted run (numpy's polyfit of the raw samples on their
temperature, no filter, no bins), which under white Gaussian noise is the
minimum-variance unbiased fit of these samples; a ratio no fit can beat
reliably. It is written in each firmware's format and applied the same way.

A fourth file, with `--floor`, holds the true bias itself (the cubic the
logs were made with, TMIN/TMAX wide enough that nothing is clamped): its
error is zero, and its residual spread is the held-out run's own noise, the
floor of that figure, printed as the last column ("truth spread").

Printed per instance and axis, median over the seeds: the residual spread
(standard deviation over the held-out run's 1 °C bins of the corrected
bin means) and the error against the true bias (standard deviation over
those bins of offset − true bias); the level (the bin means' mean) is left
out of both, since PX4 keeps the accelerometer's level apart.
"""

import functools
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


@functools.lru_cache(maxsize=2)
def ulog_topics(path):
    """The IMU topics of a ULog, parsed once for every file judged on it."""
    return ULog(str(path), message_name_filter_list=["sensor_gyro", "sensor_accel"]).data_list


def judge(pfile, log, truth):
    p = params(pfile)
    rows = {}
    for d in ulog_topics(log):
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


def ap_params(path):
    out = {}
    for line in Path(path).read_text().splitlines():
        f = line.split()
        if line.startswith("#") or len(f) != 2:
            continue
        out[f[0]] = np.float32(float(f[1]))
    return out


def ap_offsets(p, kind, imu, temp):
    """What correct_sensor subtracts from IMU `imu`'s `kind` (ACC/GYR), up
    to the constant poly(CALTEMP − 35), or None when nothing is applied."""
    s = f"INS_TCAL{imu + 1}"
    if p.get(f"{s}_ENABLE") != 1:
        return None
    t = np.clip(temp.astype(np.float32), p[f"{s}_TMIN"], p[f"{s}_TMAX"])
    d = (t - np.float32(35.0)).astype(np.float32)
    out = []
    for axis in "XYZ":
        c1, c2, c3 = (p[f"{s}_{kind}{k}_{axis}"] for k in (1, 2, 3))
        out.append((((c1 + (c2 + c3 * d) * d) * d) * np.float32(1e-6)).astype(np.float32))
    return out


@functools.lru_cache(maxsize=2)
def dataflash_imu(path):
    """The IMU messages of a DataFlash log, per instance, as pymavlink reads them."""
    from pymavlink import mavutil
    log = mavutil.mavlink_connection(str(path))
    rows = {}
    while (m := log.recv_match(type="IMU")) is not None:
        rows.setdefault(m.I, []).append((m.T, m.GyrX, m.GyrY, m.GyrZ, m.AccX, m.AccY, m.AccZ))
    return {i: np.array(r, dtype=np.float64) for i, r in rows.items()}


def judge_ap(pfile, log, truth):
    p = ap_params(pfile)
    rows = {}
    for imu, a in dataflash_imu(log).items():
        temp = a[:, 0]
        for sensor, kind, col in (("gyro", "GYR", 1), ("accel", "ACC", 4)):
            off = ap_offsets(p, kind, imu, temp)
            for k, axis in enumerate("xyz"):
                raw = a[:, col + k].astype(np.float32)
                corr = raw - off[k] if off is not None else raw
                means, _ = bins(temp, corr.astype(np.float64))
                o = off[k].astype(np.float64) if off is not None else np.zeros_like(temp)
                c = truth["instances"][imu][sensor][k]
                dT = temp - truth["t_mid_c"]
                err, _ = bins(temp, o - (c[0] + c[1] * dT + c[2] * dT**2 + c[3] * dT**3))
                rows[(imu, f"{sensor}_{axis}")] = (float(np.std(means)), float(np.std(err)), off is not None)
    enabled = {f"INS_TCAL{i + 1}_ENABLE": bool(p.get(f"INS_TCAL{i + 1}_ENABLE") == 1) for i in range(len(truth["ids"]))}
    return rows, enabled


def table(title, peer, results):
    print(title)
    keys = sorted(results[peer][0])
    floor = len(results.get("truth", [])) == len(results[peer])
    print(f"{'IMU':>3} {'axis':<8} {'spread ' + peer:>14} {'imutherm':>11} {'ratio':>6}   "
          f"{'error ' + peer:>14} {'imutherm':>11} {'ratio':>6} {'lsq ratio':>9}"
          + (f" {'truth spread':>12}" if floor else ""))
    for k in keys:
        med = lambda name, i: statistics.median(r[k][i] for r in results[name])
        sp, si, ep, ei = med(peer, 0), med("imutherm", 0), med(peer, 1), med("imutherm", 1)
        el = med("lsq", 1)
        print(f"{k[0]:>3} {k[1]:<8} {sp:>14.3e} {si:>11.3e} {si / sp:>6.2f}   "
              f"{ep:>14.3e} {ei:>11.3e} {ei / ep:>6.2f} {el / ep:>9.2f}"
              + (f" {med('truth', 0) / sp:>12.3f}" if floor else ""))
    ratios = np.array([results["imutherm"][i][k][1] / results[peer][i][k][1]
                       for i in range(len(results[peer])) for k in keys])
    print(f"{len(ratios)} seed x IMU x axis pairs: error ratio geometric mean {np.exp(np.log(ratios).mean()):.2f}, "
          f"imutherm below {peer} in {(ratios < 1).sum()}")


def lsq_px4(log, out):
    """The least-squares file in PX4's format, TREF the range's middle."""
    lines = []
    for d in ulog_topics(log):
        if d.name not in ("sensor_gyro", "sensor_accel"):
            continue
        s = f"TC_{'G' if d.name == 'sensor_gyro' else 'A'}{d.multi_id}"
        temp = d.data["temperature"].astype(np.float64)
        lo, hi = temp.min(), temp.max()
        tref = 0.5 * (lo + hi)
        vals = {f"{s}_ID": int(d.data["device_id"][0]), f"{s}_TMIN": lo, f"{s}_TMAX": hi, f"{s}_TREF": tref}
        for a, axis in enumerate("xyz"):
            c = np.polyfit(temp - tref, d.data[axis].astype(np.float64), 3)
            vals.update({f"{s}_X{k}_{a}": c[3 - k] for k in range(4)})
        lines += [f"1\t1\t{k}\t{v}\t{6 if k.endswith('_ID') else 9}" for k, v in vals.items()]
    Path(out).write_text("\n".join(lines + ["1\t1\tTC_G_ENABLE\t1\t6", "1\t1\tTC_A_ENABLE\t1\t6", ""]))


def lsq_ap(log, out):
    """The least-squares file in ArduPilot's format (about 35 °C, no constant)."""
    lines = []
    for imu, a in dataflash_imu(log).items():
        s = f"INS_TCAL{imu + 1}"
        temp = a[:, 0]
        lines += [f"{s}_ENABLE 1", f"{s}_TMIN {float(temp.min())!r}", f"{s}_TMAX {float(temp.max())!r}"]
        for kind, col in (("ACC", 4), ("GYR", 1)):
            for k, axis in enumerate("XYZ"):
                c = np.polyfit(temp - 35.0, a[:, col + k], 3)
                lines += [f"{s}_{kind}{p}_{axis} {float(c[3 - p] * 1e6)!r}" for p in (1, 2, 3)]
    Path(out).write_text("\n".join(lines + [""]))


def truth_px4(truth, out):
    """The true bias in PX4's format: TREF the cubic's own centre."""
    lines = []
    for i, ids in enumerate(truth["ids"]):
        for letter, sensor, dev in (("G", "gyro", ids[0]), ("A", "accel", ids[1])):
            s = f"TC_{letter}{i}"
            vals = {f"{s}_ID": dev, f"{s}_TMIN": -40.0, f"{s}_TMAX": 125.0, f"{s}_TREF": truth["t_mid_c"]}
            for a in range(3):
                c = truth["instances"][i][sensor][a]
                vals.update({f"{s}_X{k}_{a}": c[k] for k in range(4)})
            lines += [f"1\t1\t{k}\t{v}\t{6 if k.endswith('_ID') else 9}" for k, v in vals.items()]
    Path(out).write_text("\n".join(lines + ["1\t1\tTC_G_ENABLE\t1\t6", "1\t1\tTC_A_ENABLE\t1\t6", ""]))


def truth_ap(truth, out):
    """The true bias in ArduPilot's format: the cubic re-centred at 35 °C,
    its constant (the level) left out."""
    lines = []
    for i in range(len(truth["ids"])):
        s = f"INS_TCAL{i + 1}"
        lines += [f"{s}_ENABLE 1", f"{s}_TMIN -40.0", f"{s}_TMAX 125.0"]
        for kind, sensor in (("ACC", "accel"), ("GYR", "gyro")):
            for a, axis in enumerate("XYZ"):
                # b(x) with x = T - t_mid = d + (35 - t_mid), as a polynomial in d.
                shifted = np.polynomial.Polynomial(truth["instances"][i][sensor][a])(
                    np.polynomial.Polynomial([35.0 - truth["t_mid_c"], 1.0]))
                c = np.pad(shifted.coef, (0, 4))[:4]
                lines += [f"{s}_{kind}{k}_{axis} {float(c[k] * 1e6)!r}" for k in (1, 2, 3)]
    Path(out).write_text("\n".join(lines + [""]))


def floor(work, seeds, python):
    """Adds each seed's true-bias file, judged as the others, to its rows."""
    for seed in seeds:
        d = work / f"seed{seed}"
        if not (d / "cooling.ulg").is_file() or not (d / "cooling.bin").is_file():
            subprocess.run([python, str(HERE / "make_logs.py"), str(seed), str(d)], check=True)
        truth = json.loads((d / "truth.json").read_text())
        rows = json.loads((d / "rows.json").read_text())
        truth_px4(truth, d / "truth.params")
        judged, _ = judge(d / "truth.params", d / "cooling.ulg", truth)
        rows["truth px4"] = {f"{k[0]} {k[1]}": v for k, v in judged.items()}
        if "ArduPilot" in rows:
            truth_ap(truth, d / "truth.parm")
            judged, _ = judge_ap(d / "truth.parm", d / "cooling.bin", truth)
            rows["truth ardupilot"] = {f"{k[0]} {k[1]}": v for k, v in judged.items()}
        (d / "rows.json").write_text(json.dumps(rows))
        drop_logs(d)
        print(f"seed {seed}: floor added", file=sys.stderr)


def drop_logs(d):
    if os.environ.get("DROP_LOGS") == "1":
        for name in ("heating.ulg", "cooling.ulg", "heating.bin", "cooling.bin"):
            (d / name).unlink(missing_ok=True)


def pooled(work, seeds):
    """The tables of seeds already judged, from their rows.json."""
    results, ap_results = {}, {}
    for seed in seeds:
        rows = json.loads((work / f"seed{seed}" / "rows.json").read_text())
        for name, into in (("px4", results), ("imutherm px4", results), ("lsq px4", results),
                           ("truth px4", results), ("ArduPilot", ap_results),
                           ("imutherm ardupilot", ap_results), ("lsq ardupilot", ap_results),
                           ("truth ardupilot", ap_results)):
            if name in rows:
                into.setdefault(name.split()[0], []).append(
                    {(int(k.split()[0]), k.split()[1]): tuple(v) for k, v in rows[name].items()})
    return results, ap_results


def main():
    args = sys.argv[1:]
    if args[:1] == ["--pool"]:
        work = Path(os.environ.get("WORK") or sys.exit("--pool reads WORK/seedN/rows.json: set WORK"))
        seeds = [int(s) for s in args[1:]] or sorted(
            int(d.name[4:]) for d in work.glob("seed*") if (d / "rows.json").is_file())
        results, ap_results = pooled(work, seeds)
        print(f"seeds {' '.join(map(str, seeds))}")
        table("PX4 (ULog, 200 Hz)", "px4", results)
        if ap_results:
            table("ArduPilot (DataFlash, IMU at 25 Hz)", "ArduPilot", ap_results)
        return
    if args[:1] == ["--floor"]:
        work = Path(os.environ.get("WORK") or sys.exit("--floor adds to WORK/seedN/rows.json: set WORK"))
        floor(work, [int(s) for s in args[1:]], os.environ.get("PYTHON", sys.executable))
        return
    seeds = [int(s) for s in args] or [1, 2, 3]
    peer = os.environ.get("PX4_CALDATA")
    if not peer or not Path(peer).is_file():
        sys.exit("set PX4_CALDATA to a copy of PX4-Autopilot's Tools/process_sensor_caldata.py")
    ap_peer = os.environ.get("AP_TEMPCAL")
    if ap_peer and not Path(ap_peer).is_file():
        sys.exit("AP_TEMPCAL is not a file: set it to a copy of ArduPilot's Tools/scripts/tempcal_IMU.py")
    imutherm = os.environ.get("IMUTHERM", "imutherm")
    python = os.environ.get("PYTHON", sys.executable)
    work = Path(os.environ.get("WORK") or tempfile.mkdtemp(prefix="tcal_peers_"))
    results, ap_results = {}, {}
    for seed in seeds:
        d = work / f"seed{seed}"
        # Logs and the peer's file are kept in WORK and reused, so a change
        # of imutherm is judged on the very same files.
        if not (d / "truth.json").is_file() or not (d / "heating.bin").is_file():
            subprocess.run([python, str(HERE / "make_logs.py"), str(seed), str(d)], check=True)
        truth = json.loads((d / "truth.json").read_text())
        if not (d / "heating.ulg.params").is_file():
            subprocess.run([python, peer, str(d / "heating.ulg")], check=True, stdout=subprocess.DEVNULL)
        # Every IMU of the log in one model and one file, as a user runs it.
        ours, model = d / "imutherm.params", d / "imutherm_px4.json"
        subprocess.run([imutherm, "tcal", "fit", str(d / "heating.ulg"), "--for", "px4", "--overwrite", "-o",
                        str(model)], check=True, stderr=subprocess.DEVNULL)
        subprocess.run([imutherm, "tcal", "export", str(model), "--firmware", "px4", "--overwrite", "-o", str(ours)],
                       check=True, stderr=subprocess.DEVNULL)
        lsq_px4(d / "heating.ulg", d / "lsq.params")
        for name, pfile in (("px4", d / "heating.ulg.params"), ("imutherm", ours), ("lsq", d / "lsq.params")):
            rows, enabled = judge(pfile, d / "cooling.ulg", truth)
            results.setdefault(name, []).append(rows)
            print(f"seed {seed} {name}: ENABLE {enabled}", file=sys.stderr)
        seed_rows = {"px4": {f"{k[0]} {k[1]}": v for k, v in results["px4"][-1].items()}}
        seed_rows["imutherm px4"] = {f"{k[0]} {k[1]}": v for k, v in results["imutherm"][-1].items()}
        seed_rows["lsq px4"] = {f"{k[0]} {k[1]}": v for k, v in results["lsq"][-1].items()}
        if not ap_peer:
            (d / "rows.json").write_text(json.dumps(seed_rows))
            drop_logs(d)
            continue
        theirs = d / "heating.bin.parm"
        if not theirs.is_file():
            subprocess.run([python, ap_peer, "--no-graph", "--outfile", str(theirs), str(d / "heating.bin")],
                           check=True, stdout=subprocess.DEVNULL)
        ours, model = d / "imutherm.parm", d / "imutherm_ardupilot.json"
        subprocess.run([imutherm, "tcal", "fit", str(d / "heating.bin"), "--for", "ardupilot", "--overwrite", "-o",
                        str(model)], check=True, stderr=subprocess.DEVNULL)
        subprocess.run([imutherm, "tcal", "export", str(model), "--firmware", "ardupilot", "--overwrite", "-o",
                        str(ours)], check=True, stderr=subprocess.DEVNULL)
        lsq_ap(d / "heating.bin", d / "lsq.parm")
        for name, pfile in (("ArduPilot", theirs), ("imutherm", ours), ("lsq", d / "lsq.parm")):
            rows, enabled = judge_ap(pfile, d / "cooling.bin", truth)
            ap_results.setdefault(name, []).append(rows)
            print(f"seed {seed} {name}: ENABLE {enabled}", file=sys.stderr)
            seed_rows[name if name == "ArduPilot" else f"{name} ardupilot"] = {
                f"{k[0]} {k[1]}": v for k, v in rows.items()}
        # Each seed's rows (spread, error, applied), to pool seeds of several runs.
        (d / "rows.json").write_text(json.dumps(seed_rows))
        drop_logs(d)
    table("PX4 (ULog, 200 Hz)", "px4", results)
    if ap_results:
        table("ArduPilot (DataFlash, IMU at 25 Hz)", "ArduPilot", ap_results)


if __name__ == "__main__":
    main()
