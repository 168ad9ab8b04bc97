"""imutherm.read against the files' own truth: a text log written here, the
robot-log fixtures against what their writers were given (truth.json, made
by make_fixtures.py with rosbags/mcap and checked with pymavlink's
DFReader), and, when IMUTHERM_BIN names the command line, against its
``info --json``."""

import json
import os
import pathlib
import shutil
import subprocess

import numpy as np
import pytest

import imutherm

FIXTURES = pathlib.Path(__file__).resolve().parents[2] / "robotlogs" / "tests" / "fixtures" / "ros"
TRUTH = json.loads((FIXTURES / "truth.json").read_text())
ORDER = ("accel_x", "accel_y", "accel_z", "gyro_x", "gyro_y", "gyro_z")


def sum_tolerance(x):
    """How far two summation orders of x may part: n ulps of sum |x|."""
    return len(x) * np.finfo(float).eps * np.abs(x).sum()


def write_csv(path, columns, rate):
    names = list(columns)
    with open(path, "w") as f:
        f.write(f"# sample_rate_hz: {rate}\n")
        f.write(",".join(names) + "\n")
        for row in zip(*columns.values()):
            f.write(",".join(repr(float(v)) for v in row) + "\n")


@pytest.fixture
def text_log(tmp_path):
    rng = np.random.default_rng(18)
    cols = {
        "gyro_x": 1e-3 * rng.standard_normal(500),
        "gyro_y": 2e-3 * rng.standard_normal(500),
        "accel_z": 9.81 + 1e-2 * rng.standard_normal(500),
        "temp": np.linspace(20.0, 30.0, 500),
    }
    path = tmp_path / "imu.csv"
    write_csv(path, cols, 50.0)
    return path, cols


def test_text_log_reads_the_values_written(text_log):
    path, cols = text_log
    rec = imutherm.read(path)
    assert rec.rate == 50.0
    assert len(rec) == 500
    assert list(rec.channels) == list(cols)
    for name, data in cols.items():
        np.testing.assert_array_equal(rec.channels[name], data)
    np.testing.assert_array_equal(rec.temperature, cols["temp"])
    assert rec.units["gyro_x"] == "rad/s"
    assert rec.channel("gyro_x").quantity == "angular_rate"


def test_rate_and_units_as_on_the_command_line(text_log):
    path, cols = text_log
    rec = imutherm.read(path, rate=100, units={"gyro_x": "deg/s"})
    assert rec.rate == 100.0 and rec.rate_source == "given"
    np.testing.assert_allclose(rec.channels["gyro_x"], np.deg2rad(cols["gyro_x"]), rtol=1e-15)
    assert rec.channel("gyro_x").unit_source == "flag"


def test_mcap_fixture_holds_what_its_writer_was_given():
    truth = TRUTH["static_5s"]
    rec = imutherm.read(FIXTURES / "imu_zstd.mcap")
    assert rec.format == "MCAP"
    assert len(rec) == truth["messages"]
    assert rec.rate == pytest.approx(TRUTH["rate_hz"], rel=1e-6)
    for k, name in enumerate(ORDER):
        data = rec.channels[name]
        assert data[0] == truth["first"][k]
        assert data[-1] == truth["last"][k]
        assert abs(data.sum() - truth["sum"][k]) <= sum_tolerance(data)
    assert [s["name"] for s in rec.streams] == ["/imu/data", "/imu/temperature"]


@pytest.mark.parametrize("instance", ["0", "1"])
def test_dataflash_fixture_as_dfreader_reads_it(instance):
    truth = TRUTH["dataflash_dfreader"][instance]
    rec = imutherm.read(FIXTURES / "arducopter_imu.bin", instance=int(instance))
    data = {name: rec.channels[name][np.isfinite(rec.channels[name])] for name in ORDER}
    for k, name in enumerate(ORDER):
        assert len(data[name]) == truth["messages"]
        assert data[name][0] == truth["first"][k]
        assert abs(data[name].sum() - truth["sum"][k]) <= sum_tolerance(data[name])


