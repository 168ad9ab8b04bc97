"""Kasdin & Walter's discrete power-law noise, under AllanTools 2024.6's
name ``Noise``.

N. J. Kasdin and T. Walter, "Discrete simulation of power law noise",
IEEE Frequency Control Symposium 1992, pp. 274-283 (and Kasdin, "Discrete
simulation of colored noise and stochastic processes and 1/f^alpha power
law noise generation", Proc. IEEE 83, 1995): white noise of variance Q_d
through the filter (1 - z^-1)^(-beta/2) of impulse response
h_0 = 1, h_k = h_{k-1} (beta/2 + k - 1) / k (eq. 13 of the 1992 paper),
applied by FFT convolution over twice the length so that it does not wrap.
The phase PSD is then S_x(f) ~ 2 Q_d tau0 / (2 pi f tau0)^beta at low
frequency, so with b = -beta (the PSD exponent of the phase)

    g_b = 2 Q_d (2 pi)^b tau0^(b + 1),   S_x(f) = g_b f^b,
    h_a = 2 Q_d (2 pi)^a tau0^(a - 1),   S_y(f) = h_a f^a, a = b + 2

(y the fractional frequency, S_y = (2 pi f)^2 S_x).

The Allan and modified Allan variances of power-law noise (IEEE Std
1139-2008 Table B.2, NIST SP 1065 Table 4; MVAR after Bernier 1987 and
Benkler et al. 2015 Table 1; PVAR after Vernotte et al. 2015 Table I) give
the predicted deviations.
"""

import numpy as np

# Euler's constant, in the flicker-PM Allan variance: 3 gamma - ln 2 = 1.038.
_EULER_GAMMA = 0.5772156649015329

_NAMES = {0: "white PM", -1: "flicker PM", -2: "white FM", -3: "flicker FM", -4: "random-walk FM"}


