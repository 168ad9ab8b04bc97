#!/usr/bin/env python3
"""How many decimated points the lag-1 ACF noise identification reads.

imutherm identifies the noise at each τ by Riley & Greenhall's lag-1
autocorrelation method on at most `allan::noise_id::MAX_ACF_POINTS` points
of the phase decimated by m, the first ones. This study asks whether a cap
of 2^14 points makes the same calls as a cap of 2^17, using AllanTools'
own method (`allantools.autocorr_noise_id`) on AllanTools' own power-law
noise (Kasdin & Walter, `allantools.noise_kasdin`), so that neither side
is imutherm's code:

- on pure power-law noise of every type the Allan and Hadamard families
  identify (α = 2 … −2 with dmax = 2, α = −3 and −4 with dmax = 3), the
  share of seeds where each cap finds the true α, and where the two caps
  agree;
- on two-noise mixtures whose crossover falls inside the factors read,
  the share of seeds where the caps agree at each m, beside how split the
  2^17 call itself is across seeds there (the noise at a crossover is
  neither type);
- the spread of r1 between the caps, against that of the difference of
  two estimates from nested samples, √(1/n_small − 1/n_large);
- the share of each call as a mixture's level sweeps its crossover through
  m = 1: how much wider the smaller cap's transition is.

python3 bench/noise_id_points.py [--seeds 30] [--small 14] [--large 17]

Needs numpy and allantools (2024.6). Prints three tables; exits 1 if the
caps make different calls on a pure noise in any seed.
"""

import argparse
import sys

import numpy as np

import allantools
from allantools import noise_kasdin

FACTORS = (1, 2, 4, 8)


def kasdin(n, alpha, seed, qd=1.0):
    """n phase points of power-law rate noise S_y ∝ f^alpha (phase
    exponent b = alpha − 2), from AllanTools' generator."""
    np.random.seed(seed)
    noise = noise_kasdin.Noise(nr=n, qd=qd, b=alpha - 2)
    noise.generateNoise()
    return noise.time_series


def identify(x, m, points, dmax):
    """AllanTools' lag-1 ACF call on the first `points` points of x
    decimated by m: (alpha_int, r1)."""
    alpha_int, _alpha, _d, rho = allantools.autocorr_noise_id(
        x[: points * m], m, data_type="phase", dmin=0, dmax=dmax
    )
    # rho is δ = r1/(1 + r1); r1 = δ/(1 − δ).
    return alpha_int, rho / (1.0 - rho)


def mixture(n, parts, seed):
    """Sum of Kasdin noises [(alpha, qd)], each from its own seed."""
    return sum(kasdin(n, alpha, seed * 7919 + k, qd) for k, (alpha, qd) in enumerate(parts))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=30)
    ap.add_argument("--small", type=int, default=14, help="log2 of the smaller cap")
    ap.add_argument("--large", type=int, default=17, help="log2 of the larger cap")
    args = ap.parse_args()
    small, large = 1 << args.small, 1 << args.large
    n = large * max(FACTORS)

    print(f"# lag-1 ACF calls on the first 2^{args.small} against the first 2^{args.large}")
    print(f"# decimated points, AllanTools {allantools.__version__} (autocorr_noise_id,")
    print(f"# noise_kasdin), {args.seeds} seeds, {n} phase points, m = {FACTORS}")
    print()
    print("## pure power-law noise")
    print("alpha dmax    m  small=true  large=true  agree  calls   sd(r1 small-large)  sqrt(1/small-1/large)")
    differ = False
    pure = [(a, 2) for a in (2, 1, 0, -1, -2)] + [(a, 3) for a in (-3, -4)]
    for alpha, dmax in pure:
        series = [kasdin(n, alpha, seed) for seed in range(args.seeds)]
        for m in FACTORS:
            calls = [(identify(x, m, small, dmax), identify(x, m, large, dmax)) for x in series]
            hit_small = sum(s[0] == alpha for s, _ in calls)
            hit_large = sum(b[0] == alpha for _, b in calls)
            agree = sum(s[0] == b[0] for s, b in calls)
            spread = np.std([s[1] - b[1] for s, b in calls])
            differ |= agree < args.seeds
            found = sorted({b[0] for _, b in calls} | {s[0] for s, _ in calls})
            print(
                f"{alpha:5d} {dmax:4d} {m:4d} {hit_small:6d}/{args.seeds:<4d}"
                f" {hit_large:6d}/{args.seeds:<4d} {agree:3d}/{args.seeds:<3d}"
                f" {str(found):8s} {spread:14.4f} {np.sqrt(1 / small - 1 / large):14.4f}"
            )
    print()
    print("## two-noise mixtures (the crossover between the factors read)")
    print("mixture                          m  agree  modal share small / large, calls")
    # Levels chosen so that the two noises' Allan variances cross near
    # m = 3: 3·qd₁/τ² = qd₂/τ, qd₁/τ = qd₂·τ/3 and 0.44·qd₁ = qd₂·τ/3 (the white
    # PM, white FM, flicker FM and random-walk FM Allan variances of
    # Kasdin noise of discrete variance qd).
    mixtures = [
        ("white PM + white FM", [(2, 1.0), (0, 1.0)]),
        ("white FM + random-walk FM", [(0, 1.0), (-2, 0.33)]),
        ("flicker FM + random-walk FM", [(-1, 1.0), (-2, 0.44)]),
    ]
    for name, parts in mixtures:
        series = [mixture(n, parts, seed) for seed in range(args.seeds)]
        for m in FACTORS:
            calls = [(identify(x, m, small, 2)[0], identify(x, m, large, 2)[0]) for x in series]
            agree = sum(s == b for s, b in calls)
            shares = []
            for side in (0, 1):
                side_calls = [c[side] for c in calls]
                modal = max(set(side_calls), key=side_calls.count)
                shares.append(f"{side_calls.count(modal) / len(side_calls):4.2f} (α {modal:2d})")
            found = sorted({c for pair in calls for c in pair})
            print(f"{name:30s} {m:4d} {agree:3d}/{args.seeds:<3d}  {' / '.join(shares)}, {found}")
    print()
    print("## across a crossover: white FM + random-walk FM of level q at m = 1")
    print("q        share of calls alpha = 0, small / large")
    # The two noises generated once per seed at unit level and summed at
    # each q, so that every row sees the same draws.
    wfm = [kasdin(large, 0, 10_000 + seed) for seed in range(args.seeds)]
    rwfm = [kasdin(large, -2, 20_000 + seed) for seed in range(args.seeds)]
    for q in np.geomspace(0.1, 1.0, 16):
        calls = [
            (identify(w + np.sqrt(q) * r, 1, small, 2)[0], identify(w + np.sqrt(q) * r, 1, large, 2)[0])
            for w, r in zip(wfm, rwfm)
        ]
        share = [sum(c[side] == 0 for c in calls) / len(calls) for side in (0, 1)]
        print(f"{q:7.4f}  {share[0]:4.2f} / {share[1]:4.2f}")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
