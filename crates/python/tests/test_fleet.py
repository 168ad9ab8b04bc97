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
from imutherm.fleet import limits as limits_mod, manifest, screen, table  # noqa: E402

from fleet_support import PLANTED, cut_mid_line, write_fleet, write_unit  # noqa: E402

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
    # The histograms draw the limits; a unit page has its curves over the
    # fleet's band, with the limits.
    # (this line's limits lie far outside the fleet: named at the edges)
    assert "limit min 1e-06 ←" in page and "limit max 0.01 →" in page
    inside = fleet.page._histogram("white_noise", "gyro_x", [
        {"white_noise": v, "flagged": False, "si_unit": "rad/s"} for v in (1e-4, 2e-4, 3e-4)],
        (None, 2.5e-4))
    assert 'stroke-dasharray="4,3"><title>limit max 0.00025' in inside and "rad/√s" in inside
    unit_page = (out / "units" / "U03.html").read_text(encoding="utf-8")
    assert unit_page.count("OADEV</figcaption>") == 6 and "<polygon" in unit_page
    assert unit_page.count("compensation</figcaption>") == 12
    assert "white_noise_min = 1e-06 rad/√s" in unit_page


def test_planted_units_are_flagged_for_what_was_planted(first_run):
    _, result = first_run
    flagged = {r["unit"] for r in result.rows if r["flagged"]}
    assert flagged == set(PLANTED)
    why = lambda uid, ch: next(r["reasons"] for r in result.rows if r["unit"] == uid and r["channel"] == ch)
    assert "outlier: white_noise" in why("U03", "gyro_x")
    assert "outlier: tcal_slope" in why("U07", "accel_x")
    assert "dead axis" in why("U10", "gyro_z")
    # A dead axis has no noise terms, and no place in the fleet's spread.
    dead = next(r for r in result.rows if r["unit"] == "U10" and r["channel"] == "gyro_z")
    assert dead["white_noise"] is None and dead["white_noise_how"] == "dead"
    assert dead.get("z_white_noise") is None and dead.get("z_tcal_slope") is None
    assert "outlier" not in why("U10", "gyro_z")
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


CLI = [sys.executable, "-m", "imutherm.fleet.cli"]


def _comparable(rows):
    """A table's rows by unit and channel, the unit files named by their
    names alone (two output folders hold the same files)."""
    out = {}
    for r in rows:
        r = dict(r)
        for k in ("model_file", "params_file"):
            if r.get(k):
                r[k] = os.path.basename(r[k])
        out[(r["unit"], r["instance"], r["channel"])] = r
    return out


def _wait_for(predicate, proc, seconds=300):
    deadline = time.monotonic() + seconds
    while not predicate():
        assert proc.poll() is None, "the run ended before it could be stopped"
        assert time.monotonic() < deadline
        time.sleep(0.02)