def test_several_streams_and_none_chosen_is_refused_naming_them():
    with pytest.raises(imutherm.ImuthermError, match="choose one with topic: /imu0/data"):
        imutherm.read(FIXTURES / "two_imus.mcap")
    rec = imutherm.read(FIXTURES / "two_imus.mcap", topic="/imu1/data")
    assert len(rec) == 200


def test_missing_file_is_an_os_error_with_the_command_line_message(tmp_path):
    missing = tmp_path / "none.txt"
    with pytest.raises(FileNotFoundError, match=f"{missing}: No such file or directory"):
        imutherm.read(missing)
    with pytest.raises(IsADirectoryError, match=f"{tmp_path}: is a directory, not a file"):
        imutherm.read(tmp_path)


def test_allow_partial_reads_a_bag_missing_a_listed_file_and_reports_the_loss(tmp_path):
    bag = tmp_path / "bag"
    bag.mkdir()
    shutil.copy(FIXTURES / "bag_split" / "bag_split_0.mcap", bag)
    # rosbag2's per-file entries (rosbag2_storage/yaml.hpp: path, message_count).
    (bag / "metadata.yaml").write_text((FIXTURES / "bag_split" / "metadata.yaml").read_text()
                                       + "  files:\n    - path: bag_split_1.mcap\n"
                                       + "      message_count: 503\n")
    with pytest.raises(imutherm.ImuthermError, match="bag_split_1.mcap it lists is missing"):
        imutherm.read(bag)
    rec = imutherm.read(bag, allow_partial=True)
    assert len(rec) == 500
    lost = [p for p in rec.problems if p["kind"] == "skipped_data"]
    assert len(lost) == 1 and lost[0]["count"] == 503 and "bag_split_1.mcap" in lost[0]["message"]
    text = tmp_path / "t.csv"
    text.write_text("gyro_x\n1\n2\n3\n")
    with pytest.raises(ValueError, match=": allow_partial applies to robot logs") as refused:
        imutherm.read(text, allow_partial=True)
    assert "--" not in str(refused.value)


def test_bad_option_is_a_value_error_naming_the_keyword():
    with pytest.raises(ValueError, match="^rate=-1: the sample rate must be a positive number"):
        imutherm.read(FIXTURES / "imu_zstd.mcap", rate=-1)
    with pytest.raises(ValueError, match="^units entry 'gyro_x=furlong': unknown unit 'furlong'"):
        imutherm.read(FIXTURES / "imu_zstd.mcap", units=["gyro_x=furlong"])
    with pytest.raises(ValueError, match="no stream topic='nope' in the log; streams: /imu/data"):
        imutherm.read(FIXTURES / "imu_zstd.mcap", topic="nope")
    with pytest.raises(ValueError, match="no stream instance=7 in the log"):
        imutherm.read(FIXTURES / "imu_zstd.mcap", instance=7)
    with pytest.raises(ValueError) as refused:
        imutherm.read(FIXTURES / "arducopter_imu.bin")
    assert "--" not in str(refused.value) and "choose one with instance: IMU/0" in str(refused.value)


def test_os_errors_carry_the_file_name(tmp_path):
    missing = tmp_path / "none.csv"
    with pytest.raises(FileNotFoundError) as e:
        imutherm.read(missing)
    assert e.value.filename == str(missing)
    with pytest.raises(FileNotFoundError) as e:
        imutherm.tcal_fit([FIXTURES / "imu_zstd.mcap", missing])
    assert e.value.filename == str(missing)


def test_to_pandas_and_repr(text_log):
    pd = pytest.importorskip("pandas")
    path, cols = text_log
    rec = imutherm.read(path)
    df = rec.to_pandas()
    assert isinstance(df, pd.DataFrame)
    assert df.shape == (500, 4)
    assert df.index[1] == pytest.approx(1 / 50.0)
    assert df.attrs["units"]["gyro_x"] == "rad/s"
    assert "500 samples at 50 Hz" in repr(rec) and "gyro_x" in repr(rec)


