#!/usr/bin/env python3
"""Checks that imutherm and AllanTools computed the same OADEV.

    compare_outputs.py IMUTHERM_JSON ALLANTOOLS_JSON RATE

Compares at the taus both report: imutherm stops at Stable32's stop ratio
(m <= N/4 for OADEV) while AllanTools goes on to m < N, so the intersection is
imutherm's grid. Every imutherm tau must be one AllanTools reports, the number
of terms n must be equal and the deviations must agree to 1e-9 relative: both
compute the same sums, so anything more than rounding is a real difference.

Prints one line of verdict and exits 1 on disagreement.
"""
import json
import sys

RTOL = 1e-9


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    with open(sys.argv[1]) as f:
        imu = json.load(f)
    with open(sys.argv[2]) as f:
        at = json.load(f)
    rate = float(sys.argv[3])

    points = imu["channels"][0]["points"]
    # Match on the averaging factor m = tau * rate, an integer in both tools,
    # rather than on floating-point taus.
    ref = {int(round(t * rate)): (d, n) for t, d, n in zip(at["taus"], at["devs"], at["ns"])}

    problems = []
    worst = 0.0
    for p in points:
        m = int(p["m"])
        if m not in ref:
            problems.append("tau %g (m=%d) not reported by AllanTools" % (p["tau"], m))
            continue
        dev, n = ref[m]
        rel = abs(p["dev"] - dev) / abs(dev) if dev != 0 else abs(p["dev"])
        worst = max(worst, rel)
        if not rel < RTOL:
            problems.append("tau %g: imutherm %.17g, AllanTools %.17g (rel diff %.2e)"
                            % (p["tau"], p["dev"], dev, rel))
        if int(p["n"]) != n:
            problems.append("tau %g: n %d vs AllanTools %d" % (p["tau"], p["n"], n))

    if not points:
        problems.append("imutherm reported no points")
    if problems:
        print("  outputs DISAGREE (%d taus compared):" % len(points))
        for line in problems:
            print("    " + line)
        sys.exit(1)
    print("  outputs agree: %d taus (m = %d..%d), max relative difference %.1e < %.0e, n equal"
          % (len(points), points[0]["m"], points[-1]["m"], worst, RTOL))


if __name__ == "__main__":
    main()
