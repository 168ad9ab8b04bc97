"""Deviations updated sample by sample, under AllanTools 2024.6's names:
OADEV, OHDEV and TDEV by the recursive sums of Dobrogowski & Kasznia, "Real
time assessment of Allan deviation and time deviation", IEEE ISPCS 2007
(their eqs. 9 for OADEV and 11-14 for TDEV; OHDEV is the same recursion on
third differences). Each new phase point adds one term per averaging factor:
O(number of factors) per sample, the phase kept for the differences."""

import numpy as np


class dev_realtime:
    """The bookkeeping shared by the real-time deviations: the phase ``x``
    (seconds), the averaging factors ``afs`` (tau = af * ``tau0``) and the
    deviations ``dev``. With ``auto_afs`` the factors start at 1 and a new
    one (``pts_per_decade`` per decade, log-spaced) is added as soon as the
    phase is long enough for it."""

    def __init__(self, afs=[1], tau0=1.0, auto_afs=False, pts_per_decade=4):  # noqa: B006  (AllanTools' signature)
        self.x = []
        self.afs = np.array([1]) if auto_afs else afs
        self.auto_afs = auto_afs
        # One decade of factors, 10^(k / pts_per_decade), k = 0 ... pts - 1.
        self.af_taus = np.logspace(0, 1, pts_per_decade + 1)[:-1]
        self.af_idx = 0
        self.af_decade = 0
        self.dev = np.zeros(len(self.afs))
        self.tau0 = tau0

    def update_af(self):
        """Adds the next factor of the log grid once 2 af + 1 points exist."""
        idx, decade = self.af_idx + 1, self.af_decade
        if idx == len(self.af_taus):
            idx, decade = 0, decade + 1
        af = int(np.round(10.0 ** decade * self.af_taus[idx]))
        if len(self.x) >= 2 * af + 1:
            self.afs = np.append(self.afs, af)
            self.add_af()
            self.dev = np.append(self.dev, 0.0)
            self.af_idx, self.af_decade = idx, decade

    def add_frequency(self, f):
        """Adds a fractional-frequency sample: the phase integrates it (the
        first one starts the phase at 0)."""
        if not self.x:
            self.add_phase(0)
        self.add_phase(self.x[-1] + f)

    def add_phase(self, xnew):
        raise NotImplementedError("dev_realtime is the base class: use oadev_realtime, "
                                  "ohdev_realtime or tdev_realtime")

    def taus(self):
        """The taus in seconds."""
        return self.tau0 * np.array(self.afs)

    def add_af(self):
        """Makes room for a new factor in the subclass's sums."""

    def devs(self):
        """The deviations at :meth:`taus`."""
        return self.dev


class _overlapped_realtime(dev_realtime):
    """An overlapping deviation of a stream on the differences of order
    ``span - 1``: S accumulates each new difference squared and the
    deviation is sqrt(S / (norm (m tau0)^2 (N - span m)))."""

    span = 0
    norm = 0.0

    def __init__(self, afs=[1], tau0=1.0, auto_afs=False, pts_per_decade=4):  # noqa: B006
        super().__init__(afs=afs, tau0=tau0, auto_afs=auto_afs, pts_per_decade=pts_per_decade)
        self.S = np.zeros(len(self.afs))

    def add_phase(self, xnew):
        """Adds a phase sample (seconds)."""
        self.x.append(xnew)
        for idx, af in enumerate(self.afs):
            if len(self.x) >= self.span * af + 1:
                self.update_S(idx)
        if self.auto_afs:
            self.update_af()

    def difference(self, i, af):
        """The difference that ends at sample ``i``, at factor ``af``."""
        raise NotImplementedError

    def update_S(self, idx):
        af = int(self.afs[idx])
        i = len(self.x) - 1
        self.S[idx] += self.difference(i, af) ** 2
        terms = i + 1 - self.span * af
        self.dev[idx] = np.sqrt(self.S[idx] / (self.norm * (af * self.tau0) ** 2 * terms))

    def add_af(self):
        self.S = np.append(self.S, 0.0)


class oadev_realtime(_overlapped_realtime):
    """Overlapping Allan deviation of a stream (Dobrogowski & Kasznia 2007,
    eq. 9): S accumulates (x_i - 2 x_{i-m} + x_{i-2m})^2 and
    OADEV = sqrt(S / (2 (m tau0)^2 (N - 2m)))."""

    span = 2
    norm = 2.0

    def difference(self, i, af):
        x = self.x
        return x[i] - 2 * x[i - af] + x[i - 2 * af]


class ohdev_realtime(_overlapped_realtime):
    """Overlapping Hadamard deviation of a stream: S accumulates the third
    differences (x_i - 3 x_{i-m} + 3 x_{i-2m} - x_{i-3m})^2 and
    OHDEV = sqrt(S / (6 (m tau0)^2 (N - 3m))) (NIST SP 1065 eq. 20)."""

    span = 3
    norm = 6.0

    def difference(self, i, af):
        x = self.x
        return x[i] - 3 * x[i - af] + 3 * x[i - 2 * af] - x[i - 3 * af]


class tdev_realtime(dev_realtime):
    """Time deviation of a stream (Dobrogowski & Kasznia 2007, eqs. 11-14):
    W, the sum of the m second differences of a window, moves by
    x_{i} - 3 x_{i-m} + 3 x_{i-2m} - x_{i-3m} per sample; So accumulates W^2
    and TDEV = sqrt(So / (6 m^2 (N - 3m + 1)))."""

    def __init__(self, afs=[1], tau0=1.0, auto_afs=False, pts_per_decade=4):  # noqa: B006
        super().__init__(afs=afs, tau0=tau0, auto_afs=auto_afs, pts_per_decade=pts_per_decade)
        self.S = np.zeros(len(self.afs))
        self.So = np.zeros(len(self.afs))

    def add_phase(self, xnew):
        """Adds a phase sample (seconds)."""
        self.x.append(xnew)
        for idx, af in enumerate(self.afs):
            if len(self.x) >= 3 * af + 1:
                self.update_S(idx)
            elif len(self.x) >= 2 * af + 1:
                self.update_S3n(idx)
        if self.auto_afs:
            self.update_af()

    def add_af(self):
        self.S = np.append(self.S, 0.0)
        self.So = np.append(self.So, 0.0)

    def update_S3n(self, idx):
        """The first window's sum, one second difference at a time; complete
        (and its square the first term) at 3m points (eq. 13)."""
        af = int(self.afs[idx])
        x, j = self.x, len(self.x) - 1
        self.S[idx] += x[j] - 2 * x[j - af] + x[j - 2 * af]
        if len(self.x) == 3 * af:
            self.So[idx] = self.S[idx] ** 2
            self.update_dev(idx)

    def update_dev(self, idx):
        """TDEV from So (eq. 14)."""
        af = int(self.afs[idx])
        terms = len(self.x) - 3 * af + 1
        self.dev[idx] = np.sqrt(self.So[idx] / (6.0 * terms * af ** 2))

    def update_S(self, idx):
        """Moves the window by one sample (eq. 12) and adds its square
        (eq. 11)."""
        af = int(self.afs[idx])
        x, i = self.x, len(self.x) - 1
        self.S[idx] += x[i] - 3 * x[i - af] + 3 * x[i - 2 * af] - x[i - 3 * af]
        self.So[idx] += self.S[idx] ** 2
        self.update_dev(idx)

    def mdev(self):
        """MDEV = sqrt(3) TDEV / tau (NIST SP 1065 eq. 16)."""
        return np.array([d * np.sqrt(3.0) / (af * self.tau0) for d, af in zip(self.dev, self.afs)])
