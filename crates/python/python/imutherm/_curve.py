"""The result of a statistic: NumPy arrays by tau, with their intervals."""

import numpy as np

#: The per-tau arrays of a :class:`Curve`, in the order ``to_pandas`` puts them.
COLUMNS = ("taus", "devs", "lo", "hi", "edf", "n", "alpha", "noise_id", "m")


class Curve:
    """One statistic of one series over a tau grid.

    Attributes (NumPy arrays, one entry per tau):

    * ``taus`` -- tau in seconds;
    * ``devs`` -- the deviation, in the unit of the samples (of their
      integral for tdev and ttotdev);
    * ``lo``, ``hi`` -- the confidence interval at ``confidence``;
    * ``edf`` -- the equivalent degrees of freedom behind the interval;
    * ``n`` -- the number of terms summed;
    * ``alpha`` -- the power-law exponent of the rate noise (S_y ~ f^alpha)
      used for the EDF;
    * ``noise_id`` -- how alpha was found: ``acf``, ``b1``, ``assumed`` or
      ``capped``;
    * ``m`` -- the averaging factor (tau = m/rate, 0.75 m/rate for theo1).

    And: ``stat``, ``data_type``, ``rate``, ``confidence``, ``samples`` (the
    input's length) and ``nan_samples`` (the gaps among them).

    >>> import numpy as np, imutherm
    >>> c = imutherm.oadev(np.random.default_rng(1).standard_normal(10_000))
    >>> c.taus[:3]
    array([1., 2., 4.])
    >>> bool(np.all(c.lo <= c.devs) and np.all(c.devs <= c.hi))
    True
    """

    __slots__ = COLUMNS + ("stat", "data_type", "rate", "confidence", "samples", "nan_samples")

    def __init__(self, fields):
        for key in COLUMNS:
            setattr(self, key, fields[key])
        self.noise_id = np.asarray(fields["noise_id"], dtype=str)
        for key in ("stat", "data_type", "rate", "confidence", "samples", "nan_samples"):
            setattr(self, key, fields[key])

    def __len__(self):
        return len(self.taus)

    def to_pandas(self):
        """The points as a ``pandas.DataFrame`` indexed by tau (needs pandas).

        >>> df = imutherm.oadev(np.random.default_rng(1).standard_normal(1000)).to_pandas()
        >>> list(df.columns)[:4]
        ['devs', 'lo', 'hi', 'edf']
        """
        try:
            import pandas as pd
        except ImportError as e:  # pragma: no cover - depends on the environment
            raise ImportError("Curve.to_pandas() needs pandas: pip install pandas") from e
        frame = pd.DataFrame({key: getattr(self, key) for key in COLUMNS[1:]},
                             index=pd.Index(self.taus, name="tau"))
        frame.attrs.update(stat=self.stat, data_type=self.data_type, rate=self.rate,
                           confidence=self.confidence, samples=self.samples,
                           nan_samples=self.nan_samples)
        return frame

    def __repr__(self):
        head = (f"<imutherm.Curve {self.stat} of {self.samples} {self.data_type} samples "
                f"at {self.rate:g} Hz, {len(self)} taus, {100 * self.confidence:.1f} % intervals"
                + (f", {self.nan_samples} NaN gaps" if self.nan_samples else "") + ">")
        rows = ["       tau          dev           lo           hi       edf  alpha"]
        shown = range(len(self)) if len(self) <= 12 else list(range(6)) + [None] + list(range(len(self) - 5, len(self)))
        for i in shown:
            if i is None:
                rows.append("       ...")
                continue
            rows.append(f"{self.taus[i]:10.4g} {self.devs[i]:12.5e} {self.lo[i]:12.5e} "
                        f"{self.hi[i]:12.5e} {self.edf[i]:9.4g} {self.alpha[i]:6d}")
        return "\n".join([head] + rows)
