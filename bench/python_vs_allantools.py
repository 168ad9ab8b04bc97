#!/usr/bin/env python3
"""Times imutherm's Python package against AllanTools 2024.6 and against
imutherm's own Rust library, in one process, on the same arrays: the best of
several runs of each, and their ratios.

    python3 -m venv bench/.venv
    bench/.venv/bin/pip install numpy allantools==2024.6 ./crates/python
    bench/.venv/bin/python bench/python_vs_allantools.py --all    # every figure below
    bench/.venv/bin/python bench/python_vs_allantools.py          # simple statistics, 10^6 and 10^7
    bench/.venv/bin/python bench/python_vs_allantools.py --sizes 1e4 --runs 1 --all-taus-size 1e3
    bench/.venv/bin/python bench/python_vs_allantools.py --expensive   # MTOTDEV, HTOTDEV, Theo1

Three tables:

* the simple statistics (OADEV, MDEV, HDEV, OHDEV, TOTDEV) at octave taus
  on white-noise rate data, at --sizes (10^6 and 10^7 by default): the
  Python call, the Rust library's ``allan::analyze`` timed inside the
  extension (no Python in between), their ratio (the goal: the Python call
  within 10 % of the library), AllanTools and imutherm's speed-up over it;
* the same statistics at ``taus="all"`` on --all-taus-size samples (10^5);
* with --expensive (or --all): MTOTDEV, HTOTDEV and Theo1 at
  --expensive-sizes (10^4 and 10^5), each AllanTools call in a child process
  stopped after --cap seconds (600), reported as "> 600 s".

Both tools get the array as float64 rate data ("freq"); where AllanTools
finishes in the parent process, the deviations are checked to agree to
1e-9 relative at every tau both compute before a timing counts.
"""

import argparse
import multiprocessing as mp
import time

import allantools
import numpy as np

import imutherm
from imutherm import _imutherm

SIMPLE = ["oadev", "mdev", "hdev", "ohdev", "totdev"]
EXPENSIVE = ["mtotdev", "htotdev", "theo1"]


def best_of(runs, fn):
    times, result = [], None
    for _ in range(runs):
        start = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - start)
    return min(times), result


def check(stat, mine, theirs, rate):
    by_m = {int(round(t * rate)): d for t, d in zip(theirs[0], theirs[1])}
    common = [(d, by_m[int(m)]) for m, d in zip(mine.m, mine.devs) if int(m) in by_m]
    if not common:
        raise SystemExit(f"{stat}: no tau in common with AllanTools")
    worst = max(abs(a / b - 1) for a, b in common)
    if worst > 1e-9:
        raise SystemExit(f"{stat}: deviations differ by {worst:.2e} relative")


def library_time(stat, y, taus, runs):
    """The Rust library's best time on the same array, measured in Rust."""
    return _imutherm.time_library(stat, y, 1.0, taus, "freq", 0.683, runs)


def allantools_child(stat, y, taus, queue):
    start = time.perf_counter()
    getattr(allantools, stat)(y, rate=1.0, data_type="freq", taus=taus)
    queue.put(time.perf_counter() - start)


def capped_allantools(stat, y, taus, cap):
    """AllanTools' time in a child process, or None when it ran out of time."""
    queue = mp.Queue()
    child = mp.Process(target=allantools_child, args=(stat, y, taus, queue))
    child.start()
    child.join(cap)
    if child.is_alive():
        child.terminate()
        child.join()
        return None
    return queue.get()


def simple_table(sizes, taus, runs, rng):
    print(f"\nsimple statistics, taus={taus!r}")
    print(f"{'stat':8} {'samples':>9} {'Python s':>10} {'Rust lib s':>11} {'Py/Rust':>8} "
          f"{'AllanTools s':>13} {'speed-up':>9}")
    for n in sizes:
        y = rng.standard_normal(n)
        for stat in SIMPLE:
            mine_t, mine = best_of(runs, lambda: imutherm.analyze(stat, y, taus=taus))
            lib_t = library_time(stat, y, taus, runs)
            theirs_t, theirs = best_of(min(runs, 3), lambda: getattr(allantools, stat)(
                y, rate=1.0, data_type="freq", taus=taus))
            check(stat, mine, theirs, 1.0)
            print(f"{stat:8} {n:9d} {mine_t:10.4f} {lib_t:11.4f} {mine_t / lib_t:7.3f}x "
                  f"{theirs_t:13.4f} {theirs_t / mine_t:8.1f}x", flush=True)


def expensive_table(sizes, runs, cap, rng):
    print(f"\nexpensive statistics, octave taus, AllanTools capped at {cap:.0f} s")
    print(f"{'stat':8} {'samples':>9} {'Python s':>10} {'Rust lib s':>11} {'Py/Rust':>8} "
          f"{'AllanTools s':>13} {'speed-up':>9}")
    for n in sizes:
        y = rng.standard_normal(n)
        for stat in EXPENSIVE:
            mine_t, _ = best_of(runs, lambda: imutherm.analyze(stat, y))
            lib_t = library_time(stat, y, "octave", runs)
            theirs = capped_allantools(stat, y, "octave", cap)
            shown = f"> {cap:.0f}" if theirs is None else f"{theirs:.3f}"
            ratio = (f"> {cap / mine_t:.0f}" if theirs is None else f"{theirs / mine_t:.0f}") + "x"
            print(f"{stat:8} {n:9d} {mine_t:10.4f} {lib_t:11.4f} {mine_t / lib_t:7.3f}x "
                  f"{shown:>13} {ratio:>9}", flush=True)


def counts(text):
    return [int(float(s)) for s in text.split(",") if s.strip()]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", default="1e6,1e7", help="sample counts for the simple statistics")
    ap.add_argument("--all-taus-size", default="1e5",
                    help="sample count for the simple statistics at taus='all' (0: skip)")
    ap.add_argument("--runs", type=int, default=5,
                    help="runs per figure (AllanTools: at most 3)")
    ap.add_argument("--expensive", action="store_true",
                    help="time MTOTDEV, HTOTDEV and Theo1 instead")
    ap.add_argument("--all", action="store_true", help="every table")
    ap.add_argument("--expensive-sizes", default="1e4,1e5",
                    help="sample counts for MTOTDEV, HTOTDEV and Theo1")
    ap.add_argument("--cap", type=float, default=600.0,
                    help="seconds AllanTools gets per expensive call")
    a = ap.parse_args()
    rng = np.random.default_rng(42)
    if not a.expensive or a.all:
        simple_table(counts(a.sizes), "octave", a.runs, rng)
        if counts(a.all_taus_size) and counts(a.all_taus_size)[0] > 0:
            simple_table(counts(a.all_taus_size), "all", a.runs, rng)
    if a.expensive or a.all:
        expensive_table(counts(a.expensive_sizes), a.runs, a.cap, rng)


if __name__ == "__main__":
    main()
