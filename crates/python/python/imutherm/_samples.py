"""Checks the samples before they reach the engine, so that bad input raises
a clear exception instead of reaching Rust as something it cannot read."""

import numpy as np


def as_samples(y, name="y"):
    """A 1-D, contiguous float64 view of ``y``: the array itself when it is
    one already (no copy), a converted copy otherwise."""
    a = np.asarray(y)
    if a.dtype.kind not in "fiu":
        raise TypeError(
            f"{name}: samples must be real numbers (float or integer), got dtype {a.dtype}"
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
    """A tau grid name, or the taus in seconds as a list of floats."""
    if isinstance(taus, str):
        return taus
    arr = np.asarray(taus, dtype=np.float64)
    if arr.ndim != 1:
        raise ValueError(f"taus must be a name or a 1-D sequence of seconds, got shape {arr.shape}")
    return arr.tolist()
