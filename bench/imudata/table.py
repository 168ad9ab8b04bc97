#!/usr/bin/env python3
"""The 36-axis table of bench/README.md from imutherm's terms and AllanTools' readings.

    table.py TERMS.tsv ALLANTOOLS.tsv

TERMS.tsv: what `imudata_check` writes with IMUDATA_TERMS=FILE (file, axis, N's
status, N, its interval, B's status, B, its interval, the model, whether it
describes the curve, the fit range, ...). ALLANTOOLS.tsv: the lines of
`allantools_readings.py` (file, axis, σ(1 s), the slope at 1 s, the octave
minimum, its τ, the larger neighbour over the minimum or "end"), in the
data's own units (°/s and g), taken to SI here (π/180, 9.80665 m/s²) as
imutherm reads them.

Prints the Markdown table, then the counts the acceptance reads: N a value,
within 10 % of σ(1 s) where the slope at 1 s is −½ (−0.45 to −0.55), and B a
value within 30 % of σ_min/0.664 on the axes with a flat interior minimum
(the larger neighbour within 10 % of the minimum).
"""

import math
import sys

G = 9.80665
AXES = {"gyro_x": "gyro_x", "gyro_y": "gyro_y", "gyro_z": "gyro_z",
        "acc_x": "accel_x", "acc_y": "accel_y", "acc_z": "accel_z"}


def rows(path):
    with open(path) as f:
        return [line.rstrip("\n").split("\t") for line in f if line.strip()]


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    terms = {(r[0], r[1]): r for r in rows(sys.argv[1])}
    readings = {}
    for r in rows(sys.argv[2]):
        axis = AXES.get(r[1], r[1])
        scale = math.pi / 180 if axis.startswith("gyro") else G
        readings[(r[0], axis)] = {
            "s1": float(r[2]) * scale, "slope": float(r[3]),
            "smin": float(r[4]) * scale, "tmin": r[5], "nb": r[6],
        }
    print("| run | axis | model (τ range, s) | N | AllanTools σ(1 s), slope | N/σ(1 s) "
          "| B | AllanTools σ_min/0.664 (τ_min, neighbour/σ_min) | B/(σ_min/0.664) |")
    print("|---|---|---|---|---|---|---|---|---|")
    n_value = n_white = n_within = flat = b_value = b_within = 0
    for key in sorted(terms, key=lambda k: (k[0], list(AXES.values()).index(k[1]))):
        t = terms[key]
        a = readings.get(key)
        if a is None:
            sys.exit(f"{sys.argv[2]}: no reading for {key[0]} {key[1]}")
        n_is, n = t[2] == "value", float(t[3])
        b_is, b = t[6] == "value", float(t[7])
        white = abs(a["slope"] + 0.5) <= 0.05
        is_flat = a["nb"] != "end" and float(a["nb"]) <= 1.10
        b_ref = a["smin"] / 0.664
        n_value += n_is
        n_white += white
        n_within += n_is and white and abs(n / a["s1"] - 1) <= 0.10
        flat += is_flat
        b_value += is_flat and b_is
        b_within += is_flat and b_is and abs(b / b_ref - 1) <= 0.30
        nb = "end" if a["nb"] == "end" else f"{float(a['nb']):.2f}"
        n_ratio = f"{n / a['s1']:.3f}" if n_is else "—"
        b_ratio = f"{b / b_ref:.2f}" if b_is else "—"
        print(f"| {key[0].split('.')[0]} | {key[1]} | {t[10]} ({t[12]}) "
              f"| {'' if n_is else '≤ '}{n:.3e} | {a['s1']:.3e}, {a['slope']:.2f} "
              f"| {n_ratio} "
              f"| {'' if b_is else '≤ '}{b:.3e} "
              f"| {b_ref:.3e} ({a['tmin']} s, {nb}) | {b_ratio} |")
    print()
    print(f"N a value on {n_value} of {len(terms)} axes; slope −½ at 1 s on {n_white}, "
          f"of which N a value within 10 % of σ(1 s) on {n_within}.")
    print(f"Flat interior minimum on {flat} axes: B a value on {b_value}, "
          f"within 30 % of σ_min/0.664 on {b_within}.")


if __name__ == "__main__":
    main()
