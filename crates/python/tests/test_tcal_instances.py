"""Every IMU of a flight controller's log from Python, against the command
line on the same files: ``imutherm.tcal_fit(log, instance="all")`` (and by
default with ``firmware``) holds each instance as ``imutherm tcal fit
--instance all`` does, ``export`` writes the one parameter file ``tcal
export`` writes, and ``evaluate`` gives ``tcal eval --json``'s document,
field by field. The logs are PX4 ULogs and ArduPilot DataFlash logs of two
IMUs (flight_logs.py), and the repository's own DataFlash fixture of two
IMUs (crates/robotlogs/tests/fixtures/ros/arducopter_imu.bin)."""

import json
import os
import pathlib
import shutil
import subprocess

import numpy as np
import pytest

import imutherm

import flight_logs

FIXTURE = (pathlib.Path(__file__).resolve().parents[2] / "robotlogs" / "tests" / "fixtures" / "ros"
           / "arducopter_imu.bin")
LOG = {"px4": "ulg", "ardupilot": "bin"}


def cli(*args, cwd, check=True):
    done = subprocess.run([os.environ["IMUTHERM_BIN"], *args], cwd=cwd, capture_output=True)
    if check and done.returncode != 0:
        raise AssertionError(f"imutherm {' '.join(args)}: status {done.returncode}\n"
                             f"{done.stderr.decode()}")
    return done


@pytest.fixture(scope="module")
def logs(tmp_path_factory):
    if "IMUTHERM_BIN" not in os.environ:
        pytest.skip("IMUTHERM_BIN names no command line to compare with")
    d = tmp_path_factory.mktemp("flight_logs")
    flight_logs.write_all(d)
    shutil.copy(FIXTURE, d / "arducopter_imu.bin")
    return d


@pytest.fixture
def in_logs(logs, monkeypatch):
    # The documents name the files as given: both sides run in the logs'
    # directory with relative names.
    monkeypatch.chdir(logs)
    return logs


def same_fields(python, command_line, where=""):
    """Asserts two JSON values equal, naming the first field that differs."""
    if isinstance(command_line, dict):
        assert isinstance(python, dict), where
        assert sorted(python) == sorted(command_line), f"{where}: fields"
        for k in command_line:
            same_fields(python[k], command_line[k], f"{where}.{k}")
    elif isinstance(command_line, list):
        assert isinstance(python, list) and len(python) == len(command_line), f"{where}: length"
        for i, (p, c) in enumerate(zip(python, command_line)):
            same_fields(p, c, f"{where}[{i}]")
    else:
        assert python == command_line, f"{where}: Python {python!r}, command line {command_line!r}"


def as_read(python, in_file, where):
    """Asserts an instance's model, as imutherm reads it from the file, is
    the file's: every field the same, every float to its last bit (the
    model loader parses a decimal to the nearest double, as Python does)."""
    if isinstance(in_file, dict):
        assert sorted(python) == sorted(in_file), where
        for k in in_file:
            as_read(python[k], in_file[k], f"{where}.{k}")
    elif isinstance(in_file, list):
        assert len(python) == len(in_file), where
        for i, (p, f) in enumerate(zip(python, in_file)):
            as_read(p, f, f"{where}[{i}]")
    else:
        assert python == in_file, f"{where}: {python!r} read from {in_file!r}"


