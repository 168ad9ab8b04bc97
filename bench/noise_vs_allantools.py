"""CPU time of AllanTools' octave OADEV of each inertial channel of a log,
the curve `imutherm noise` fits its noise model to, for bench/README.md's
table of the noise model's cost.

    PY=target/atvenv/bin/python   # AllanTools 2024.6, NumPy
    $PY bench/noise_vs_allantools.py imutherm-demo/run_34C.txt

Prints one line per channel and the total, in CPU seconds of this process
(time.process_time), reading excluded: AllanTools computes the curve only,
with no noise model, so its time is a floor under any tool that fits one.
"""

import sys
import time

import allantools
import numpy as np


def columns(path):
    rate, header, rows = None, None, []
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                if line.startswith("# sample_rate_hz:"):
                    rate = float(line.split(":", 1)[1])
                continue
            if header is None:
                header = [h.strip().split("[")[0] for h in line.split(",")]
                continue
            rows.append([float(v) for v in line.split(",")])
    data = np.array(rows)
    return rate, {h: data[:, k] for k, h in enumerate(header) if not h.startswith("temp")}


def main():
    rate, chans = columns(sys.argv[1])
    total = 0.0
    for name, x in chans.items():
        start = time.process_time()
        allantools.oadev(x, rate=rate, data_type="freq", taus="octave")
        spent = time.process_time() - start
        total += spent
        print(f"{name:<14} {1e3 * spent:8.1f} ms")
    print(f"{'total':<14} {1e3 * total:8.1f} ms ({len(chans)} curves of {len(x)} samples at {rate} Hz)")


if __name__ == "__main__":
    main()
