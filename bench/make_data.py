#!/usr/bin/env python3
"""Writes the benchmark input: N samples of a synthetic gyro axis, one value per line.

    make_data.py N PATH

The series is white rate noise (angle random walk) of 1e-3 rad/s per sample on a
0.0123 rad/s bias, plus a slow random walk of the bias (rate random walk) of
2e-7 rad/s per sample: the shape of an MPU-9250-class gyro at 100 Hz, so both
tools see realistic magnitudes. The generator is seeded; the same N always gives
the same file, byte for byte.

Values are written with 7 decimals (0.1 urad/s, far below the noise), which keeps
a 10^7-sample file near 100 MB. The file appears under its final name only once
it is complete, so an interrupted run never leaves a truncated file to be reused.
"""
import os
import sys

import numpy as np

SEED = 20240601
BIAS = 0.0123
WHITE = 1.0e-3
RANDOM_WALK = 2.0e-7
# Bounded memory for 10^7 samples and more.
CHUNK = 1_000_000


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    n = int(float(sys.argv[1]))
    path = sys.argv[2]
    # Independent streams, so changing one noise term leaves the other unchanged.
    white_ss, walk_ss = np.random.SeedSequence(SEED).spawn(2)
    white_rng, walk_rng = np.random.default_rng(white_ss), np.random.default_rng(walk_ss)

    tmp = path + ".partial"
    walk = 0.0
    with open(tmp, "w") as f:
        for start in range(0, n, CHUNK):
            k = min(CHUNK, n - start)
            steps = np.cumsum(walk_rng.standard_normal(k)) * RANDOM_WALK + walk
            walk = steps[-1]
            y = BIAS + WHITE * white_rng.standard_normal(k) + steps
            f.write("\n".join(map("{:.7f}".format, y)))
            f.write("\n")
    os.replace(tmp, path)


if __name__ == "__main__":
    main()