def test_a_killed_driver_loses_no_finished_unit(line, client, first_run, tmp_path):
    """SIGKILL the driver mid-run: the units it committed stay; the rerun
    analyses only the others, removes the scratch a killed write leaves,
    and its table equals the undisturbed run's."""
    out = tmp_path / "out"
    journal = out / "rows"
    proc = subprocess.Popen(CLI + [str(line), "--limits", str(line.parent / "limits.toml"),
                                   "--out", str(out), "--scheduler", client.scheduler.address],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    committed = lambda: [n for n in os.listdir(journal) if n.endswith(".parquet")] \
        if journal.is_dir() else []
    _wait_for(lambda: len(committed()) >= 3, proc)
    proc.kill()
    proc.wait()
    kept = committed()
    assert 3 <= len(kept) < len(IDS) and not (out / "fleet.parquet").exists()
    (out / "fleet.parquet.4242.0badc0de.partial").write_bytes(b"half a table")
    (journal / "U99.parquet.4242.0badc0de.partial").write_bytes(b"half a unit")
    again = fleet.run(line, line.parent / "limits.toml", out, client=client,
                      progress=fleet.Progress(0, QUIET))
    assert (again.counts["analysed"], again.counts["reused"]) == (len(IDS) - len(kept), len(kept))
    assert not [p for p in out.rglob("*.partial")] and not committed()
    undisturbed = _comparable(pq.read_table(first_run[0] / "fleet.parquet").to_pylist())
    assert _comparable(pq.read_table(out / "fleet.parquet").to_pylist()) == undisturbed


def test_ctrl_c_keeps_the_finished_units_and_says_how_to_resume(line, tmp_path):
    """Ctrl-C at a terminal: SIGINT to the whole process group, the local
    cluster's workers included. The driver alone answers: it says what it
    kept and how to resume, exits 130, and nothing prints a traceback."""
    out = tmp_path / "out"
    proc = subprocess.Popen(CLI + [str(line), "--limits", str(line.parent / "limits.toml"),
                                   "--out", str(out), "--workers", "1"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)
    _wait_for(lambda: (out / "rows").is_dir() and any(
        n.endswith(".parquet") for n in os.listdir(out / "rows")), proc)
    os.killpg(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert "Traceback" not in err and "run the same command again" in err, err
    kept = {r["unit"] for r in pq.read_table(out / "fleet.parquet").to_pylist()}
    assert 1 <= len(kept) < len(IDS) and f"{len(kept)} of the manifest's {len(IDS)} units" in err


def test_two_manifests_into_one_out_and_an_explicit_prune(line, client, tmp_path):
    folder = line.parent
    text = line.read_text().splitlines()
    for name, lines in (("a.csv", text[1:3]), ("b.csv", text[3:5])):  # U01, U02 / U03, U04
        (folder / name).write_text("\n".join([text[0]] + lines) + "\n")
    args = dict(limits=folder / "limits.toml", out=tmp_path, client=client,
                progress=fleet.Progress(0, QUIET))
    fleet.run(folder / "a.csv", **args)
    both = fleet.run(folder / "b.csv", **args)
    assert (both.counts["analysed"], both.counts["earlier"], both.counts["table"]) == (2, 2, 4)
    rows = pq.read_table(tmp_path / "fleet.parquet").to_pylist()
    assert {r["unit"] for r in rows} == {"U01", "U02", "U03", "U04"}
    page = (tmp_path / "fleet.html").read_text(encoding="utf-8")
    assert "4 units:" in page
    pruned = fleet.run(folder / "b.csv", prune=True, **args)
    assert (pruned.counts["analysed"], pruned.counts["pruned"]) == (0, 2)
    assert {r["unit"] for r in pq.read_table(tmp_path / "fleet.parquet").to_pylist()} == {"U03", "U04"}
    assert sorted(p.name for p in (tmp_path / "units").iterdir() if p.name.startswith("U01")) == []


def test_a_truncated_thermal_run_and_a_short_static_run_fail(line, client, tmp_path):
    """Cut mid-line, as a full disk leaves a file: the reader's
    truncated_last_line is in the table and fails the unit, and so do the
    run checks of the limits; a limit that allows it lets it pass them."""
    folder = line.parent
    cut_mid_line(folder / "U01_thermal.txt", tmp_path / "cut_thermal.txt", 0.4)
    cut_mid_line(folder / "U02_static.txt", tmp_path / "short_static.txt", 140 / 300)
    (tmp_path / "units.csv").write_text(
        "unit,static,thermal\n"
        f"CUT-T,{folder / 'U01_static.txt'},cut_thermal.txt\n"
        f"SHORT-S,short_static.txt,{folder / 'U02_thermal.txt'}\n")
    (tmp_path / "limits.toml").write_text(
        "[run]\nstatic_duration_min = 250\nfit_range = [22, 68]\nrate_min = 19\n")
    result = fleet.run(tmp_path / "units.csv", tmp_path / "limits.toml", tmp_path / "out",
                       client=client, progress=fleet.Progress(0, QUIET))
    for uid, role, check in (("CUT-T", "thermal", "not covering 22–68 °C"),
                             ("SHORT-S", "static", "s < 250 s (limit)")):
        rows = [r for r in result.rows if r["unit"] == uid]
        assert len(rows) == 6 and {r["status"] for r in rows} == {"fail"}, rows[0]["reasons"]
        for r in rows:
            assert f"{role}:truncated_last_line" in r["problem_kinds"]
            assert f"reader: {role} " in r["reasons"] and "truncated_last_line" in r["reasons"]
            assert check in r["reasons"], r["reasons"]
    rejudged = screen.judge([dict(r) for r in result.rows],
                            limits_mod.parse({"run": {"allow": ["truncated_last_line"]}}))
    assert {r["status"] for r in rejudged} == {"pass"}


def test_every_numeric_column_has_its_unit_in_the_schema(first_run):
    import pyarrow as pa

    schema = pq.read_schema(first_run[0] / "fleet.parquet")
    numeric = [f for f in schema if pa.types.is_floating(f.type) or pa.types.is_integer(f.type)
               or (pa.types.is_list(f.type) and pa.types.is_floating(f.type.value_type))]
    assert len(numeric) > 30
    for f in numeric:
        assert f.metadata and b"unit" in f.metadata, f.name
    unit = lambda name, key=b"unit": schema.field(name).metadata[key].decode()
    assert (unit("white_noise", b"unit.rad/s"), unit("white_noise", b"unit.m/s^2")) == \
        ("rad/√s", "m/s/√s")
    assert (unit("tcal_slope", b"unit.rad/s"), unit("tcal_slope", b"unit.m/s^2")) == \
        ("rad/s/°C", "m/s^2/°C")
    assert unit("static_duration_s") == "s" and unit("tcal_t_min_c") == "°C"
    assert {r["si_unit"] for r in pq.read_table(first_run[0] / "fleet.parquet").to_pylist()} == \
        {"rad/s", "m/s^2"}