# Every robot-log fixture, with the stream to read where it holds several.
ROBOT_LOGS = [("imu_zstd.mcap", {}), ("imu_lz4_big_endian.mcap", {}), ("imu_zero_stamps.mcap", {}),
              ("two_imus.mcap", {"topic": "/imu1/data"}), ("imu_bz2.bag", {}), ("imu_lz4.bag", {}),
              ("imu_none.bag", {}), ("gap.bag", {}), ("bag_mcap/bag_mcap.mcap", {}),
              ("bag_split/bag_split_0.mcap", {}), ("bag_sqlite3/bag_sqlite3.db3", {}),
              ("arducopter_imu.bin", {"instance": 0}), ("arducopter_imu.bin", {"instance": 1}),
              ("../px4/sample_log_small.ulg", {}), ("../px4/sample_appended_multiple.ulg", {}),
              ("../px4/sample_logging_tagged_and_default_params.ulg", {})]


def gap_samples(rec):
    return sum(p["count"] for p in rec.problems if p["kind"] == "time_gap")


@pytest.mark.parametrize("which,options", ROBOT_LOGS, ids=[f"{w}{o}" for w, o in ROBOT_LOGS])
def test_to_pandas_puts_every_robot_log_on_its_clock(which, options):
    pytest.importorskip("pandas")
    rec = imutherm.read(FIXTURES / which, **options)
    df = rec.to_pandas()
    # One row per slot of the clock, every channel's samples as read.
    assert len(df) == len(rec)
    for name, data in rec.channels.items():
        np.testing.assert_array_equal(df[name].to_numpy(), data)
    assert df.index[1] - df.index[0] == pytest.approx(1 / rec.rate)
    # Each stamp read sits in one slot, in order; the other slots are the
    # filled gaps (with problems listed in full, their counts add up).
    stamps = df["timestamp_s"].to_numpy()
    placed = stamps[np.isfinite(stamps)]
    assert len(placed) == np.isfinite(rec.timestamps).sum() - rec.dropped_samples
    assert np.all(np.diff(placed) > 0) or rec.clock["duplicate_stamps"] + rec.clock["backward_stamps"]
    if not rec.problems_unlisted:
        assert np.isnan(stamps).sum() == gap_samples(rec) + (~np.isfinite(rec.timestamps)).sum()


@pytest.mark.parametrize("which", ["gap.bag", "../px4/sample_logging_tagged_and_default_params.ulg"])
def test_to_pandas_stamps_sit_in_their_slots_on_a_steady_clock(which):
    # Logs whose clock is steady (jitter far below a period): each stamp is
    # within half a period of its slot's time.
    pytest.importorskip("pandas")
    rec = imutherm.read(FIXTURES / which)
    assert gap_samples(rec) > 0
    df = rec.to_pandas()
    off = (df["timestamp_s"] - df.index.to_numpy()).abs().max()
    assert off < 0.5 / rec.rate


def test_to_pandas_on_a_csv_with_rows_removed(tmp_path):
    pd = pytest.importorskip("pandas")
    rng = np.random.default_rng(37)
    n, rate = 300, 100.0
    t = np.arange(n) / rate
    gyro = 1e-3 * rng.standard_normal(n)
    removed = np.r_[50:60, 200:210]  # 20 rows in two gaps
    keep = np.setdiff1d(np.arange(n), removed)
    path = tmp_path / "gapped.csv"
    write_csv(path, {"time": t[keep], "gyro_x": gyro[keep]}, rate)
    rec = imutherm.read(path)
    assert len(rec) == n and len(rec.timestamps) == n - 20
    df = rec.to_pandas()
    assert isinstance(df, pd.DataFrame) and len(df) == n
    np.testing.assert_allclose(df.index.to_numpy(), t, atol=1e-12)
    assert np.isnan(df["gyro_x"].to_numpy()[removed]).all()
    np.testing.assert_array_equal(df["gyro_x"].to_numpy()[keep], gyro[keep])
    np.testing.assert_array_equal(df["timestamp_s"].to_numpy()[keep], t[keep])
    assert np.isnan(df["timestamp_s"].to_numpy()[removed]).all()


def cli_info(path):
    out = subprocess.run([os.environ["IMUTHERM_BIN"], "info", "--json", str(path)],
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out)["files"][0]