@pytest.mark.parametrize("firmware", ["px4", "ardupilot"])
def test_fit_holds_every_instance_as_the_command_line(in_logs, firmware):
    log = f"heating.{LOG[firmware]}"
    cli("tcal", "fit", log, "--for", firmware, "-o", f"cli_{firmware}.json", cwd=in_logs)
    written = (in_logs / f"cli_{firmware}.json").read_text()
    # The default for a firmware on a log of several IMUs is every instance,
    # as --for's is; instance="all" says it outright.
    for model in (imutherm.tcal_fit(log, firmware=firmware),
                  imutherm.tcal_fit(log, firmware=firmware, instance="all")):
        same_fields(json.loads(model.to_json()), json.loads(written), "model")
        assert model.to_json() == written
    assert sorted(model.instances) == [0, 1]
    for n, (gyro_id, accel_id) in enumerate(flight_logs.IDS):
        one = model.instances[n]
        assert one.instance == n
        as_read(json.loads(one.to_json()), json.loads(written)["instances"][n], f"instances[{n}]")
        assert json.loads(one.to_json())["device_id"] == gyro_id
        assert json.loads(one.to_json())["accel_device_id"] == accel_id
        assert sorted(one.channels) == ["accel_x", "accel_y", "accel_z", "gyro_x", "gyro_y", "gyro_z"]
    # The top level is the first instance's, as in the file.
    assert model.instance == 0
    as_read(model.instances[0].channels, model.channels, "channels")
    assert "instance 1: 21.5..59.5 degC" in repr(model)


def test_every_instance_without_a_firmware(in_logs):
    cli("tcal", "fit", "heating.ulg", "--instance", "all", "--order", "2", "-o", "all.json", cwd=in_logs)
    model = imutherm.tcal_fit("heating.ulg", instance="all", order=2)
    assert model.to_json() == (in_logs / "all.json").read_text()
    # One instance asked for is a model of one sensor, as --instance 1.
    cli("tcal", "fit", "heating.ulg", "--instance", "1", "-o", "one.json", "--for", "px4", cwd=in_logs)
    one = imutherm.tcal_fit("heating.ulg", instance=1, firmware="px4")
    assert one.to_json() == (in_logs / "one.json").read_text()
    assert one.instances == {} and one.instance is None


@pytest.mark.parametrize("firmware", ["px4", "ardupilot"])
def test_export_is_the_one_file_of_tcal_export(in_logs, firmware):
    model = imutherm.tcal_fit(f"heating.{LOG[firmware]}", firmware=firmware)
    model.save(f"py_{firmware}.json")
    exported = cli("tcal", "export", f"py_{firmware}.json", "--firmware", firmware, cwd=in_logs)
    assert model.export(firmware) == exported.stdout.decode()
    text = model.export(firmware)
    if firmware == "px4":
        for n, (gyro_id, accel_id) in enumerate(flight_logs.IDS):
            assert f"\tTC_G{n}_ID\t{gyro_id}\t" in text and f"\tTC_A{n}_ID\t{accel_id}\t" in text
    else:
        assert "INS_TCAL1_ENABLE 1" in text and "INS_TCAL2_ENABLE 1" in text
    # Each instance goes to its own slot with the ids its log gave.
    with pytest.raises(imutherm.ImuthermError, match=r"holds instances \[0, 1\]"):
        model.export(firmware, instance=1)


@pytest.mark.parametrize("firmware", ["px4", "ardupilot"])
def test_evaluate_gives_the_command_line_document(in_logs, firmware):
    ext = LOG[firmware]
    model = imutherm.tcal_fit(f"heating.{ext}", firmware=firmware)
    model.save(f"m_{firmware}.json")
    params = f"m_{firmware}.{'params' if firmware == 'px4' else 'parm'}"
    (in_logs / params).write_text(model.export(firmware))
    # Every instance against the file as loaded, and one instance against
    # the exported file (each evaluation costs seconds: two cases only).
    cases = [(dict(export=firmware, params=params), ["--export", firmware, "--params", params]),
             (dict(export=firmware, instance=1), ["--export", firmware, "--instance", "1"])]
    docs = []
    for kwargs, flags in cases:
        printed = cli("tcal", "eval", "--json", *flags, f"m_{firmware}.json", f"cooling.{ext}",
                      cwd=in_logs)
        docs.append(model.evaluate(f"cooling.{ext}", **kwargs))
        same_fields(docs[-1], json.loads(printed.stdout), f"evaluate({kwargs})")
    doc = docs[0]
    assert {(r["instance"], r["held_out"]) for r in doc["rows"]} == {(0, True), (1, True)}
    assert [v["instance"] for v in doc["firmware"]["verdicts"]] == [0, 1]
    assert all(v["applies"] for v in doc["firmware"]["verdicts"])
    assert {r["instance"] for r in docs[1]["rows"]} == {1}
    # The file corrects each IMU on the held-out run as the model does.
    for r in doc["rows"]:
        assert r["bias_rms_as_loaded"] < 0.1 * r["bias_rms_before"], (r["instance"], r["channel"])


