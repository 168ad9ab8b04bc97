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
