"""Seeded power-law noise shared by the tests."""

import numpy as np
import pytest


def power_law(rng, n, exponent):
    """n samples of noise with PSD proportional to f**(-exponent): white noise
    through the fractional-integration filter of Kasdin & Walter (1992),
    h_k = h_{k-1} (exponent/2 + k - 1) / k, applied by FFT convolution."""
    h = np.empty(n)
    h[0] = 1.0
    for k in range(1, n):
        h[k] = h[k - 1] * (exponent / 2.0 + k - 1.0) / k
    w = rng.standard_normal(n)
    size = 2 * n
    return np.fft.irfft(np.fft.rfft(h, size) * np.fft.rfft(w, size), size)[:n]


#: Rate (frequency) data: white, flicker and random-walk FM, with a gyro-like
#: bias several times the noise, as an IMU gives them.
RATE_NOISES = {"white FM": 0.0, "flicker FM": 1.0, "random-walk FM": 2.0}


@pytest.fixture(params=sorted(RATE_NOISES))
def rate_noise(request):
    rng = np.random.default_rng(1000 + sorted(RATE_NOISES).index(request.param))
    return 5e-3 + 1e-3 * power_law(rng, 1024, RATE_NOISES[request.param])


@pytest.fixture
def phase_noise():
    """Flicker PM: phase data."""
    return 1e-9 * power_law(np.random.default_rng(7), 1024, 1.0)
