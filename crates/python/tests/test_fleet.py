"""imutherm.fleet on a small simulated line (12 units, three planted bad
ones) on a LocalCluster: the table, the planted units flagged for the right
reason, a unit's numbers identical to the steps run by hand, a failing unit
as a row, a rerun that analyses only what changed, a worker killed
mid-run."""

import json
import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

pytest.importorskip("dask.distributed", reason="the fleet extra is not installed "
                    "(pip install 'imutherm[fleet]': dask[distributed], pyarrow)")
pytest.importorskip("pyarrow", reason="the fleet extra is not installed (pyarrow)")

import pyarrow.parquet as pq  # noqa: E402
from dask.distributed import Client, LocalCluster  # noqa: E402

import imutherm  # noqa: E402
from imutherm import fleet  # noqa: E402
from imutherm.fleet import limits as limits_mod, manifest, table  # noqa: E402

from fleet_support import PLANTED, write_fleet, write_unit  # noqa: E402

IDS = [f"U{i:02d}" for i in range(1, 13)]
QUIET = open(os.devnull, "w")


@pytest.fixture(scope="module")
def line(tmp_path_factory):
    return write_fleet(tmp_path_factory.mktemp("line"), IDS, held_out={"U05"})


@pytest.fixture(scope="module")
def client():
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as c:
        yield c


@pytest.fixture(scope="module")
def first_run(line, client, tmp_path_factory):
    out = tmp_path_factory.mktemp("out")
    result = fleet.run(line, line.parent / "limits.toml", out, client=client,
                       progress=fleet.Progress(len(IDS), QUIET))
    return out, result


def test_the_table_has_every_unit_and_channel_once(first_run):
    out, result = first_run
    rows = pq.read_table(out / "fleet.parquet").to_pylist()
    keys = [(r["unit"], r["channel"]) for r in rows]
    assert len(keys) == len(set(keys)) == 12 * 6
    assert {r["unit"] for r in rows} == set(IDS)
    assert result.counts["flagged"] == 3 and result.counts["errors"] == 0, result.counts
    for uid in IDS:
        assert (out / "units" / f"{uid}.tcal.json").exists()
        assert (out / "units" / f"{uid}.px4.params").exists()
        assert (out / "units" / f"{uid}.html").exists()
    assert not [f for f in os.listdir(out / "units") if f.endswith(".partial")]
    page = (out / "fleet.html").read_text(encoding="utf-8")
    for uid in PLANTED:
        assert f'href="units/{uid}.html"' in page


def test_planted_units_are_flagged_for_what_was_planted(first_run):
    _, result = first_run
    flagged = {r["unit"] for r in result.rows if r["flagged"]}
    assert flagged == set(PLANTED)
    why = lambda uid, ch: next(r["reasons"] for r in result.rows if r["unit"] == uid and r["channel"] == ch)
    assert "outlier: white_noise" in why("U03", "gyro_x")
    assert "outlier: tcal_slope" in why("U07", "accel_x")
    assert "dead axis" in why("U10", "gyro_z")
    # Out of limits first: the dead axis fails a limit, the others are outliers.
    ranks = {r["unit"]: r["rank"] for r in result.rows}
    assert ranks["U10"] == 1 and {ranks["U03"], ranks["U07"]} == {2, 3}


def test_a_units_numbers_are_the_steps_run_by_hand(first_run, line):
    out, result = first_run
    folder = line.parent
    static = imutherm.read(folder / "U05_static.txt")
    model = imutherm.tcal_fit([folder / "U05_thermal.txt"], firmware="px4")
    params = model.export("px4")
    (folder / "by_hand.params").write_text(params)
    held = model.evaluate(folder / "U05_held_out.txt", export="px4", params=folder / "by_hand.params")
    for ch in ("gyro_x", "accel_z"):
        row = next(r for r in result.rows if r["unit"] == "U05" and r["channel"] == ch)
        n = imutherm.noise_terms(static.channels[ch], rate=static.rate)["terms"]["white_noise"]
        assert row["white_noise"] == n["value"]
        assert (row["white_noise_lo"], row["white_noise_hi"]) == (n[n["how"]]["lo"], n[n["how"]]["hi"])
        assert row["tcal_residual_rms"] == model.channels[ch]["residual_rms"]
        assert row["tcal_coefficients"] == model.channels[ch]["coefficients"]
        ev = next(r for r in held["rows"] if r["channel"] == ch)
        assert row["held_out_bias_rms"] == ev["bias_rms_after"]
        assert row["held_out_bias_rms_as_loaded"] == ev["bias_rms_as_loaded"]
    assert json.loads((out / "units" / "U05.tcal.json").read_text())["channels"] == \
        json.loads(model.to_json())["channels"]
    assert (out / "units" / "U05.px4.params").read_text() == params


