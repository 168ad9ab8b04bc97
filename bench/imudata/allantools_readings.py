"""AllanTools' readings of one converted ADIS16405 recording
(convert.py's gzip CSV): for each axis, the overlapping ADEV at τ = 1 s
and the log-log slope there (from τ = 0.5 s to 2 s), and the minimum of
the octave curve with its τ, the numbers allan_variance_ros, imu_utils
and the thesis read N and B from (N = σ(1 s) on a −½ slope,
B = σ_min/0.664). Units as the file's header (°/s, g).

usage: allantools_readings.py RATE_HZ FILE.csv.gz
Prints one tab-separated line per axis:
file axis sigma_1s slope_1s sigma_min tau_min neighbour/sigma_min
"""

import contextlib
import gzip
import math
import os
import sys

import allantools
import numpy as np


def main(rate: float, path: str) -> None:
    with gzip.open(path, "rt") as f:
        header = f.readline().strip().split(",")
        data = np.loadtxt(f, delimiter=",")
    name = os.path.basename(path)
    for j, col in enumerate(header):
        y = data[:, j]
        with contextlib.redirect_stdout(sys.stderr):
            t3, d3, _, _ = allantools.oadev(y, rate=rate, data_type="freq", taus=[0.5, 1.0, 2.0])
            to, do, _, _ = allantools.oadev(y, rate=rate, data_type="freq", taus="octave")
        slope = math.log(d3[2] / d3[0]) / math.log(t3[2] / t3[0])
        k = int(np.argmin(do))
        # How flat the minimum is: the larger of its octave neighbours over
        # it (inf where the minimum is an end of the curve).
        flat = max(do[k - 1], do[k + 1]) / do[k] if 0 < k < len(do) - 1 else float("inf")
        axis = col.split("[")[0]
        print(f"{name}\t{axis}\t{d3[1]:.6e}\t{slope:.3f}\t{do[k]:.6e}\t{to[k]:.4g}\t{flat:.3f}")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(float(sys.argv[1]), sys.argv[2])
