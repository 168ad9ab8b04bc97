"""The compensation from Python against the command line: the model file,
the evaluation and the parameter files equal the CLI's golden files
(crates/cli/tests/golden, written by `imutherm tcal` on the runs
golden_cli.rs simulates), and a fit on a synthetic run recovers the bias
put in."""

import json
import os
import pathlib
import subprocess

import numpy as np
import pytest

import imutherm

GOLDEN = pathlib.Path(__file__).resolve().parents[2] / "cli" / "tests" / "golden"
needs_cli = pytest.mark.skipif("IMUTHERM_BIN" not in os.environ,
                               reason="IMUTHERM_BIN names no command line to simulate the runs")


def cli(*args, cwd):
    return subprocess.run([os.environ["IMUTHERM_BIN"], *args], cwd=cwd, check=True,
                          capture_output=True).stdout


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """golden_cli.rs's runs: thesis preset, 600 s at 20 Hz, fixed seeds."""
    if "IMUTHERM_BIN" not in os.environ:
        pytest.skip("IMUTHERM_BIN names no command line to simulate the runs")
    d = tmp_path_factory.mktemp("runs")
    for profile, seed, name in [("cooling:80:20:300", "3", "cool.txt"),
                                ("ramp:25:45:300", "5", "ramp.txt")]:
        cli("simulate", "--profile", profile, "--duration", "600", "--rate", "20", "--seed", seed,
            "-o", name, cwd=d)
    return d


@pytest.fixture
def in_runs(runs, monkeypatch):
    # The golden files name the runs relatively, as the command ran in their
    # directory.
    monkeypatch.chdir(runs)
    return runs


@needs_cli
def test_fit_writes_the_golden_model_file(in_runs):
    model = imutherm.tcal_fit(["cool.txt"], firmware="px4")
    golden = (GOLDEN / "tcal_model.json").read_text()
    assert model.to_json() == golden
    model.save("py_model.json")
    assert pathlib.Path("py_model.json").read_bytes() == (GOLDEN / "tcal_model.json").read_bytes()


@needs_cli
def test_evaluate_gives_the_golden_document(in_runs):
    pathlib.Path("model.json").write_text((GOLDEN / "tcal_model.json").read_text())
    model = imutherm.TcalModel.load("model.json")
    assert model.evaluate("ramp.txt") == json.loads((GOLDEN / "tcal_eval.json").read_text())
    live = json.loads(cli("tcal", "eval", "--json", "--export", "ardupilot", "model.json",
                          "ramp.txt", "cool.txt", cwd=in_runs))
    assert model.evaluate(["ramp.txt", "cool.txt"], export="ardupilot") == live


@needs_cli
def test_export_gives_the_golden_parameter_files(in_runs):
    model = imutherm.TcalModel((GOLDEN / "tcal_model.json").read_text())
    assert model.export("px4") == (GOLDEN / "tcal_export_px4.params").read_text()
    # The file names the command line's --device-id (it is the same file
    # from both); the warnings name the keyword argument.
    placeholders = [w for w in model.export_warnings if "is a placeholder" in w]
    assert placeholders and all(w.endswith("export with device_id") for w in placeholders)
    assert model.export("ardupilot", instance=2) == (GOLDEN / "tcal_export_ardupilot.parm").read_text()


@needs_cli
def test_apply_gives_what_tcal_apply_writes(in_runs):
    pathlib.Path("model.json").write_text((GOLDEN / "tcal_model.json").read_text())
    cli("tcal", "apply", "model.json", "ramp.txt", "-o", "ramp_comp.txt", cwd=in_runs)
    written = imutherm.read("ramp_comp.txt")
    model = imutherm.TcalModel.load("model.json")
    applied = model.apply(imutherm.read("ramp.txt"))
    for name, data in written.channels.items():
        np.testing.assert_array_equal(applied.channels[name], data)
    assert applied.out_of_range > 0  # the ramp leaves the cooling run's range


@pytest.fixture
def synthetic(tmp_path):
    """A 4000-sample heating run at 10 Hz whose gyro bias is a known
    quadratic of the temperature, with 1e-5 rad/s white noise."""
    rng = np.random.default_rng(42)
    t = np.linspace(20.0, 60.0, 4000)
    bias = 1e-4 * (t - 40.0) ** 2 + 2e-4 * (t - 40.0) + 3e-3
    gyro = bias + 1e-5 * rng.standard_normal(t.size)
    path = tmp_path / "heat.csv"
    with open(path, "w") as f:
        f.write("# sample_rate_hz: 10\ngyro_x,temp\n")
        for g, c in zip(gyro, t):
            f.write(f"{float(g)!r},{float(c)!r}\n")
    return path, t, bias, gyro


def test_fit_recovers_a_known_bias(synthetic):
    path, t, bias, gyro = synthetic
    model = imutherm.tcal_fit(path, order=2, tref=40.0)
    assert model.channels["gyro_x"]["order"] == 2
    assert model.t_ref == 40.0
    applied = model.apply(imutherm.read(path))
    comp = applied.channels["gyro_x"]
    # The fitted range is the data's own, so the run the model was fitted on
    # has no sample out of range. What is left is the bias at T_ref (3e-3)
    # plus the noise: the fit solves the samples' own normal equations (bins
    # keep their samples' sums of products), so the bins' width adds no error
    # of its own; the bound is the one a 1 degC bin-mean fit met, a*w^2/12.
    assert model.t_min == pytest.approx(t.min()) and model.t_max == pytest.approx(t.max())
    inside = (t >= model.t_min) & (t <= model.t_max)
    assert applied.out_of_range == np.count_nonzero(~inside) == 0
    np.testing.assert_allclose((comp - (gyro - bias))[inside], 3e-3, atol=1e-4 * 1.0**2 / 12)
    row = model.evaluate(path)["rows"][0]
    assert row["held_out"] is False
    assert row["bias_rms_after"] < 1e-2 * row["bias_rms_before"]


def test_refusals_carry_the_command_line_messages_naming_keywords(synthetic):
    path = synthetic[0]
    with pytest.raises(imutherm.ImuthermError,
                       match=r"^order=4 firmware='px4': PX4 evaluates a cubic at most \(order=3 or 'auto'\)"):
        imutherm.tcal_fit(path, order=4, firmware="px4")
    with pytest.raises(imutherm.ImuthermError, match="are the same recording: give each run once"):
        imutherm.tcal_fit([path, path])
    model = imutherm.tcal_fit(path, order=2)
    with pytest.raises(imutherm.ImuthermError, match="^instance=7: PX4 has calibration instances 0 to 3"):
        model.export("px4", instance=7)
    with pytest.raises(imutherm.ImuthermError, match=r"^bin_width=0.001: bins over"):
        imutherm.tcal_fit(path, bin_width=0.001)
    with pytest.raises(FileNotFoundError):
        imutherm.tcal_fit(path.parent / "missing.csv")


def test_recordings_bring_the_options_they_were_read_with(synthetic):
    path = synthetic[0]
    in_deg = {"gyro_x": "deg/s"}
    rec = imutherm.read(path, units=in_deg)
    from_recording = imutherm.tcal_fit(rec, order=2).to_json()
    assert from_recording == imutherm.tcal_fit(path, order=2, units=in_deg).to_json()
    assert from_recording != imutherm.tcal_fit(path, order=2).to_json()
    with pytest.raises(ValueError, match="read with different options"):
        imutherm.tcal_fit([rec, imutherm.read(path)])