def test_the_repository_dataflash_log_of_two_imus(in_logs):
    """The fixture of two IMUs, 25 to 36 degC in 3 s, through the path the
    README shows (fit, export, eval as loaded): Python's model, file and
    document equal the command line's."""
    log = "arducopter_imu.bin"
    cli("tcal", "fit", log, "--for", "ardupilot", "-o", "vehicle.json", cwd=in_logs)
    cli("tcal", "export", "vehicle.json", "--firmware", "ardupilot", "-o", "vehicle.parm", cwd=in_logs)
    printed = cli("tcal", "eval", "--json", "vehicle.json", log, "--export", "ardupilot", "--params",
                  "vehicle.parm", cwd=in_logs)
    model = imutherm.tcal_fit(log, firmware="ardupilot")
    assert model.to_json() == (in_logs / "vehicle.json").read_text()
    assert sorted(model.instances) == [0, 1]
    model.name = "vehicle.json"
    assert model.export("ardupilot") == (in_logs / "vehicle.parm").read_text()
    doc = model.evaluate(log, export="ardupilot", params="vehicle.parm")
    same_fields(doc, json.loads(printed.stdout), "evaluate")
    assert [v["instance"] for v in doc["firmware"]["verdicts"]] == [0, 1]


def test_apply_takes_the_instance_read(in_logs):
    model = imutherm.tcal_fit("heating.ulg", firmware="px4")
    model.save("apply.json")
    cli("tcal", "apply", "apply.json", "cooling.ulg", "--instance", "1", "-o", "applied1.txt", cwd=in_logs)
    written = imutherm.read("applied1.txt")
    rec = imutherm.read("cooling.ulg", instance=1)
    for applied in (model.apply(rec), model.apply(rec, instance=1)):
        for name in model.instances[1].channels:
            np.testing.assert_array_equal(applied.channels[name], written.channels[name])
    # Instance 0's model on instance 1's data is another correction.
    other = model.apply(rec, instance=0)
    assert not np.array_equal(other.channels["gyro_x"], written.channels["gyro_x"])
    with pytest.raises(imutherm.ImuthermError, match=r"^instance=5: apply.json holds instances \[0, 1\]"):
        model.apply(rec, instance=5)


def test_refusals_name_the_keywords(in_logs, tmp_path):
    run = tmp_path / "run.csv"
    run.write_text("# sample_rate_hz: 10\ngyro_x,temp\n" +
                   "".join(f"{1e-3 * i},{20 + 0.01 * i}\n" for i in range(600)))
    with pytest.raises(imutherm.ImuthermError,
                       match=r"^instance='all': .*run.csv has no IMU instances"):
        imutherm.tcal_fit(run, instance="all")
    single = imutherm.tcal_fit(run, order=1)
    with pytest.raises(imutherm.ImuthermError,
                       match="^instance='all': model is the model of one sensor; give its instance number"):
        single.evaluate(run, instance="all")
    many = imutherm.tcal_fit("heating.bin", firmware="ardupilot")
    many.name = "two.json"
    with pytest.raises(imutherm.ImuthermError,
                       match=r"^two.json holds instances \[0, 1\]: give instance=N to compensate one"):
        many.apply(imutherm.read(run))
    with pytest.raises(imutherm.ImuthermError, match=r"^instance=3: two.json holds instances \[0, 1\]"):
        many.evaluate("cooling.bin", instance=3)
