"""imutherm.fleet's inputs and its screen, which need neither Dask nor
pyarrow: manifests and limits refused with file and line, and the robust
z-score's laws."""

import numpy as np
import pytest

from imutherm import fleet
from imutherm.fleet import limits as limits_mod, manifest, screen


def test_bad_manifests_and_limits_name_file_and_line(tmp_path):
    m = tmp_path / "m.csv"
    for text, says in [("unit,static\nA,a.txt\n", "line 1: the manifest has no column thermal"),
                       ("unit,static,thermal,colour\n", "unknown column colour"),
                       ("unit,static,thermal\nA,a,b\nA,c,d\n", "line 3: unit A already on line 2"),
                       ("unit,static,thermal\n../x,a,b\n", "line 2: unit id '../x'"),
                       ("unit,static,thermal,firmware\nA,a,b,betaflight\n", "firmware 'betaflight'"),
                       ("unit,static,thermal\nA,a;b,c\n", "one static run"),
                       ("unit,static,thermal\nA,a,b,c,d\n",
                        "line 2: unit A: 2 more fields than the header names: 'c', 'd'"),
                       ("unit,static,thermal\nsn-0001,a,b\nSN-0001,c,d\n",
                        "line 3: unit SN-0001 already on line 2 as sn-0001")]:
        m.write_text(text)
        with pytest.raises(fleet.FleetInputError, match=says.replace("(", r"\(")):
            manifest.load(m)
    lim = tmp_path / "l.toml"
    for text, says in [("[gyro]\nwhite_nose_max = 1\n", r"\[gyro\] white_nose_max"),
                       ("[gyro]\nwhite_noise_max = 'a'\n", "expected a number"),
                       ("[mag]\n", r"\[mag\]"), ("[outliers]\nz_max = 0\n", "above 0"),
                       ("[gyro\n", "l.toml"),
                       ("[run]\nstatic_duration_min = -1\n", r"\[run\] static_duration_min"),
                       ("[run]\nfit_range = [70, 20]\n", "low below high"),
                       ("[run]\nallow = 'nan'\n", "list of problem kinds"),
                       ("[run]\nduration_min = 3\n", r"\[run\] duration_min: expected one of")]:
        lim.write_text(text)
        with pytest.raises(fleet.FleetInputError, match=says):
            limits_mod.load(lim)


def test_a_directory_of_units(tmp_path):
    for uid in ("B", "A"):
        (tmp_path / uid).mkdir()
        for f in ("static.txt", "thermal_1.txt", "thermal_2.txt"):
            (tmp_path / uid / f).write_text("")
    units = manifest.load(tmp_path, default_firmware="ardupilot")
    assert [u.id for u in units] == ["A", "B"]
    assert [p.rsplit("/", 1)[1] for p in units[0].thermal] == ["thermal_1.txt", "thermal_2.txt"]
    assert units[0].held_out is None and units[0].firmware == "ardupilot"
    (tmp_path / "A" / "static_2.txt").write_text("")
    with pytest.raises(fleet.FleetInputError, match="one file named static"):
        manifest.load(tmp_path)
    (tmp_path / "A" / "static_2.txt").unlink()
    (tmp_path / "a").mkdir()
    with pytest.raises(fleet.FleetInputError, match="unit a: the same id as A but for case"):
        manifest.load(tmp_path)


def test_the_run_checks_and_what_the_limits_allow():
    row = {"unit": "U", "channel": "gyro_x", "si_unit": "rad/s", "static_duration_s": 100.0,
           "static_rate_hz": 20.0, "thermal_duration_s": 1200.0, "thermal_rate_hz": 20.0,
           "tcal_t_min_c": 20.0, "tcal_t_max_c": 42.0, "tcal_slope": 3e-3,
           "problems": ["thermal t.txt line 9: time_gap: 3 samples missing"],
           "problem_kinds": ["thermal:time_gap"]}
    judge = lambda doc: screen.judge([dict(row)], limits_mod.parse(doc))[0]
    r = judge({})
    assert r["status"] == "fail" and r["reasons"] == "reader: " + row["problems"][0]
    assert judge({"run": {"allow": ["time_gap"]}})["status"] == "pass"
    assert judge({"run": {"allow": ["thermal:time_gap"]}})["status"] == "pass"
    assert judge({"run": {"allow": ["static:time_gap"]}})["status"] == "fail"
    # Each problem judged by its own kind: one allowed leaves the other.
    two = dict(row, problems=row["problems"] + ["static s.txt line 4: nan: 2 NaN samples"],
               problem_kinds=row["problem_kinds"] + ["static:nan"])
    r = screen.judge([two], limits_mod.parse({"run": {"allow": ["time_gap"]}}))[0]
    assert r["status"] == "fail" and r["reasons"] == "reader: static s.txt line 4: nan: 2 NaN samples"
    r = judge({"run": {"allow": ["time_gap"], "static_duration_min": 300, "rate_min": 50,
                       "temperature_span_min": 40, "fit_range": [20, 70]},
               "gyro": {"tcal_slope_max": 1e-3}})
    for says in ("static run 100 s < 300 s", "static run's rate 20 Hz < 50 Hz",
                 "thermal run's rate 20 Hz < 50 Hz", "fitted over 22 °C < 40 °C",
                 "fitted over 20.0–42.0 °C, not covering 20–70 °C",
                 "tcal_slope 0.003 > 0.001 rad/s/°C"):
        assert says in r["reasons"], r["reasons"]