@pytest.mark.skipif("IMUTHERM_BIN" not in os.environ, reason="IMUTHERM_BIN names no command line")
# The formats the command line reads: text, MCAP, ROS 1 (bz2, lz4), a ROS 2
# SQLite3 bag and PX4 ULog (DataFlash, whose fixture holds two IMUs, in
# test_dataflash_fixture_as_dfreader_reads_it).
@pytest.mark.parametrize("which", ["text", "imu_zstd.mcap", "imu_bz2.bag", "imu_lz4.bag", "gap.bag",
                                   "bag_sqlite3/bag_sqlite3.db3", "../px4/sample_log_small.ulg"])
def test_same_as_info_json(which, text_log):
    path = text_log[0] if which == "text" else FIXTURES / which
    info = cli_info(path)
    rec = imutherm.read(path)
    assert info["format"] == rec.format
    assert info["samples"] == len(rec)
    assert info["lines"] == rec.lines
    assert info["rate_hz"] == rec.rate
    assert info["rate_source"] == rec.rate_source
    assert info["notes"] == rec.notes
    assert info["dropped_samples"] == rec.dropped_samples
    assert [p["message"] for p in info["problems"]] == [p["message"] for p in rec.problems]
    assert [s["name"] for s in info.get("streams", [])] == [s["name"] for s in rec.streams]
    for c in info["channels"]:
        data = rec.channels[c["name"]]
        finite = data[np.isfinite(data)]
        assert c["unit"] == rec.units[c["name"]]
        assert c["nan_samples"] == len(data) - len(finite)
        assert c["min"] == finite.min() and c["max"] == finite.max()
        assert c["mean"] == pytest.approx(finite.mean(), rel=1e-12, abs=1e-15)
        assert c["std"] == pytest.approx(finite.std(ddof=1), rel=1e-9, abs=1e-15)


def test_a_dead_gyro_is_among_the_checks(tmp_path):
    # A gyro reading exactly 0.0 in every sample, beside a live one.
    rng = np.random.default_rng(35)
    cols = {
        "gyro_x": np.zeros(500),
        "gyro_y": 2e-3 * rng.standard_normal(500),
    }
    path = tmp_path / "dead.csv"
    write_csv(path, cols, 50.0)
    rec = imutherm.read(path)
    stuck = [c for c in rec.checks if c["kind"] == "stuck"]
    assert [(c["channel"], c["value"], c["samples"], c["of"]) for c in stuck] == [("gyro_x", 0.0, 500, 500)]
    assert "stuck at zero" in stuck[0]["message"]


def write_stamped(path, rows):
    with open(path, "w") as f:
        f.write("time,gyro_x\n")
        for t, g in rows:
            f.write(f"{float(t)!r},{float(g)!r}\n")
    return path


def test_to_pandas_leaves_out_a_row_the_reader_dropped(tmp_path):
    pytest.importorskip("pandas")
    t = np.arange(100) / 100.0
    g = np.random.default_rng(3).standard_normal(100)
    rows = list(zip(t, g))
    rec = imutherm.read(write_stamped(tmp_path / "twice.csv", rows[:50] + [rows[49]] + rows[50:]))
    assert rec.dropped_samples == 1 and len(rec.timestamps) == 101 and len(rec) == 100
    assert list(rec.timestamp_slots[48:53]) == [48, 49, -1, 50, 51]
    df = rec.to_pandas()
    np.testing.assert_array_equal(df["gyro_x"].to_numpy(), g)
    np.testing.assert_array_equal(df["timestamp_s"].to_numpy(), t)


def test_to_pandas_refuses_stamps_it_cannot_place(tmp_path):
    # A repeated row (dropped) and a repeated stamp with new values (kept):
    # which of the repeated stamps lost its row is not in the stamps.
    t = np.arange(100) / 100.0
    g = np.random.default_rng(4).standard_normal(100)
    rows = list(zip(t, g))
    rows = rows[:30] + [(t[29], 5.0)] + rows[30:50] + [rows[49]] + rows[50:]
    rec = imutherm.read(write_stamped(tmp_path / "mixed.csv", rows))
    assert rec.timestamp_slots is None
    with pytest.raises(ValueError, match="102 time stamps for 101 samples"):
        rec.to_pandas()
