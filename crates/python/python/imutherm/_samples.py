"""Checks the samples before they reach the engine, so that bad input raises
a clear exception instead of reaching Rust as something it cannot read."""

import re

import numpy as np


def as_samples(y, name="y"):
    """A 1-D, contiguous float64 view of ``y``: the array itself when it is
    one already (no copy), a converted copy otherwise."""
    a = np.asarray(y)
    # Booleans count as 0 and 1, as NumPy and AllanTools take them.
    if a.dtype.kind not in "fiub":
        raise TypeError(
            f"{name}: samples must be real numbers (float, integer or bool), got dtype {a.dtype}"
        )
    if a.ndim != 1:
        raise ValueError(
            f"{name}: samples must be a 1-D array, got shape {a.shape}; "
            "pass one channel at a time, e.g. y[:, 0]"
        )
    if a.size == 0:
        raise ValueError(f"{name}: no samples")
    return np.ascontiguousarray(a, dtype=np.float64)


def as_taus(taus):
    """A tau grid name, or the taus in seconds as a list of floats; a single
    number is a list of one."""
    if isinstance(taus, str):
        return taus
    arr = np.asarray(taus, dtype=np.float64)
    if arr.ndim == 0:
        arr = arr.reshape(1)
    if arr.ndim != 1:
        raise ValueError(f"taus must be a name or a 1-D sequence of seconds, got shape {arr.shape}")
    return arr.tolist()


_TOO_SHORT = re.compile(r"needs at least (\d+) valid samples, the series has (\d+)")
_NO_TAU = re.compile(r"can be computed from (\d+) samples")


def in_samples(message, data_type):
    """An engine message with its counts in the caller's samples: rate
    (``"freq"``) data of N samples is the phase series of N + 1 points the
    engine counts (crates/allan/src/phase.rs, PhaseSeries::new)."""
    if data_type != "freq":
        return message
    message = _TOO_SHORT.sub(
        lambda m: f"needs at least {int(m[1]) - 1} valid samples, the series has {int(m[2]) - 1}",
        message)
    return _NO_TAU.sub(lambda m: f"can be computed from {int(m[1]) - 1} samples", message)
