"""A recording as NumPy arrays: what ``imutherm.read`` and
``imutherm.simulate`` return."""

import numpy as np


class Channel:
    """One column of a recording: ``name`` (imutherm's, e.g. ``gyro_x``),
    ``source`` (the file's), ``quantity`` (``angular_rate``,
    ``acceleration``, ``temperature``, ...), ``unit`` (SI for inertial
    channels), ``unit_source`` (``header``, ``flag``, ``metadata`` or
    ``assumed``) and ``data`` (a float64 NumPy array, NaN where a sample is
    missing)."""

    __slots__ = ("name", "source", "quantity", "unit", "unit_source", "data")

    def __init__(self, fields):
        for key in self.__slots__:
            setattr(self, key, fields[key])

    def __repr__(self):
        return (f"<imutherm.Channel {self.name} ({self.quantity}, {self.unit or '-'}), "
                f"{len(self.data)} samples>")


class Recording:
    """A recording read by :func:`imutherm.read` or made by
    :func:`imutherm.simulate`.

    * ``channels`` -- a dict, channel name -> float64 NumPy array, in the
      file's order; ``channel(name)`` gives the :class:`Channel` with its
      unit and quantity, ``units`` the units by name;
    * ``rate`` -- the sample rate in Hz (None when nothing gives it),
      ``rate_source`` where it came from (as ``imutherm info`` says);
    * ``temperature`` -- the temperature channel in degrees C, or None;
    * ``timestamps`` -- the file's stamps in seconds from the first one, one
      per row read (not per slot: a time gap leaves slots without a stamp),
      or None; ``timestamp_slots`` gives each stamp's slot on the clock (-1
      for a row dropped as a repeat of the previous one), or None;
    * ``metadata`` -- ``device``, ``start_time`` and the file's ``entries``
      (key, value pairs);
    * ``file``, ``format``, ``lines``, ``notes`` (what the reader guessed or
      found suspicious), ``problems`` (dicts: ``kind``, ``line``,
      ``column``, ``channel``, ``count``, ``message``), ``dropped_samples``,
      ``clock`` (the fitted clock of a time column, or None),
      ``streams`` (a robot log's streams) and ``checks`` (dicts: ``kind``
      -- stuck, saturated, accel_norm or motion --, ``message`` and the
      figures): the fields of ``imutherm info --json``.

    >>> import imutherm
    >>> rec = imutherm.simulate(preset="white", duration=10, rate=100, seed=1)
    >>> rec.rate, len(rec), list(rec.channels)[:2]
    (100.0, 1000, ['accel_x', 'accel_y'])
    """

    def __init__(self, fields):
        self._channels = [Channel(c) for c in fields["channels"]]
        self.channels = {c.name: c.data for c in self._channels}
        self.rate = fields["rate_hz"]
        self.timestamps = fields["timestamps"]
        self.metadata = fields["metadata"]
        self.file = fields["file"]
        self.format = fields["format"]
        self.rate_source = fields["rate_source"]
        self.lines = fields.get("lines")
        self.notes = fields.get("notes", [])
        self.problems = fields.get("problems", [])
        self.problems_unlisted = fields.get("problems_unlisted", 0)
        self.dropped_samples = fields.get("dropped_samples", 0)
        self.clock = fields.get("clock")
        self.streams = fields.get("streams", [])
        self.checks = fields.get("checks", [])
        self.timestamp_slots = fields.get("timestamp_slots")
        # Set by TcalModel.apply: samples compensated at the edge of the
        # fitted temperature range.
        self.out_of_range = 0
        # The options imutherm.read was given (empty for a simulation).
        self.read_options = {}

    def __len__(self):
        return len(self._channels[0].data) if self._channels else 0

    def channel(self, name):
        """The :class:`Channel` called ``name`` (imutherm's name or the
        file's); ``KeyError`` listing the channels when there is none."""
        for c in self._channels:
            if c.name == name or c.source == name:
                return c
        raise KeyError(f"no channel '{name}' (channels: {', '.join(self.channels)})")

    @property
    def units(self):
        """Channel name -> unit."""
        return {c.name: c.unit for c in self._channels}

    @property
    def temperature(self):
        """The temperature channel (degrees C), or None."""
        for c in self._channels:
            if c.quantity == "temperature":
                return c.data
        return None

    @property
    def duration(self):
        """Seconds covered (samples / rate), or None without a rate."""
        return len(self) / self.rate if self.rate else None

    def to_pandas(self):
        """The channels as a ``pandas.DataFrame``, one row per slot of the
        sample clock, indexed by time in seconds (``time_s``: the first
        stamp plus slot / rate; the sample index when the rate is unknown).
        A time gap the reader filled is a run of NaN rows. With stamps in the
        file, the column ``timestamp_s`` holds each row's real stamp (NaN in
        a gap). Units and metadata in ``attrs`` (needs pandas).

        >>> df = imutherm.simulate(preset="white", duration=1, rate=10, seed=1).to_pandas()
        >>> df.index.name, df.shape
        ('time_s', (10, 7))
        """
        try:
            import pandas as pd
        except ImportError as e:  # pragma: no cover - depends on the environment
            raise ImportError("Recording.to_pandas() needs pandas: pip install pandas") from e
        stamps = self._stamps_on_clock()
        if self.rate:
            start = 0.0
            if stamps is not None and np.isfinite(stamps).any():
                first = int(np.flatnonzero(np.isfinite(stamps))[0])
                start = float(stamps[first]) - first / self.rate
            index = pd.Index(start + np.arange(len(self)) / self.rate, name="time_s")
        else:
            index = pd.RangeIndex(len(self), name="sample")
        frame = pd.DataFrame(dict(self.channels), index=index)
        if stamps is not None:
            frame["timestamp_s"] = stamps
        frame.attrs.update(units=self.units, rate=self.rate, file=self.file, format=self.format,
                           metadata=self.metadata)
        return frame

    def _stamps_on_clock(self):
        """The stamps on the channels' slots, NaN where no row sits; None
        without stamps. Raises ``ValueError`` when the reader's placement
        cannot be told from the stamps (see ``timestamp_slots``)."""
        if self.timestamps is None:
            return None
        slots = self.timestamp_slots
        if slots is None:
            if len(self.timestamps) == len(self):
                return np.asarray(self.timestamps, dtype=np.float64)
            raise ValueError(
                f"{self.file}: {len(self.timestamps)} time stamps for {len(self)} samples, and "
                "which rows the reader dropped as repeats cannot be told from the stamps; "
                "the samples are in channels, the stamps in timestamps")
        out = np.full(len(self), np.nan)
        kept = slots >= 0
        out[slots[kept]] = np.asarray(self.timestamps)[kept]
        return out

    def __repr__(self):
        rate = f"{self.rate:g} Hz ({self.rate_source})" if self.rate else "unknown rate"
        head = (f"<imutherm.Recording {self.file or 'simulated'} ({self.format}): "
                f"{len(self)} samples at {rate}")
        if self.rate:
            head += f", {self.duration:.3f} s"
        rows = [head + ">"]
        for c in self._channels:
            finite = c.data[np.isfinite(c.data)]
            mean = f"{finite.mean():14.6e}" if finite.size else f"{'-':>14}"
            rows.append(f"  {c.name:<12} {c.unit or '-':<8} mean {mean}  "
                        f"NaN {len(c.data) - finite.size}")
        if self.problems:
            rows.append(f"  problems: {len(self.problems) + self.problems_unlisted}")
        for n in self.notes:
            rows.append(f"  note: {n}")
        return "\n".join(rows)
