"""How the fleet scales: the same units analysed by a plain loop in one
process (the steps of one Dask task, without Dask), by imutherm.fleet on
a LocalCluster of 1 worker and of 2, each from an empty output folder,
timed once the cluster is up. Prints wall time, the CPU time the work
took (the loop's process, or the workers'), cores busy, and the ratios:
2 workers against 1, and 1 worker against the loop (what Dask costs).

    python bench/fleet/scaling.py DIR [--units 200] [--rayon-threads N]

Units are the acceptance line's (bench/fleet/acceptance.py writes them
into DIR/line; they are written here when missing). On a loaded machine
the wall-time ratio says little: read the CPU times.
"""

import argparse
import os
import pathlib
import shutil
import sys
import time


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dir")
    ap.add_argument("--units", type=int, default=200)
    ap.add_argument("--rayon-threads", type=int,
                    help="imutherm's threads per process (RAYON_NUM_THREADS; default: the loop "
                         "takes every core, a worker its share)")
    a = ap.parse_args()
    if a.rayon_threads:
        # Before imutherm is imported: rayon reads it when its pool starts.
        os.environ["RAYON_NUM_THREADS"] = str(a.rayon_threads)
    sys.path.insert(0, os.path.dirname(__file__))
    from acceptance import LIMITS, manifest, timed_run, uid, write_line  # the acceptance line's

    from imutherm import fleet
    from imutherm.fleet import manifest as manifest_mod, unit as unit_mod

    line = pathlib.Path(a.dir, "line")
    line.mkdir(parents=True, exist_ok=True)
    missing = [i for i in range(a.units) if not (line / f"{uid(i)}_thermal.txt").exists()]
    if missing:
        t = time.time()
        write_line(line, 0, a.units)
        print(f"wrote {a.units} units in {time.time() - t:.0f} s")
    rows = [f"{uid(i)},{uid(i)}_static.txt,{uid(i)}_thermal.txt,,,px4" for i in range(a.units)]
    units_csv = manifest(line, "scaling.csv", rows)
    limits = os.path.join(a.dir, "limits.toml")
    pathlib.Path(limits).write_text(LIMITS, encoding="utf-8")
    settings = {"rate": None, "order": "auto", "confidence": 0.95}

    results = {}
    out = os.path.join(a.dir, "scaling_loop")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    units = manifest_mod.load(units_csv)
    cpu0, t0 = time.process_time(), time.monotonic()
    for u in units:
        unit_mod.analyse(u, settings, out)
    results["loop"] = (time.monotonic() - t0, time.process_time() - cpu0)
    for w in (1, 2):
        out = os.path.join(a.dir, f"scaling_w{w}")
        shutil.rmtree(out, ignore_errors=True)
        results[f"{w} worker{'s' if w > 1 else ''}"] = timed_run(
            units, limits, out, w, progress=fleet.Progress(0, open(os.devnull, "w")))

    print(f"{a.units} units, {os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f}, "
          f"RAYON_NUM_THREADS {os.environ.get('RAYON_NUM_THREADS', 'unset')}")
    print(f"{'':10} {'wall s':>8} {'CPU s':>8} {'CPU s/unit':>10} {'cores busy':>10}")
    for name, (wall, used) in results.items():
        print(f"{name:10} {wall:8.1f} {used:8.1f} {used / a.units:10.3f} {used / wall:10.2f}")
    one, two, loop = results["1 worker"], results["2 workers"], results["loop"]
    print(f"2 workers / 1 worker: {one[0] / two[0]:.2f}x in wall time; "
          f"1 worker / loop: {one[0] / loop[0]:.2f}x in wall time, {one[1] / loop[1]:.2f}x in CPU")
    return 0


if __name__ == "__main__":
    sys.exit(main())
