"""Power-law noise generators and PSD estimates, under AllanTools 2024.6's
names. The one-sided PSD coefficients follow from the sampling: white noise
of variance s^2 at rate fs has the one-sided PSD 2 s^2 / fs, integration
divides the PSD by (2 pi f)^2 and differentiation multiplies it by that
(NIST SP 1065 sec. 8). The draws use NumPy's global generator
(``numpy.random.seed`` makes them repeatable), as AllanTools' do."""

import math

import numpy as np


def numpy_psd(x, f_sample=1.0):
    """One-sided PSD of ``x`` by the periodogram, 2 |FFT(x)|^2 / (N fs), at
    frequencies 0 ... fs / 2. Returns ``(f, psd)``."""
    psd = 2.0 / (len(x) * f_sample) * np.abs(np.fft.rfft(x)) ** 2
    return np.linspace(0.0, f_sample / 2.0, len(psd)), psd


def scipy_psd(x, f_sample=1.0, nr_segments=4):
    """One-sided PSD of ``x`` by Welch's method over ``nr_segments``
    segments (SciPy's ``welch``). Returns ``(f, psd)``."""
    try:
        from scipy import signal
    except ImportError as e:
        raise ImportError("scipy_psd needs SciPy: pip install scipy") from e
    return signal.welch(x, f_sample, nperseg=int(len(x) / nr_segments))


def white(num_points=1024, b0=1.0, fs=1.0):
    """White noise with one-sided PSD ``b0`` at sample rate ``fs``: normal
    samples of variance b0 fs / 2."""
    return math.sqrt(b0 * fs / 2.0) * np.random.randn(num_points)


def brown(num_points=1024, b_minus2=1.0, fs=1.0):
    """Brownian (random-walk) noise, PSD ``b_minus2`` / f^2: white noise of
    PSD 4 pi^2 b_minus2 integrated (summed, times 1 / fs)."""
    return np.cumsum(white(num_points, b0=b_minus2 * 4.0 * math.pi ** 2, fs=fs)) / float(fs)


def violet(num_points=1024, b2=1, fs=1):
    """Violet noise, PSD ``b2`` f^2: white noise of PSD b2 / (2 pi)^2
    differentiated (differenced, times fs)."""
    return float(fs) * np.diff(white(num_points + 1, b0=b2 / (2.0 * math.pi) ** 2, fs=fs))


def pink(num_points=1024, depth=80):
    """Pink (1/f) noise by the Voss-McCartney algorithm (:func:`iterpink`),
    ``num_points`` samples from ``depth`` rows. Unnormalised, as in
    AllanTools."""
    s = iterpink(depth)
    return np.array([next(s) for _ in range(num_points)])


def iterpink(depth=20):
    """An endless 1/f sequence (Voss's algorithm with McCartney's trailing-zero
    row choice, Gardner 1978, "White and brown music, fractal curves and
    one-over-f fluctuations", Sci. Am. 238): ``depth`` random rows, row k
    redrawn every 2^(k+1) samples, plus a fresh white term each sample; the
    output is their sum."""
    rows = np.random.randn(depth)
    total = rows.sum()
    fresh = np.random.randn(depth)
    draws = np.random.randn(depth)
    i = 0
    while True:
        yield total + fresh[i]
        i += 1
        if i == depth:
            # A new block of draws; the rows carry on.
            i = 0
            fresh = np.random.randn(depth)
            draws = np.random.randn(depth)
            continue
        row = (i & -i).bit_length() - 1  # trailing zeros of i
        total += draws[i] - rows[row]
        rows[row] = draws[i]
