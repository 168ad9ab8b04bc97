#!/usr/bin/env python3
"""The AllanTools side of the benchmark: what a user of AllanTools 2024.6 would write.

    allantools_oadev.py FILE [RATE [TAUS]] > out.json

Reads a one-column text file with pandas, computes the overlapping Allan
deviation of the rate (frequency) data at TAUS (AllanTools' own names:
octave, the default, or all, decade, many), and prints JSON:
{"taus": [...], "devs": [...], "ns": [...], "samples": N,
 "read_seconds": ..., "compute_seconds": ...}.
The two inner timings show where AllanTools' time goes; the benchmark itself
times the whole process, interpreter start-up and imports included, just as it
does for imutherm.
"""
import contextlib
import json
import sys
import time

import allantools
import pandas as pd


def main():
    if len(sys.argv) not in (2, 3, 4):
        sys.exit(__doc__)
    path = sys.argv[1]
    rate = float(sys.argv[2]) if len(sys.argv) >= 3 else 100.0
    tau_grid = sys.argv[3] if len(sys.argv) == 4 else "octave"

    t0 = time.perf_counter()
    data = pd.read_csv(path, header=None).iloc[:, 0].to_numpy()
    t1 = time.perf_counter()
    # AllanTools reports some conditions with print(); keep stdout pure JSON.
    with contextlib.redirect_stdout(sys.stderr):
        taus, devs, _errs, ns = allantools.oadev(data, rate=rate, data_type="freq", taus=tau_grid)
    t2 = time.perf_counter()

    json.dump({
        "taus": [float(t) for t in taus],
        "devs": [float(d) for d in devs],
        "ns": [int(n) for n in ns],
        "samples": int(len(data)),
        "read_seconds": t1 - t0,
        "compute_seconds": t2 - t1,
    }, sys.stdout)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