def test_a_rerun_analyses_only_what_changed(line, client, tmp_path):
    folder = line.parent
    out = tmp_path / "out"
    few = line.read_text().splitlines()[:4]  # header and 3 units
    (folder / "few.csv").write_text("\n".join(few) + "\n")
    args = dict(limits=folder / "limits.toml", out=out, client=client,
                progress=fleet.Progress(0, QUIET))
    first = fleet.run(folder / "few.csv", **args)
    assert first.counts["analysed"] == 3
    write_unit(folder, "U13")
    few.append(few[-1].replace("U03", "U13"))
    (folder / "few.csv").write_text("\n".join(few) + "\n")
    again = fleet.run(folder / "few.csv", **args)
    assert (again.counts["analysed"], again.counts["reused"]) == (1, 3)
    rows = pq.read_table(out / "fleet.parquet").to_pylist()
    assert sorted({r["unit"] for r in rows}) == ["U01", "U02", "U03", "U13"]
    # A changed setting or input changes the digest that decides.
    u = manifest.load(folder / "few.csv")[0]
    settings = {"rate": None, "order": "auto", "confidence": 0.95}
    assert {r["digest"] for r in rows if r["unit"] == u.id} == {table.unit_digest(u, settings)}
    assert table.unit_digest(u, {**settings, "order": 2}) != table.unit_digest(u, settings)
    moved = manifest.Unit(u.id, u.thermal[0], u.thermal)
    assert table.unit_digest(moved, settings) != table.unit_digest(u, settings)


def test_a_failing_unit_is_a_row_with_its_error(line, client, tmp_path):
    folder = line.parent
    (folder / "broken.txt").write_text("# sample_rate_hz: 20\nnot, a, log\n1, 2\n")
    text = line.read_text().splitlines()[:3]
    text.append("BAD,broken.txt,U01_thermal.txt,,,px4")
    (folder / "with_bad.csv").write_text("\n".join(text) + "\n")
    # Through the scheduler's address, as --scheduler tcp://... connects.
    result = fleet.run(folder / "with_bad.csv", folder / "limits.toml", tmp_path,
                       scheduler=client.scheduler.address, progress=fleet.Progress(0, QUIET))
    bad = [r for r in result.rows if r["unit"] == "BAD"]
    assert len(bad) == 1 and bad[0]["status"] == "error" and "broken.txt" in bad[0]["error"]
    assert result.rows[0]["unit"] != "BAD" or result.rows[0]["status"] == "error"
    assert {r["unit"] for r in result.rows if r["status"] != "error"} == {"U01", "U02"}


def test_a_killed_workers_unit_is_retried(line, tmp_path):
    """SIGKILL one of two workers while units run: the scheduler hands its
    task to the other (and the nanny restarts it); every unit is in the
    table exactly once."""
    # Six units without the held-out run: enough for a kill mid-run.
    no_held_out = "\n".join(",".join(f if i != 3 else "" for i, f in enumerate(l.split(",")))
                            if not l.startswith("unit") else l for l in line.read_text().splitlines()[:7])
    units = line.parent / "no_held_out.csv"
    units.write_text(no_held_out + "\n")
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as c:
        pids = c.run(os.getpid)
        done = []

        class Killer(fleet.Progress):
            def update(self):
                super().update()
                done.append(1)
                if len(done) == 2:
                    os.kill(next(iter(pids.values())), signal.SIGKILL)

        result = fleet.run(units, line.parent / "limits.toml", tmp_path, client=c,
                           progress=Killer(6, QUIET))
    rows = pq.read_table(tmp_path / "fleet.parquet").to_pylist()
    keys = [(r["unit"], r["channel"]) for r in rows]
    assert len(keys) == len(set(keys)) == 6 * 6
    assert not [r for r in rows if r["error"]]
    assert result.counts["analysed"] == 6 and len(done) == 6


def test_a_foreign_table_in_the_output_folder_is_left_alone(tmp_path, line):
    import pyarrow as pa

    pq.write_table(pa.table({"x": [1, 2]}), tmp_path / "fleet.parquet")
    before = (tmp_path / "fleet.parquet").read_bytes()
    with pytest.raises(fleet.FleetError, match="not written by imutherm-fleet"):
        fleet.run(line, line.parent / "limits.toml", tmp_path, client=object())
    (tmp_path / "other.parquet").write_bytes(b"not parquet")
    assert (tmp_path / "fleet.parquet").read_bytes() == before


def test_the_command_line_exit_codes(tmp_path):
    cmd = [sys.executable, "-m", "imutherm.fleet.cli"]
    usage = subprocess.run(cmd + ["units.csv"], capture_output=True, text=True)
    assert usage.returncode == 2 and "--limits" in usage.stderr
    (tmp_path / "l.toml").write_text("")
    missing = subprocess.run(cmd + [str(tmp_path / "none.csv"), "--limits", str(tmp_path / "l.toml"),
                                    "--out", str(tmp_path / "o")], capture_output=True, text=True)
    assert missing.returncode == 1 and "none.csv: no such manifest" in missing.stderr
    assert not (tmp_path / "o").exists()
