"""imutherm.allantools returns AllanTools 2024.6's own tuples: the same taus
and ns exactly, deviations and error bars to 1e-9 relative."""

import allantools
import numpy as np
import pytest

from imutherm import allantools as dropin

RTOL = 1e-9
GRIDS = ["octave", "decade", "all", np.array([0.5, 1.5, 10.0, 37.0, 1e9])]
# AllanTools' own Theo1, MTOTDEV and HTOTDEV are Python loops: shorter data,
# and not at every m.
SLOW = {"theo1", "mtotdev", "ttotdev", "htotdev"}


def assert_same_tuple(got, want):
    assert len(got) == len(want) == 4
    taus, devs, errs, ns = got
    np.testing.assert_array_equal(taus, want[0])
    np.testing.assert_array_equal(ns, want[3])
    np.testing.assert_allclose(devs, want[1], rtol=RTOL, atol=0)
    np.testing.assert_allclose(errs, want[2], rtol=RTOL, atol=0)
    assert len(taus) > 0


CASES = [(stat, grid) for stat in dropin.allantools.ENGINE_STATISTICS for grid in range(len(GRIDS))
         if not (stat in SLOW and GRIDS[grid] is GRIDS[2])]


@pytest.mark.parametrize(("stat", "grid"), CASES)
def test_rate_data(stat, grid, rate_noise):
    taus = GRIDS[grid]
    y = rate_noise[:300] if stat in SLOW else rate_noise
    got = getattr(dropin, stat)(y, rate=2.0, data_type="freq", taus=taus)
    want = getattr(allantools, stat)(y, rate=2.0, data_type="freq", taus=taus)
    assert_same_tuple(got, want)


@pytest.mark.parametrize("stat", dropin.allantools.ENGINE_STATISTICS)
def test_default_is_phase_data(stat, phase_noise):
    if stat in SLOW:
        phase_noise = phase_noise[:512]
    got = getattr(dropin, stat)(phase_noise)
    want = getattr(allantools, stat)(phase_noise)
    assert_same_tuple(got, want)
    # Taken as rate data the same samples give another curve.
    other = getattr(dropin, stat)(phase_noise, data_type="freq")
    k = min(len(other[1]), len(got[1]))
    assert not np.allclose(other[1][:k], got[1][:k], rtol=1e-3, atol=0)


def test_lists_are_accepted(phase_noise):
    got = dropin.oadev(list(phase_noise), taus=[1, 2, 3])
    assert_same_tuple(got, allantools.oadev(list(phase_noise), taus=[1, 2, 3]))


def test_bad_data_type_and_grid(phase_noise):
    with pytest.raises(ValueError, match="data_type"):
        dropin.adev(phase_noise, data_type="frequency-ish")
    with pytest.raises(ValueError, match="taus"):
        dropin.adev(phase_noise, taus="fast")
