#!/usr/bin/env python3
"""Times imutherm.allantools, the drop-in, against AllanTools 2024.6 itself:
the same call on the same arrays in one process, best of --runs interleaved
runs (the drop-in, then AllanTools, then again), after checking that the
deviations agree to 1e-9 relative.

    bench/.venv/bin/python bench/dropin_vs_allantools.py                       # 10^6 and 10^7
    bench/.venv/bin/python bench/dropin_vs_allantools.py --sizes 1e4 --stats mtotdev --runs 1

Rate data ("freq"), white noise seeded by the size, AllanTools' default
octave taus. AllanTools' MTOTDEV, HTOTDEV and Theo1 are Python loops of
minutes at 10^4 (bench/python_vs_allantools.py --expensive caps them).
"""

import argparse
import time

import allantools
import numpy as np

from imutherm import allantools as dropin


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--sizes", default="1e6,1e7")
    p.add_argument("--stats", default="oadev,mdev,hdev,ohdev,totdev")
    p.add_argument("--runs", type=int, default=3)
    a = p.parse_args()
    print(f"{'stat':8} {'samples':>8} {'drop-in [s]':>12} {'AllanTools [s]':>15} {'ratio':>7}")
    for n in (int(float(s)) for s in a.sizes.split(",")):
        y = np.random.default_rng(n).standard_normal(n)
        for stat in a.stats.split(","):
            ours, theirs = getattr(dropin, stat), getattr(allantools, stat)
            mine, want = ours(y, data_type="freq"), theirs(y, data_type="freq")
            np.testing.assert_array_equal(mine[0], want[0])
            np.testing.assert_allclose(mine[1], want[1], rtol=1e-9, atol=0)
            t_ours, t_theirs = [], []
            for _ in range(a.runs):
                t = time.perf_counter()
                ours(y, data_type="freq")
                t_ours.append(time.perf_counter() - t)
                t = time.perf_counter()
                theirs(y, data_type="freq")
                t_theirs.append(time.perf_counter() - t)
            best_ours, best_theirs = min(t_ours), min(t_theirs)
            print(f"{stat:8} {n:8.0e} {best_ours:12.4f} {best_theirs:15.3f} {best_theirs / best_ours:6.1f}x",
                  flush=True)


if __name__ == "__main__":
    main()