class Noise:
    """Discrete power-law noise: ``nr`` points (a power of two), discrete
    variance ``qd``, phase-PSD exponent ``b`` (0 white PM, -1 flicker PM,
    -2 white FM, -3 flicker FM, -4 random-walk FM).

    >>> n = Noise(nr=2 ** 8, qd=1e-20, b=-1)
    >>> n.generateNoise()
    >>> len(n.time_series)
    256
    """

    def __init__(self, nr=2, qd=1, b=0):
        self.nr = nr
        self.qd = qd
        self.b = b
        self.time_series = np.array([])

    def set_input(self, nr=2, qd=1, b=0):
        """Sets the length, discrete variance and exponent."""
        self.nr = nr
        self.qd = qd
        self.b = b

    def generateNoise(self):
        """Draws ``time_series`` (``nr`` points) from NumPy's global
        generator."""
        n = int(self.nr)
        w = np.zeros(2 * n)
        w[:n] = np.random.normal(0.0, np.sqrt(self.qd), n)
        h = np.zeros(2 * n)
        k = np.arange(1, n)
        h[0] = 1.0
        h[1:n] = np.cumprod((-self.b / 2.0 + k - 1.0) / k)
        self.time_series = np.fft.irfft(np.fft.rfft(w) * np.fft.rfft(h))[:n]

    def phase_psd_from_qd(self, tau0=1.0):
        """g_b of S_x(f) = g_b f^b: 2 Q_d (2 pi)^b tau0^(b + 1)."""
        return 2.0 * self.qd * (2.0 * np.pi) ** self.b * tau0 ** (self.b + 1.0)

    def frequency_psd_from_qd(self, tau0=1.0):
        """h_a of S_y(f) = h_a f^a, a = b + 2: 2 Q_d (2 pi)^a tau0^(a - 1)."""
        a = self.b + 2.0
        return 2.0 * self.qd * (2.0 * np.pi) ** a * tau0 ** (a - 1.0)

    def adev(self, tau0, tau):
        """The Allan deviation the noise has at ``tau`` (seconds)."""
        return np.sqrt(self.adev_from_qd(tau0=tau0, tau=tau) ** 2 * tau ** self.c_avar())

    def mdev(self, tau0, tau):
        """The modified Allan deviation the noise has at ``tau``."""
        return np.sqrt(self.mdev_from_qd(tau0=tau0, tau=tau) ** 2 * tau ** self.c_mvar())

    def _kind(self):
        if self.b not in _NAMES:
            raise ValueError(f"b = {self.b}: expected 0, -1, -2, -3 or -4")
        return self.b

    def c_avar(self):
        """tau exponent of AVAR: 1, 0, -1, -2, -2 for b = -4 ... 0."""
        return {-4: 1.0, -3: 0.0, -2: -1.0, -1: -2.0, 0: -2.0}[self._kind()]

    def c_mvar(self):
        """tau exponent of MVAR: 1, 0, -1, -2, -3 for b = -4 ... 0."""
        return {-4: 1.0, -3: 0.0, -2: -1.0, -1: -2.0, 0: -3.0}[self._kind()]

    def adev_from_qd(self, tau0=1.0, tau=1.0):
        """sqrt(K h_a), with AVAR = K h_a tau^c (NIST SP 1065 Table 4, with
        f_h = 1 / (2 tau0)): white PM 3 f_h / (4 pi^2), flicker PM
        (3 gamma - ln 2 + 3 ln(2 pi f_h tau)) / (4 pi^2), white FM 1/2,
        flicker FM 2 ln 2, random-walk FM 2 pi^2 / 3."""
        f_h = 0.5 / tau0
        k = {0: 3.0 * f_h / (4.0 * np.pi ** 2),
             -1: (3.0 * _EULER_GAMMA - np.log(2.0) + 3.0 * np.log(2.0 * np.pi * f_h * tau))
             / (4.0 * np.pi ** 2),
             -2: 0.5, -3: 2.0 * np.log(2.0), -4: 2.0 * np.pi ** 2 / 3.0}[self._kind()]
        return np.sqrt(k * self.frequency_psd_from_qd(tau0))

    def mdev_from_qd(self, tau0=1.0, tau=1.0):
        """sqrt(K h_a), with MVAR = K h_a tau^c (Benkler et al. 2015,
        Metrologia 52, Table 1): white PM 3 / (8 pi^2), flicker PM
        (24 ln 2 - 9 ln 3) / (8 pi^2), white FM 1/4, flicker FM 27/20 ln 2,
        random-walk FM 11 pi^2 / 20. ``tau`` is unused (AllanTools'
        signature)."""
        k = {0: 3.0 / (8.0 * np.pi ** 2),
             -1: (24.0 * np.log(2.0) - 9.0 * np.log(3.0)) / (8.0 * np.pi ** 2),
             -2: 0.25, -3: 27.0 / 20.0 * np.log(2.0), -4: 11.0 / 20.0 * np.pi ** 2}[self._kind()]
        return np.sqrt(k * self.frequency_psd_from_qd(tau0))

    def pdev_from_qd(self, tau0=1.0, tau=1.0):
        """sqrt(K g_b (2 pi)^2), with PVAR = K g_b (2 pi)^2 tau^c (Vernotte
        et al. 2015, Metrologia 53, Table I): white PM 3 / (2 pi^2), flicker
        PM (3 ln 16 - 1) / (2 pi^2), white FM 3/5, flicker FM
        2 (7 - ln 16) / 5, random-walk FM 26 pi^2 / 35. ``tau`` is unused."""
        k = {0: 3.0 / (2.0 * np.pi ** 2),
             -1: (3.0 * np.log(16.0) - 1.0) / (2.0 * np.pi ** 2),
             -2: 3.0 / 5.0, -3: 2.0 * (7.0 - np.log(16.0)) / 5.0,
             -4: 26.0 / 35.0 * np.pi ** 2}[self._kind()]
        return np.sqrt(k * self.phase_psd_from_qd(tau0) * (2.0 * np.pi) ** 2)
