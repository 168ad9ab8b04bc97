"""Every statistic of the main API against AllanTools 2024.6, computed on the
same arrays in the same process: deviations to 1e-9 relative and the same
number of terms at every averaging factor both report."""

import allantools
import numpy as np
import pytest

import imutherm

DEV_RTOL = 1e-9
MIN_COMMON = 3
# AllanTools' own MTOTDEV, HTOTDEV and Theo1 are Python loops: shorter data
# keep the suite fast.
SLOW = {"theo1", "mtotdev", "ttotdev", "htotdev"}


def allantools_by_m(stat, y, rate, data_type):
    taus, devs, _, ns = getattr(allantools, stat)(y, rate=rate, data_type=data_type, taus="octave")
    # AllanTools labels every statistic, Theo1 included, at tau = m/rate.
    return {int(round(t * rate)): (d, n) for t, d, n in zip(taus, devs, ns)}


def check_against_allantools(stat, y, rate, data_type):
    if stat in SLOW:
        y = y[:512]
    curve = imutherm.analyze(stat, y, rate=rate, data_type=data_type)
    ref = allantools_by_m(stat, y, rate, data_type)
    common = [i for i, m in enumerate(curve.m) if int(m) in ref]
    assert len(common) >= MIN_COMMON, (stat, curve.m, sorted(ref))
    for i in common:
        dev, n = ref[int(curve.m[i])]
        assert curve.devs[i] == pytest.approx(dev, rel=DEV_RTOL), (stat, curve.m[i])
        assert curve.n[i] == n, (stat, curve.m[i])


@pytest.mark.parametrize("stat", imutherm.STATISTICS)
def test_rate_data_equals_allantools(stat, rate_noise):
    check_against_allantools(stat, rate_noise, 100.0, "freq")


@pytest.mark.parametrize("stat", imutherm.STATISTICS)
def test_phase_data_equals_allantools(stat, phase_noise):
    check_against_allantools(stat, phase_noise, 1.0, "phase")


def test_curve_arrays_are_consistent(rate_noise):
    c = imutherm.oadev(rate_noise, rate=100.0, confidence=0.95)
    assert c.taus == pytest.approx(c.m / 100.0)
    assert np.all(c.lo < c.devs) and np.all(c.devs < c.hi)
    assert np.all(c.edf > 0) and c.n.dtype.kind == "u" and c.alpha.dtype.kind == "i"
    assert set(c.noise_id) <= {"acf", "b1", "assumed", "capped"}
    assert (c.stat, c.data_type, c.rate, c.confidence, c.samples) == ("oadev", "freq", 100.0, 0.95, 1024)
    wider = imutherm.oadev(rate_noise, rate=100.0, confidence=0.99)
    assert np.all(wider.hi > c.hi) and np.all(wider.lo < c.lo)


def test_theo1_reports_its_own_tau(rate_noise):
    c = imutherm.theo1(rate_noise, rate=10.0)
    assert c.taus == pytest.approx(0.75 * c.m / 10.0)


def test_explicit_taus_and_grids(rate_noise):
    c = imutherm.oadev(rate_noise, rate=100.0, taus=np.array([0.01, 0.03, 0.5, 1e6]))
    assert list(c.m) == [1, 3, 50]
    assert len(imutherm.oadev(rate_noise, taus="all")) == (len(rate_noise) + 1) // 4
    assert list(imutherm.totdev(rate_noise, taus="decade").m) == [1, 2, 4, 10, 20, 40, 100, 200, 400]


def test_repr_and_pandas(rate_noise):
    c = imutherm.mdev(rate_noise, rate=100.0)
    text = repr(c)
    assert text.startswith("<imutherm.Curve mdev of 1024 freq samples at 100 Hz")
    assert f"{c.devs[0]:12.5e}" in text
    pd = pytest.importorskip("pandas")
    frame = c.to_pandas()
    assert isinstance(frame, pd.DataFrame) and len(frame) == len(c)
    assert frame["devs"].to_numpy() == pytest.approx(c.devs)
    assert frame.index.name == "tau" and frame.attrs["stat"] == "mdev"
