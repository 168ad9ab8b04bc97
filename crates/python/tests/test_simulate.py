"""imutherm.simulate: the samples `imutherm simulate` writes with the same
arguments (when IMUTHERM_BIN names the command line), and the noise the
preset's metadata states."""

import os
import subprocess

import numpy as np
import pytest

import imutherm

ARGS = dict(preset="white", duration=120, rate=100, seed=11)


def test_seeded_and_sized():
    a = imutherm.simulate(**ARGS)
    b = imutherm.simulate(**ARGS)
    c = imutherm.simulate(**{**ARGS, "seed": 12})
    assert len(a) == 12_000 and a.rate == 100.0
    np.testing.assert_array_equal(a.channels["gyro_x"], b.channels["gyro_x"])
    assert not np.array_equal(a.channels["gyro_x"], c.channels["gyro_x"])


def test_white_noise_as_its_metadata_states():
    rec = imutherm.simulate(**ARGS)
    meta = dict(rec.metadata["entries"])
    for name in ("gyro_x", "accel_y"):
        density = float(meta[f"true.{name}.n"])
        # White noise of density N sampled at f has the per-sample standard
        # deviation N*sqrt(f) (IEEE Std 952-1997 C.1); 12 000 samples pin the
        # estimate to about 0.65 % (1 sigma), 4 sigma allowed.
        assert rec.channels[name].std(ddof=1) == pytest.approx(density * np.sqrt(ARGS["rate"]),
                                                              rel=4 * np.sqrt(1 / (2 * 12_000)))


def test_a_unit_is_one_board_whatever_the_seed():
    one = imutherm.simulate(**ARGS, unit="SN-1")
    again = imutherm.simulate(**{**ARGS, "seed": 12}, unit="SN-1")
    other = imutherm.simulate(**ARGS, unit="SN-2")
    truth = [dict(r.metadata["entries"])["true.gyro_x.n"] for r in (one, again, other)]
    assert truth[0] == truth[1] != truth[2]
    assert not np.array_equal(one.channels["gyro_x"], again.channels["gyro_x"])
    dead = imutherm.simulate(**ARGS, unit="SN-1", defect="dead-axis:gyro_y")
    assert np.ptp(dead.channels["gyro_y"]) == 0.0 and np.ptp(dead.channels["gyro_x"]) > 0.0
    with pytest.raises(imutherm.ImuthermError, match="give its id"):
        imutherm.simulate(**ARGS, defect="noise-3x")
    with pytest.raises(imutherm.ImuthermError, match="noise-3x, slope-5x"):
        imutherm.simulate(**ARGS, unit="SN-1", defect="broken")


def test_bad_arguments_carry_the_command_line_message():
    with pytest.raises(imutherm.ImuthermError, match="unknown preset 'nope'"):
        imutherm.simulate(preset="nope")
    with pytest.raises(imutherm.ImuthermError, match="unknown kind 'wobble'"):
        imutherm.simulate(profile="wobble:1")


@pytest.mark.skipif("IMUTHERM_BIN" not in os.environ, reason="IMUTHERM_BIN names no command line")
@pytest.mark.parametrize("args", [ARGS, dict(preset="mpu9250-thesis", duration=300, rate=20, seed=3,
                                             profile="ramp:20:60:300"),
                                  dict(preset="mpu9250-thesis", duration=120, unit="SN-7", seed=2,
                                       scatter="0.2,0.3", defect="dead-axis:accel_y")])
def test_same_samples_as_the_command_line(tmp_path, args):
    out = tmp_path / "sim.txt"
    cmd = [os.environ["IMUTHERM_BIN"], "simulate", "-o", str(out)]
    for k, v in args.items():
        cmd += [f"--{k}", str(v)]
    subprocess.run(cmd, check=True, capture_output=True)
    written = imutherm.read(out)
    rec = imutherm.simulate(**args)
    assert list(written.channels) == list(rec.channels)
    for name, data in rec.channels.items():
        # The log holds each value's shortest round-trip decimal: equal bits.
        np.testing.assert_array_equal(written.channels[name], data)
    assert set(rec.metadata["entries"]) <= set(written.metadata["entries"])
