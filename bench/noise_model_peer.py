"""The noise model against a peer on the same records.

The peer is `avar` (PyPI, MIT; its `fit` class): the Allan variance curve fitted
by a sum of processes whose set the user chooses (quantization, white noise,
first-order Gauss-Markov with its time constant given, Brownian, ramp), the
magnitudes optimised by `scipy.optimize.leastsq` on log10 of the curve, as its
"o" key does. It selects no model and has no flicker term, so it is given the
true set of processes of each case (and the true Gauss-Markov T), which
favours it; the N+B+K case has no counterpart.

    cargo run --release -p imusim --example noise_model_study -- 20 --dump DIR
    python bench/noise_model_peer.py DIR

needs numpy, scipy, matplotlib and avar==1.0.4. Prints per case and term the
median relative error against the truth of imutherm's selected model and of
avar's fit on the same octave curve (avar.variance at m = 1, 2, 4, ... up to a
quarter of the record, as imutherm's octave OADEV), their ratio, and the seeds
whose model holds the term.
"""

import argparse
import contextlib
import io
import os
import sys

import matplotlib

matplotlib.use("Agg")
import avar  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.backend_bases import KeyEvent  # noqa: E402

NAMES = ["Q", "N", "B", "K", "GM σ", "GM T"]

# The cases of bench/noise_model_cases.rs, by index: the truth (in NAMES'
# order) and avar's components (slope, variance, [T]) of the true model.
CASES = {
    0: ("N+K 4 h", [0, 1.5e-4, 0, 2e-6, 0, 0], [(-1,), (1,)]),
    2: ("N+GM(100 s) 4 h", [0, 1.5e-4, 0, 0, 1e-4, 100.0], [(-1,), (0, 100.0)]),
    3: ("Q+N 10 min", [2e-4, 1.5e-4, 0, 0, 0, 0], [(-2,), (-1,)]),
}

# Which of NAMES each avar slope gives, and how its variance becomes the term.
TERM_OF_SLOPE = {-2: 0, -1: 1, 1: 3, 0: 4}


def octave_curve(y, rate_hz):
    top = (len(y) + 1) // 4
    m = 2 ** np.arange(int(np.log2(top)) + 1)
    m = m[m <= top]
    # avar.variance prints its progress.
    with contextlib.redirect_stdout(io.StringIO()):
        va = avar.variance(y, m)
    return m / rate_hz, va


def peer_fit(tau, va, rate_hz, comps):
    """avar's own optimiser on the given components, started as large as the
    curve allows shared among them (a user placing them by eye)."""
    shapes = {-2: 3 / tau**2, -1: 1 / tau, 1: tau / 3, 2: tau**2 / 2}
    ks = []
    for c in comps:
        if c[0] == 0:
            t = c[1]
            ks.append([0, float(np.min(va)) / len(comps), t])
        else:
            ks.append([c[0], float(np.min(va / shapes[c[0]])) / len(comps)])
    f = avar.fit(tau, va, T=1.0 / rate_hz, ks=ks)
    f.on_key_press(KeyEvent("key_press_event", f.ax.figure.canvas, key="o"))
    plt.close(f.ax.figure)
    out = [None] * 6
    for k in f.ks:
        slot = TERM_OF_SLOPE.get(int(k[0]))
        if slot is not None:
            out[slot] = float(np.sqrt(k[1]))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dir", help="the study's --dump directory")
    args = ap.parse_args()
    rows = [line.rstrip("\n").split("\t") for line in open(os.path.join(args.dir, "imutherm.tsv"))]
    for index, (name, truth, comps) in CASES.items():
        ours, theirs = {k: [] for k in range(6)}, {k: [] for k in range(6)}
        held = {k: 0 for k in range(6)}
        seeds = [r for r in rows[1:] if int(r[0]) == index]
        for r in seeds:
            seed, rate = int(r[1]), float(r[2])
            y = np.fromfile(os.path.join(args.dir, f"{index}_{seed}.f64"), dtype="<f8")
            tau, va = octave_curve(y, rate)
            peer = peer_fit(tau, va, rate, comps)
            for k in range(6):
                if truth[k] == 0 or peer[k] is None:
                    continue
                mine = None if r[3 + k] == "-" else float(r[3 + k])
                if mine is not None:
                    held[k] += 1
                    ours[k].append(abs(mine / truth[k] - 1))
                theirs[k].append(abs(peer[k] / truth[k] - 1))
        print(f"## {name} ({len(seeds)} seeds)")
        print("| term | imutherm median |error| (seeds holding it) | avar median |error| | ratio |")
        print("| --- | --- | --- | --- |")
        for k in range(6):
            if not theirs[k]:
                continue
            a = float(np.median(ours[k])) if ours[k] else float("nan")
            b = float(np.median(theirs[k]))
            print(f"| {NAMES[k]} | {100 * a:.2f} % ({held[k]}) | {100 * b:.2f} % | {a / b:.2f} |")
        print()
    return 0


if __name__ == "__main__":
    sys.exit(main())