def test_nothing_is_written_when_the_cluster_does_not_answer(tmp_path, monkeypatch):
    pytest.importorskip("dask.distributed")
    from imutherm.fleet import dispatch

    monkeypatch.setattr(dispatch, "CONNECT_TIMEOUT", "1s")
    (tmp_path / "m.csv").write_text("unit,static,thermal\nA,a.txt,b.txt\n")
    (tmp_path / "l.toml").write_text("")
    with pytest.raises(fleet.FleetError, match="cannot reach the Dask scheduler"):
        fleet.run(tmp_path / "m.csv", tmp_path / "l.toml", tmp_path / "out",
                  scheduler="tcp://127.0.0.1:9")
    assert not (tmp_path / "out").exists()


def test_robust_z_is_unmoved_by_shift_and_scale_and_by_the_outlier_itself():
    rng = np.random.default_rng(4)
    for _ in range(50):
        x = rng.normal(size=rng.integers(5, 60))
        z = screen.robust_z(x)
        a, b = rng.uniform(0.1, 10), rng.uniform(-5, 5)
        np.testing.assert_allclose(screen.robust_z(a * x + b), z, rtol=1e-9, atol=1e-9)
        # Moving the value farthest from the median further out moves only
        # its own z: the median and the MAD hold (the screen relies on it).
        y = x.copy()
        k = int(np.argmax(np.abs(y - np.median(y))))
        y[k] += 100.0 * np.sign(y[k] - np.median(y))
        zy = screen.robust_z(y)
        np.testing.assert_allclose(np.delete(zy, k), np.delete(z, k), rtol=1e-9, atol=1e-9)
        assert abs(zy[k]) > abs(z[k])
    assert np.isnan(screen.robust_z([1.0, 2.0, 3.0])).all()  # too few units
    assert np.isnan(screen.robust_z([2.0] * 9)).all()        # no spread


def test_the_screen_ranks_out_of_limits_before_outliers():
    rows = [{"unit": f"U{i}", "channel": "gyro_x", "si_unit": "rad/s", "samples": 10,
             "static_spread": 1.0, "white_noise": 1e-4 * (1 + 0.01 * i)} for i in range(10)]
    rows[3]["white_noise"] = 5e-4            # an outlier, within the limit
    rows[7]["white_noise"] = 2.5e-3          # beyond the limit
    rows[7]["static_spread"] = 0.0           # and dead
    rows.append({"unit": "U10", "channel": None, "error": "OSError: gone"})
    lim = limits_mod.parse({"gyro": {"white_noise_max": 2e-3}, "outliers": {"terms": ["white_noise"]}})
    out = screen.judge(rows, lim)
    assert [r["unit"] for r in out[:3]] == ["U7", "U10", "U3"]
    assert [r["status"] for r in out[:3]] == ["fail", "error", "outlier"]
    assert "dead axis" in out[0]["reasons"] and "white_noise 0.0025 > 0.002" in out[0]["reasons"]
    assert out[2]["reasons"].startswith("outlier: white_noise")
    assert all(r["status"] == "pass" for r in out[3:])


def test_a_unit_runs_with_the_gil_released(tmp_path):
    """A fleet worker's threads share one interpreter: every imutherm call
    of a unit (read, noise terms, fit, export, evaluation) releases the GIL,
    so the interpreter's other threads keep running throughout."""
    import threading
    import time

    from fleet_support import write_unit
    from imutherm.fleet import unit as unit_mod

    p = write_unit(tmp_path, "G1", held_out=True)
    u = manifest.Unit("G1", str(p["static"]), [str(p["thermal"])], str(p["held_out"]),
                      firmware="px4")
    settings = {"rate": None, "order": "auto", "confidence": 0.95}
    ticks, rows, done = [], [], threading.Event()

    def work():
        rows.extend(unit_mod.analyse(u, settings, str(tmp_path / "out")))
        done.set()

    worker = threading.Thread(target=work)
    start = time.perf_counter()
    worker.start()
    while not done.is_set():
        ticks.append(time.perf_counter())
        time.sleep(0.001)
    worker.join()
    took = time.perf_counter() - start
    assert len(rows) == 6 and not rows[0]["error"] and rows[0]["held_out_bias_rms"] is not None
    assert took > 0.05 and len(ticks) >= 5
    # Held through a call, the GIL would stop this loop for all of it.
    assert max(np.diff(ticks)) < took / 4


def test_outputs_are_readable_as_open_would_make_them(tmp_path):
    import os

    from imutherm.fleet.files import remove_scratch, write_atomic

    old = os.umask(0o022)
    try:
        write_atomic(tmp_path / "a.json", "{}")
    finally:
        os.umask(old)
    assert (tmp_path / "a.json").read_text() == "{}"
    assert oct((tmp_path / "a.json").stat().st_mode & 0o777) == oct(0o644)
    (tmp_path / "b.json.1.ab.partial").write_text("half")
    assert remove_scratch(tmp_path) == 1 and sorted(os.listdir(tmp_path)) == ["a.json"]
