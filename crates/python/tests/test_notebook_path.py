"""What a notebook touches first: the version, the drop-in after a plain
import, the attributes the stubs promise, counts in the caller's samples,
and the argument forms NumPy users pass (a scalar tau, booleans)."""

import subprocess
import sys

import numpy as np
import pytest

import imutherm


def test_version_is_the_package_metadata():
    from importlib.metadata import version
    assert imutherm.__version__ == version("imutherm")


def test_allantools_after_a_plain_import():
    # A fresh interpreter: no earlier test has imported the submodule.
    code = "import imutherm; print(imutherm.allantools.oadev([0.0, 1.0, 3.0, 2.0])[1][0])"
    out = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True)
    assert float(out.stdout) > 0


def test_recording_attributes_the_stubs_declare():
    rec = imutherm.simulate(preset="white", duration=1, rate=10, seed=1)
    assert rec.out_of_range == 0
    assert rec.read_options == {}
    assert rec.timestamp_slots is None


@pytest.mark.parametrize("data_type,given", [("freq", 1), ("phase", 2)])
def test_too_short_counts_the_samples_given(data_type, given):
    with pytest.raises(imutherm.ImuthermError, match=f"the series has {given}$"):
        imutherm.oadev(np.ones(given), data_type=data_type)


def test_scalar_tau_is_a_list_of_one():
    y = np.random.default_rng(4).standard_normal(1000)
    c = imutherm.oadev(y, rate=10.0, taus=0.4)
    np.testing.assert_array_equal(c.taus, [0.4])
    assert c.devs[0] == imutherm.oadev(y, rate=10.0, taus=[0.4]).devs[0]


def test_booleans_are_zeros_and_ones():
    bits = np.random.default_rng(5).standard_normal(1000) > 0
    np.testing.assert_array_equal(imutherm.oadev(bits).devs, imutherm.oadev(bits.astype(float)).devs)
    np.testing.assert_array_equal(imutherm.allantools.adev(bits)[1],
                                  imutherm.allantools.adev(bits.astype(float))[1])


def test_the_notebook_extra_brings_what_the_notebook_imports():
    # Every module docs/notebook_example.py imports is the standard
    # library's, imutherm's own dependency, or in the `notebook` extra.
    import ast
    import pathlib
    import re
    root = pathlib.Path(__file__).resolve().parents[3]
    tree = ast.parse((root / "docs" / "notebook_example.py").read_text(encoding="utf-8"))
    imported = {a.name.split(".")[0] for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
    imported |= {n.module.split(".")[0] for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) and n.module}
    third_party = {m for m in imported if m not in sys.stdlib_module_names} - {"imutherm", "numpy"}
    text = (root / "docs" / "notebook_example.py").read_text(encoding="utf-8")
    if "to_pandas(" in text:
        third_party.add("pandas")  # imported by imutherm's to_pandas
    pyproject = (root / "crates" / "python" / "pyproject.toml").read_text(encoding="utf-8")
    extra = re.search(r'^notebook = \[(.*)\]$', pyproject, re.M)
    assert extra, "no notebook extra in pyproject.toml"
    listed = set(re.findall(r'"([A-Za-z0-9_.-]+)', extra.group(1)))
    assert third_party and third_party <= listed, (third_party, listed)
