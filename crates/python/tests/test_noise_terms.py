"""imutherm.noise_terms against `imutherm noise --json` on the same samples
written to a file, and against the closed form of white noise."""

import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

import imutherm

RATE = 100.0
SIGMA = 1e-3  # rad/s per sample: white noise of density N = SIGMA / sqrt(RATE)


@pytest.fixture(scope="module")
def gyro():
    return SIGMA * np.random.default_rng(3).standard_normal(100_000)


def cli_binary():
    if os.environ.get("IMUTHERM_BIN"):
        return Path(os.environ["IMUTHERM_BIN"])
    root = Path(__file__).resolve().parents[3]
    for profile in ("release", "debug"):
        path = root / "target" / profile / "imutherm"
        if path.exists():
            return path
    pytest.skip("no imutherm binary: cargo build --release -p imutherm (or set IMUTHERM_BIN)")


def test_white_noise_density_is_the_closed_form(gyro):
    white = imutherm.noise_terms(gyro, rate=RATE)["terms"]["white_noise"]
    assert white["how"] == "fit"
    assert white["fit"]["lo"] < SIGMA / np.sqrt(RATE) < white["fit"]["hi"]
    assert white["value"] == white["fit"]["value"]


def test_same_terms_as_the_command_line(gyro, tmp_path):
    path = tmp_path / "gyro.txt"
    # 17 significant digits: the file holds exactly the array's values.
    np.savetxt(path, gyro, fmt="%.17g", header="gyro_x[rad/s]", comments="")
    out = subprocess.run([str(cli_binary()), "noise", str(path), "--rate", str(RATE), "--json"],
                         check=True, capture_output=True, text=True).stdout
    channel = json.loads(out)["files"][0]["channels"][0]
    terms = imutherm.noise_terms(gyro, rate=RATE)["terms"]
    for cli in channel["fit"] + channel["slope"]:
        mine = terms[cli["name"]][cli["method"]]
        if cli["identified"]:
            for key in ("value", "lo", "hi"):
                assert mine[key] == pytest.approx(cli["si"][key], rel=1e-12), cli["name"]
        else:
            assert mine["value"] is None and mine["reason"] == cli["reason"], cli["name"]
    symbols = {v["symbol"]: v for v in terms.values()}
    for cli in channel["chosen"]:
        mine = symbols[cli["term"]]
        assert mine["how"] == cli["method"] and mine["note"] == cli["note"], cli["term"]
        assert mine["value"] == pytest.approx(cli["si"]["value"], rel=1e-12), cli["term"]


def cli_channels(tmp_path, columns, values, *extra):
    """`imutherm noise --json` on `values` (one column per name) at RATE."""
    path = tmp_path / "imu.txt"
    np.savetxt(path, np.column_stack(values), fmt="%.17g", delimiter=",",
               header=",".join(columns), comments="")
    out = subprocess.run([str(cli_binary()), "noise", str(path), "--rate", str(RATE), "--json", *extra],
                         check=True, capture_output=True, text=True).stdout
    return {c["name"]: c for c in json.loads(out)["files"][0]["channels"]}


def test_the_model_and_the_filters_are_the_command_lines(gyro, tmp_path):
    # The same serde types on both sides: equal field by field, number by number.
    channel = cli_channels(tmp_path, ["gyro_x[rad/s]"], [gyro])["gyro_x"]
    mine = imutherm.noise_terms(gyro, rate=RATE, quantity="angular_rate")
    assert mine["model"] == channel["model"]
    assert mine["state_space"] == channel["state_space"]
    assert mine["filters"] == channel["filters"]
    assert [f["filter"] for f in mine["filters"]] == ["px4_ekf2", "ardupilot_ekf3"]
    assert mine["verdict"] == "fits" and mine["model"]["label"] == "N"
    assert mine["model"]["defeat"] is None


def test_kalibr_values_are_the_yamls(gyro, tmp_path):
    accel = 0.05 * np.random.default_rng(4).standard_normal(gyro.size)
    yaml = tmp_path / "imu.yaml"
    cli_channels(tmp_path, ["gyro_x[rad/s]", "acc_x[m/s^2]"], [gyro, accel], "--kalibr", str(yaml))
    written = dict(line.split(": ", 1) for line in yaml.read_text().splitlines()
                   if line and not line.startswith("#") and ": " in line)
    for y, quantity in ((gyro, "angular_rate"), (accel, "acceleration")):
        for p in imutherm.noise_terms(y, rate=RATE, quantity=quantity)["kalibr"]:
            # One axis per sensor: the worst axis is this one.
            # The file's values carry 7 significant digits and a unit comment.
            value = float(written[p["name"]].split("#")[0])
            assert value == pytest.approx(p["value"], rel=1e-6), p["name"]


def test_kept_terms_have_values_and_dropped_ones_their_bounds(gyro):
    t = imutherm.noise_terms(gyro, rate=RATE)
    assert t["terms"]["white_noise"]["kept"]
    for name, term in t["terms"].items():
        assert term["kept"] == (term["fit"]["value"] is not None), name
        if not term["kept"]:
            assert term["how"] == "upper_bound" and term["value"] == term["bound"], name
    bounds = dict(t["model"]["bounds"])
    assert bounds["K"] == t["terms"]["rate_random_walk"]["bound"]
    assert t["filters"] is None and t["kalibr"] is None


def test_a_record_no_candidate_fits_says_so_and_holds_no_term():
    t = imutherm.noise_terms(np.random.default_rng(5).standard_normal(10), rate=RATE)
    assert t["verdict"] == "no_candidate_fits"
    assert t["model"]["label"] == "none" and t["model"]["p_value"] is None
    assert not any(term["kept"] for term in t["terms"].values())


def test_where_no_candidate_fits_the_verdict_names_the_tau():
    # A strong tone over white noise: no sum of noise processes describes it.
    rng = np.random.default_rng(11)
    k = np.arange(60_000)
    y = 1e-3 * rng.standard_normal(k.size) + 0.05 * np.sin(2 * np.pi * 0.7 * k / 100.0)
    t = imutherm.noise_terms(y, rate=100.0)
    d = t["model"]["defeat"]
    if t["verdict"] == "fits":
        assert d is None
        return
    assert d["tau"] > 0 and d["ratio"] > 0
    assert d["candidate"] and str(d["text"]).startswith(("the best candidate", d["candidate"]))


def test_an_unknown_sensor_is_refused(gyro):
    with pytest.raises(ValueError, match="angular_rate"):
        imutherm.noise_terms(gyro, rate=RATE, quantity="gyro")
