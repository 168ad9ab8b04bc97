"""Noise identification against AllanTools 2024.6's own lag-1 ACF method
(`autocorr_noise_id`, dmin = 0) on AllanTools' own power-law noise (Kasdin
& Walter, `noise_kasdin`). imutherm reads the first 2^14 decimated points
at each factor (`allan::noise_id::MAX_ACF_POINTS`); AllanTools reads them
all, from 2^17 at m = 1 down to 2^15 at m = 4. The calls agree on every
noise type the Allan family identifies, flicker included
(`bench/noise_id_points.py` studies the cap at length)."""

import allantools
import numpy as np
import pytest
from allantools import noise_kasdin

import imutherm

N = 1 << 17
FACTORS = [1, 2, 4]


def kasdin_phase(alpha, seed):
    """Phase data of rate noise S_y ∝ f^alpha (phase exponent alpha − 2)."""
    np.random.seed(seed)
    noise = noise_kasdin.Noise(nr=N, qd=1e-18, b=alpha - 2)
    noise.generateNoise()
    return noise.time_series


@pytest.mark.parametrize("alpha", [2, 1, 0, -1, -2])
@pytest.mark.parametrize("seed", [1, 2])
def test_first_points_make_allantools_call_on_all_points(alpha, seed):
    x = kasdin_phase(alpha, 100 * seed + alpha)
    curve = imutherm.oadev(x, rate=1.0, taus=FACTORS, data_type="phase")
    assert list(curve.m) == FACTORS
    for m, got, method in zip(curve.m, curve.alpha, curve.noise_id):
        want = allantools.autocorr_noise_id(x, int(m), data_type="phase", dmin=0, dmax=2)[0]
        assert (int(got), method) == (want, "acf"), (alpha, int(m))
        assert want == alpha, (alpha, int(m))
