"""The fleet's acceptance run: a simulated production line of N units
(mpu9250-thesis population, five planted faults), analysed by
imutherm.fleet on a LocalCluster; checks that every planted unit is
flagged for what was planted and at most one good unit is, that a few
units' numbers equal the steps run by hand, the throughput of 2 workers
against 1, and that a rerun after adding 10 units analyses only those.

    python bench/fleet/acceptance.py DIR [--units 200] [--compare 20]

Needs the package with its fleet extra (pip install './crates/python[fleet]').
Prints one line per check and the figures for bench/README.md.
"""

import argparse
import os
import pathlib
import random
import shutil
import sys
import time

import imutherm
from imutherm import fleet

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "crates", "python", "tests"))
from fleet_support import write_unit  # noqa: E402  (the tests' writer of thesis logs)

#: Unit index -> planted fault, and the word its reason must carry.
PLANTED = {17: ("noise-3x", "white_noise"), 58: ("slope-5x", "tcal_slope"),
           101: ("dead-axis:accel_y", "dead axis"), 142: ("noise-3x", "white_noise"),
           176: ("slope-5x", "tcal_slope")}
LIMITS = """\
[gyro]
white_noise_max = 3.5e-4     # rad/sqrt(s): the population's N is 1.5e-4 (+-10 %)
white_noise_min = 1e-6
[accel]
white_noise_max = 1.7e-2     # m/s/sqrt(s)
white_noise_min = 1e-6
[outliers]
z_max = 5.0
terms = ["white_noise", "bias_instability", "tcal_slope", "tcal_residual_rms"]
"""


def uid(i):
    return f"SN-{i:04d}"


def write_line(folder, first, last):
    rows = []
    for i in range(first, last):
        defect = PLANTED.get(i, (None,))[0]
        p = write_unit(folder, uid(i), defect)
        rows.append(f"{uid(i)},{p['static'].name},{p['thermal'].name},,,px4")
    return rows


def manifest(folder, name, rows):
    path = os.path.join(folder, name)
    with open(path, "w", encoding="utf-8") as f:
        f.write("unit,static,thermal,held_out,instance,firmware\n" + "\n".join(rows) + "\n")
    return path


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dir")
    ap.add_argument("--units", type=int, default=200)
    ap.add_argument("--compare", type=int, default=20, help="units of the 1-vs-2-worker timing")
    ap.add_argument("--rayon-threads", type=int,
                    help="imutherm's threads per worker in the timing (RAYON_NUM_THREADS; default: "
                         "the cores shared among the workers)")
    ap.add_argument("--compare-only", action="store_true",
                    help="only the 1-vs-2-worker timing, on units written before")
    ap.add_argument("--no-write", dest="write", action="store_false",
                    help="use the units a previous run wrote into DIR/line")
    a = ap.parse_args()
    if a.rayon_threads:
        os.environ["RAYON_NUM_THREADS"] = str(a.rayon_threads)
    line = pathlib.Path(a.dir, "line")
    os.makedirs(line, exist_ok=True)
    t = time.time()
    rows = write_line(line, 0, a.units + 10) if a.write else [
        f"{uid(i)},{uid(i)}_static.txt,{uid(i)}_thermal.txt,,,px4" for i in range(a.units + 10)]
    print(f"wrote {a.units + 10} units in {time.time() - t:.0f} s" if a.write else "units as written before")
    limits = os.path.join(a.dir, "limits.toml")
    with open(limits, "w", encoding="utf-8") as f:
        f.write(LIMITS)
    units = manifest(line, "units.csv", rows[:a.units])
    ok = True
    if not a.compare_only:
        ok = accept(a, line, rows, units, limits)
    ok &= compare(a, line, rows, limits)
    print("ACCEPTED" if ok else "NOT ACCEPTED")
    return 0 if ok else 1


def accept(a, line, rows, units, limits):
    ok = True
    out = os.path.join(a.dir, "out")
    shutil.rmtree(out, ignore_errors=True)
    t = time.time()
    r = fleet.run(units, limits, out, workers=2)
    took = time.time() - t
    print(f"{a.units} units on 2 workers: {took:.0f} s ({a.units / took:.3f} units/s), {r.counts}")
    flagged = {}
    for row in r.rows:
        if row["flagged"]:
            flagged.setdefault(row["unit"], []).append(f"{row['channel']}: {row['reasons']}")
    ok = True
    for i, (defect, word) in PLANTED.items():
        why = " | ".join(flagged.get(uid(i), []))
        hit = word in why
        ok &= hit
        print(f"planted {uid(i)} {defect}: {'flagged' if uid(i) in flagged else 'NOT flagged'}, "
              f"reason {'has' if hit else 'lacks'} '{word}'")
    good = sorted(set(flagged) - {uid(i) for i in PLANTED})
    print(f"good units flagged: {len(good)} {good[:10]}")
    for u in good[:10]:
        print("   ", u, flagged[u][:2])
    ok &= len(good) < 2

    # The steps by hand on a few units: identical numbers.
    for i in random.Random(1).sample(range(a.units), 3):
        s = imutherm.read(os.path.join(line, f"{uid(i)}_static.txt"))
        m = imutherm.tcal_fit([os.path.join(line, f"{uid(i)}_thermal.txt")], firmware="px4")
        for row in (x for x in r.rows if x["unit"] == uid(i) and not x.get("noise_error")):
            n = imutherm.noise_terms(s.channels[row["channel"]], rate=s.rate)["terms"]["white_noise"]["value"]
            same = n == row["white_noise"] and m.channels[row["channel"]]["residual_rms"] == row["tcal_residual_rms"]
            ok &= same
        print(f"{uid(i)}: N and residual of every channel identical to the steps by hand: {same}")

    # A rerun after adding 10 units.
    more = manifest(line, "units_plus10.csv", rows)
    t = time.time()
    r2 = fleet.run(more, limits, out, workers=2)
    print(f"rerun with 10 more units: analysed {r2.counts['analysed']}, reused {r2.counts['reused']} "
          f"in {time.time() - t:.0f} s")
    ok &= r2.counts["analysed"] == 10
    return ok


def timed_run(units, limits, out, workers, progress=None):
    """``fleet.run`` on a local cluster of ``workers``, timed once the
    cluster is up (throughput, not the workers' start): its wall time and
    the CPU time its workers spent."""
    with fleet.connect(workers=workers) as c:
        c.run(lambda: __import__("imutherm").__version__)
        cpu = lambda: sum(c.run(time.process_time).values())
        before, t = cpu(), time.monotonic()
        fleet.run(units, limits, out, client=c, progress=progress)
        return time.monotonic() - t, cpu() - before


def compare(a, line, rows, limits):
    # Throughput: the same units on 1 worker and on 2, each from scratch.
    sub = manifest(line, "compare.csv", rows[:a.compare])
    times = {}
    for w in (1, 2):
        o = os.path.join(a.dir, f"out_w{w}")
        shutil.rmtree(o, ignore_errors=True)
        times[w], used = timed_run(sub, limits, o, w)
        # CPU seconds the workers spent: what the units cost whatever the
        # machine's other load, against the wall time it took.
        print(f"    workers' CPU {used:.1f} s ({used / a.compare:.2f} s a unit), "
              f"{used / times[w]:.2f} cores busy on average")
        print(f"{a.compare} units on {w} worker(s): {times[w]:.1f} s")
    ratio = times[1] / times[2]
    print(f"throughput 2 workers / 1 worker: {ratio:.2f}x "
          f"(load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores)")
    return ratio >= 1.7


if __name__ == "__main__":
    sys.exit(main())
