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
  limited to --cap CPU seconds (600, RLIMIT_CPU), reported as "> 600 s".

The repetitions are interleaved (imutherm, the library, AllanTools, then
again), so a build or test suite sharing the machine slows every tool alike,
and the ratios are of the minima. AllanTools' expensive calls are timed in
CPU seconds of their own process, which load cannot lengthen; imutherm's
are wall-clock, which load can only lengthen: a loaded machine understates
imutherm's speed-up, never overstates it.

AllanTools' expensive calls at 10^5 take up to half an hour; they can run
apart, at the same time as other work, and be fed into the table:

    nice bench/.venv/bin/python bench/python_vs_allantools.py --allantools-only \
        --stats mtotdev --expensive-sizes 1e5 --out at_mtotdev.json &
    ...
    bench/.venv/bin/python bench/python_vs_allantools.py --expensive \
        --allantools-from at_mtotdev.json,at_htotdev.json,at_theo1.json

The arrays of the expensive table are seeded by their size, so both runs
time the same data.

Both tools get the array as float64 rate data ("freq"); where AllanTools
finishes in the parent process, the deviations are checked to agree to
1e-9 relative at every tau both compute before a timing counts.
"""

import argparse
import json
import math
import multiprocessing as mp
import resource
import signal
import time

import allantools
import numpy as np

try:
    import imutherm
    from imutherm import _imutherm
except ImportError:  # --allantools-only needs AllanTools alone
    imutherm = None

SIMPLE = ["oadev", "mdev", "hdev", "ohdev", "totdev"]
EXPENSIVE = ["mtotdev", "htotdev", "theo1"]


def timed(fn):
    start = time.perf_counter()
    result = fn()
    return time.perf_counter() - start, result


def check(stat, mine, theirs, rate):
    by_m = {int(round(t * rate)): d for t, d in zip(theirs[0], theirs[1])}
    common = [(d, by_m[int(m)]) for m, d in zip(mine.m, mine.devs) if int(m) in by_m]
    if not common:
        raise SystemExit(f"{stat}: no tau in common with AllanTools")
    worst = max(abs(a / b - 1) for a, b in common)
    if worst > 1e-9:
        raise SystemExit(f"{stat}: deviations differ by {worst:.2e} relative")


def library_time(stat, y, taus):
    """The Rust library's time on the same array, measured in Rust."""
    return _imutherm.time_library(stat, y, 1.0, taus, "freq", 0.683, 1)


def allantools_child(stat, y, taus, cap, queue):
    # The limit is on this process's CPU time: the kernel sends SIGXCPU at
    # the soft limit, which ends the process.
    limit = math.ceil(cap)
    resource.setrlimit(resource.RLIMIT_CPU, (limit, limit + 5))
    start = time.process_time()
    getattr(allantools, stat)(y, rate=1.0, data_type="freq", taus=taus)
    queue.put(time.process_time() - start)


def capped_allantools(stat, y, taus, cap):
    """AllanTools' CPU seconds in a child process, or None past the cap."""
    ctx = mp.get_context("fork")
    queue = ctx.Queue()
    child = ctx.Process(target=allantools_child, args=(stat, y, taus, cap, queue))
    child.start()
    child.join()
    if child.exitcode != 0:
        if child.exitcode in (-signal.SIGXCPU, -signal.SIGKILL):
            return None
        raise SystemExit(f"AllanTools {stat}: child exited with {child.exitcode}")
    return queue.get()


def simple_table(sizes, taus, runs, rng):
    print(f"\nsimple statistics, taus={taus!r}, best of {runs} interleaved runs "
          f"(AllanTools: {min(runs, 3)})")
    print(f"{'stat':8} {'samples':>9} {'Python s':>10} {'Rust lib s':>11} {'Py/Rust':>8} "
          f"{'AllanTools s':>13} {'speed-up':>9}")
    for n in sizes:
        y = rng.standard_normal(n)
        for stat in SIMPLE:
            mine_ts, lib_ts, theirs_ts = [], [], []
            mine = theirs = None
            for r in range(runs):
                t, mine = timed(lambda: imutherm.analyze(stat, y, taus=taus))
                mine_ts.append(t)
                lib_ts.append(library_time(stat, y, taus))
                if r < 3:
                    t, theirs = timed(lambda: getattr(allantools, stat)(
                        y, rate=1.0, data_type="freq", taus=taus))
                    theirs_ts.append(t)
            check(stat, mine, theirs, 1.0)
            mine_t, lib_t, theirs_t = min(mine_ts), min(lib_ts), min(theirs_ts)
            print(f"{stat:8} {n:9d} {mine_t:10.4f} {lib_t:11.4f} {mine_t / lib_t:7.3f}x "
                  f"{theirs_t:13.4f} {theirs_t / mine_t:8.1f}x", flush=True)


