#!/usr/bin/env python3
"""Times imutherm's Python package against AllanTools 2024.6 in one process,
on the same arrays: the best of several runs of each, and their ratio.

    python3 -m venv bench/.venv
    bench/.venv/bin/pip install numpy allantools==2024.6 ./crates/python
    bench/.venv/bin/python bench/python_vs_allantools.py               # 10^6 and 10^7
    bench/.venv/bin/python bench/python_vs_allantools.py --sizes 1e6
    bench/.venv/bin/python bench/python_vs_allantools.py --expensive   # MTOTDEV, HTOTDEV, Theo1

The simple statistics (OADEV, MDEV, HDEV, OHDEV, TOTDEV) run at octave taus
on white-noise rate data. --expensive times MTOTDEV, HTOTDEV and Theo1 at
10^4 and 10^5 samples, each AllanTools call in a child process stopped after
--cap seconds (reported as "> cap s"). Both tools get the array as float64
rate data ("freq"); the deviations are checked to agree before timing counts.
"""

import argparse
import multiprocessing as mp
import time

import allantools
import numpy as np

import imutherm

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
    worst = max(abs(a / b - 1) for a, b in common)
    if worst > 1e-9:
        raise SystemExit(f"{stat}: deviations differ by {worst:.2e} relative")


def allantools_child(stat, y, queue):
    start = time.perf_counter()
    getattr(allantools, stat)(y, rate=1.0, data_type="freq", taus="octave")
    queue.put(time.perf_counter() - start)


def capped_allantools(stat, y, cap):
    queue = mp.Queue()
    child = mp.Process(target=allantools_child, args=(stat, y, queue))
    child.start()
    child.join(cap)
    if child.is_alive():
        child.terminate()
        child.join()
        return None
    return queue.get()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", default="1e6,1e7", help="sample counts for the simple statistics")
    ap.add_argument("--runs", type=int, default=5, help="runs of imutherm per figure (AllanTools: 3)")
    ap.add_argument("--expensive", action="store_true", help="time MTOTDEV, HTOTDEV and Theo1 instead")
    ap.add_argument("--cap", type=float, default=600.0, help="seconds AllanTools gets per expensive call")
    a = ap.parse_args()
    rng = np.random.default_rng(42)
    print(f"{'stat':8} {'samples':>9} {'imutherm s':>11} {'AllanTools s':>13} {'ratio':>8}")
    if a.expensive:
        for n in (10_000, 100_000):
            y = rng.standard_normal(n)
            for stat in EXPENSIVE:
                mine, _ = best_of(a.runs, lambda: imutherm.analyze(stat, y))
                theirs = capped_allantools(stat, y, a.cap)
                shown = f"> {a.cap:.0f}" if theirs is None else f"{theirs:.3f}"
                ratio = (f"> {a.cap / mine:.0f}" if theirs is None else f"{theirs / mine:.0f}") + "x"
                print(f"{stat:8} {n:9d} {mine:11.4f} {shown:>13} {ratio:>8}", flush=True)
        return
    for n in (int(float(s)) for s in a.sizes.split(",")):
        y = rng.standard_normal(n)
        for stat in SIMPLE:
            mine_t, mine = best_of(a.runs, lambda: imutherm.analyze(stat, y))
            theirs_t, theirs = best_of(3, lambda: getattr(allantools, stat)(
                y, rate=1.0, data_type="freq", taus="octave"))
            check(stat, mine, theirs, 1.0)
            print(f"{stat:8} {n:9d} {mine_t:11.4f} {theirs_t:13.4f} {theirs_t / mine_t:7.1f}x", flush=True)


if __name__ == "__main__":
    main()
