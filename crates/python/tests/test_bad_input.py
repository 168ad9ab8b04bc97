"""Bad input raises a clear Python exception, never a crash; NaN samples
are gaps as on the command line."""

import threading
import time

import numpy as np
import pytest

import imutherm
from imutherm._samples import as_samples

Y = np.random.default_rng(5).standard_normal(1000)


def test_empty():
    with pytest.raises(ValueError, match="no samples"):
        imutherm.oadev(np.array([]))


# Booleans are numbers (0 and 1) as in AllanTools: test_notebook_path.py.
@pytest.mark.parametrize("bad", [np.array(["a", "b"] * 50), np.ones(100, dtype=complex),
                                 [None] * 100])
def test_wrong_dtype(bad):
    with pytest.raises(TypeError, match="real numbers"):
        imutherm.adev(bad)


def test_two_dimensional():
    with pytest.raises(ValueError, match="1-D"):
        imutherm.oadev(np.ones((100, 3)))


def test_too_short_and_bad_options():
    with pytest.raises(imutherm.ImuthermError, match="needs at least"):
        imutherm.oadev(np.ones(2))
    with pytest.raises(imutherm.ImuthermError, match="invalid sample rate"):
        imutherm.oadev(Y, rate=0.0)
    with pytest.raises(imutherm.ImuthermError, match="confidence"):
        imutherm.oadev(Y, confidence=1.5)
    with pytest.raises(imutherm.ImuthermError, match="unknown statistic"):
        imutherm.analyze("bogus", Y)
    with pytest.raises(imutherm.ImuthermError, match="unknown data type"):
        imutherm.oadev(Y, data_type="volts")
    with pytest.raises(imutherm.ImuthermError, match="invalid tau list"):
        imutherm.oadev(Y, taus="1,2")
    with pytest.raises(imutherm.ImuthermError, match="invalid tau list"):
        imutherm.oadev(Y, taus=[1.0, -2.0])
    with pytest.raises(imutherm.ImuthermError, match="no requested tau"):
        imutherm.oadev(Y, taus=[1e6])
    assert issubclass(imutherm.ImuthermError, ValueError)


def test_infinite_sample():
    y = Y.copy()
    y[10] = np.inf
    with pytest.raises(imutherm.ImuthermError, match="sample 10 is infinite"):
        imutherm.oadev(y)


def test_nan_gaps_are_skipped_by_the_allan_family():
    y = Y.copy()
    y[100:110] = np.nan
    with pytest.warns(RuntimeWarning, match="10 NaN samples treated as gaps"):
        c = imutherm.oadev(y)
    assert c.nan_samples == 10
    clean = imutherm.oadev(Y)
    # Terms across the gap are skipped: fewer of them than without it.
    assert np.all(c.n < clean.n)


def test_nan_gaps_are_refused_by_the_total_statistics():
    y = Y.copy()
    y[100] = np.nan
    for stat in ("totdev", "mtotdev", "htotdev", "theo1"):
        with pytest.raises(imutherm.ImuthermError, match="cannot skip gaps"):
            imutherm.analyze(stat, y)


def test_all_nan():
    with pytest.raises(imutherm.ImuthermError):
        imutherm.oadev(np.full(100, np.nan))


def test_contiguous_float64_is_not_copied():
    assert as_samples(Y) is Y
    read_only = Y.copy()
    read_only.flags.writeable = False
    assert as_samples(read_only) is read_only
    assert imutherm.oadev(read_only).devs == pytest.approx(imutherm.oadev(Y).devs, rel=0)
    # A strided view or integers are converted once, and give the same result.
    doubled = np.repeat(Y, 2)[::2]
    assert as_samples(doubled) is not doubled
    assert imutherm.oadev(doubled).devs == pytest.approx(imutherm.oadev(Y).devs, rel=0)
    assert imutherm.oadev(np.arange(100) % 7).samples == 100


def test_the_gil_is_released_while_computing():
    y = np.random.default_rng(6).standard_normal(20_000)
    start = time.perf_counter()
    imutherm.mtotdev(y)
    alone = time.perf_counter() - start
    ticks = []
    done = threading.Event()

    def work():
        imutherm.mtotdev(y)
        done.set()

    worker = threading.Thread(target=work)
    worker.start()
    while not done.is_set():
        ticks.append(time.perf_counter())
        time.sleep(0.001)
    worker.join()
    # Held, the GIL would stop this loop for the whole call; released, it
    # ticks about once a millisecond throughout.
    assert alone > 0.02, "the call is too short to show anything"
    assert len(ticks) >= 5
    assert max(np.diff(ticks)) < alone / 2