def expensive_array(n):
    return np.random.default_rng(n).standard_normal(n)


def allantools_only(stats, sizes, cap, out):
    """AllanTools' capped CPU seconds alone, for --allantools-from."""
    found = {}
    for n in sizes:
        y = expensive_array(n)
        for stat in stats:
            secs = capped_allantools(stat, y, "octave", cap)
            found.setdefault(stat, {})[str(n)] = {"cpu_s": secs, "cap_s": cap}
            print(f"{stat} {n}: " + (f"> {cap:.0f} s" if secs is None else f"{secs:.3f} s"),
                  flush=True)
    if out:
        with open(out, "w") as f:
            json.dump(found, f, indent=1)


def expensive_table(stats, sizes, runs, cap, known):
    print(f"\nexpensive statistics, octave taus, best of {runs} runs; "
          f"AllanTools: CPU seconds, capped at {cap:.0f}")
    print(f"{'stat':8} {'samples':>9} {'Python s':>10} {'Rust lib s':>11} {'Py/Rust':>8} "
          f"{'AllanTools s':>13} {'speed-up':>9}")
    for n in sizes:
        y = expensive_array(n)
        for stat in stats:
            mine_ts, lib_ts = [], []
            for _ in range(runs):
                mine_ts.append(timed(lambda: imutherm.analyze(stat, y))[0])
                lib_ts.append(library_time(stat, y, "octave"))
            mine_t, lib_t = min(mine_ts), min(lib_ts)
            if str(n) in known.get(stat, {}):
                entry = known[stat][str(n)]
                theirs, their_cap = entry["cpu_s"], entry["cap_s"]
            else:
                theirs, their_cap = capped_allantools(stat, y, "octave", cap), cap
            shown = f"> {their_cap:.0f}" if theirs is None else f"{theirs:.3f}"
            ratio = (f"> {their_cap / mine_t:.0f}" if theirs is None
                     else f"{theirs / mine_t:.0f}") + "x"
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
                    help="CPU seconds AllanTools gets per expensive call")
    ap.add_argument("--stats", default=",".join(EXPENSIVE),
                    help="the expensive statistics to time")
    ap.add_argument("--allantools-only", action="store_true",
                    help="time only AllanTools' expensive calls (no imutherm needed)")
    ap.add_argument("--out", help="with --allantools-only: write the times to this JSON file")
    ap.add_argument("--allantools-from", default="",
                    help="JSON files of --allantools-only whose times the expensive table uses")
    a = ap.parse_args()
    stats = [s.strip() for s in a.stats.split(",") if s.strip()]
    if a.allantools_only:
        allantools_only(stats, counts(a.expensive_sizes), a.cap, a.out)
        return
    if imutherm is None:
        raise SystemExit("imutherm is not installed (pip install ./crates/python)")
    known = {}
    for path in filter(None, a.allantools_from.split(",")):
        with open(path) as f:
            for stat, by_n in json.load(f).items():
                known.setdefault(stat, {}).update(by_n)
    rng = np.random.default_rng(42)
    if not a.expensive or a.all:
        simple_table(counts(a.sizes), "octave", a.runs, rng)
        if counts(a.all_taus_size) and counts(a.all_taus_size)[0] > 0:
            simple_table(counts(a.all_taus_size), "all", a.runs, rng)
    if a.expensive or a.all:
        expensive_table(stats, counts(a.expensive_sizes), a.runs, a.cap, known)


if __name__ == "__main__":
    main()
