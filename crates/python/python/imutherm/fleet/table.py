"""The fleet's table: one Parquet file, one row per unit, instance and
channel; each unit's rows committed as the unit finishes; and what decides
whether a unit needs analysing again.

A finished unit's rows go at once to ``rows/<id>.parquet`` (a journal,
written by rename): a run stopped in any way (Ctrl-C, a killed driver, a
power cut) keeps every unit it finished, and the next run reads the
journal before deciding what to analyse. A run that completes folds the
journal into ``fleet.parquet`` and empties it.
"""

import hashlib
import json
import os

import imutherm

from . import units as units_mod
from .errors import FleetError
from .files import remove_scratch, write_atomic

TABLE = "fleet.parquet"
JOURNAL = "rows"
#: The layout of a unit's rows: part of the digest, so that a table
#: written by an imutherm-fleet whose rows lack columns is analysed again.
ROWS_VERSION = 2


def file_digest(path, chunk=1 << 20):
    """SHA-256 of a file's bytes, read in chunks (a run may be gigabytes)."""
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(chunk), b""):
            h.update(block)
    return h.hexdigest()


def unit_digest(unit, settings):
    """What the unit's rows depend on: its inputs' bytes, how they are
    analysed, and the imutherm that analyses them. A file that cannot be
    read gives no digest: the unit is analysed and its row says why."""
    h = hashlib.sha256()
    h.update(json.dumps({"version": imutherm.__version__, "rows": ROWS_VERSION, "settings": settings,
                         "instances": unit.instances, "firmware": unit.firmware},
                        sort_keys=True).encode())
    for role, paths in (("static", [unit.static]), ("thermal", unit.thermal),
                        ("held_out", [unit.held_out] if unit.held_out else [])):
        for p in paths:
            try:
                h.update(f"{role}:{file_digest(p)}".encode())
            except OSError:
                return None
    return h.hexdigest()


def previous_rows(out_dir):
    """The rows of the units earlier runs into ``out_dir`` finished, by
    unit id: the table's, and over them the journal's (units committed
    after the table was last written); empty without either."""
    by_unit = {}
    path = os.path.join(out_dir, TABLE)
    if os.path.exists(path):
        by_unit.update(_read(path, "move it, or choose another output folder"))
    folder = os.path.join(out_dir, JOURNAL)
    if os.path.isdir(folder):
        for name in sorted(os.listdir(folder)):
            if name.endswith(".parquet"):
                by_unit.update(_read(os.path.join(folder, name), "remove it"))
    return by_unit


def _read(path, advice):
    import pyarrow.parquet as pq

    try:
        previous = pq.read_table(path)
    except (OSError, ValueError) as e:
        raise FleetError(f"{path}: not a table imutherm-fleet can read ({e}): {advice}") from None
    if not {"unit", "digest"} <= set(previous.column_names):
        raise FleetError(f"{path} exists and was not written by imutherm-fleet: {advice}")
    by_unit = {}
    for row in previous.to_pylist():
        by_unit.setdefault(row["unit"], []).append(row)
    return by_unit


def remove_leftovers(out_dir):
    """Removes the scratch files a stopped run left in ``out_dir``, its
    journal and its ``units/``; returns how many."""
    return sum(remove_scratch(os.path.join(out_dir, d)) for d in ("", JOURNAL, "units"))


def commit(out_dir, uid, rows):
    """Writes one finished unit's rows to the journal (by rename: a unit
    is committed whole or not at all)."""
    _write(os.path.join(out_dir, JOURNAL, f"{uid}.parquet"), rows)


def forget(out_dir, uids):
    """Removes units' journal entries (pruned, or folded into the table)."""
    for uid in uids:
        try:
            os.unlink(os.path.join(out_dir, JOURNAL, f"{uid}.parquet"))
        except FileNotFoundError:
            pass


def journal_units(out_dir):
    """The ids the journal holds."""
    folder = os.path.join(out_dir, JOURNAL)
    if not os.path.isdir(folder):
        return []
    return [n[: -len(".parquet")] for n in os.listdir(folder) if n.endswith(".parquet")]


def reusable(rows, digest):
    """Whether an earlier run's rows of a unit stand: same digest, no error."""
    return (digest is not None and rows and all(r.get("digest") == digest for r in rows)
            and not any(r.get("error") for r in rows))


def write(out_dir, rows):
    """Writes the table atomically; returns its path."""
    path = os.path.join(out_dir, TABLE)
    _write(path, rows)
    return path


def _write(path, rows):
    import pyarrow as pa
    import pyarrow.parquet as pq

    table = pa.Table.from_pylist(rows, schema=_schema(rows))
    sink = pa.BufferOutputStream()
    pq.write_table(table, sink)
    write_atomic(path, sink.getvalue().to_pybytes())


def _schema(rows):
    """Column types fixed where a column may be all null (a fleet of one
    failing unit still writes numbers as doubles, not nulls), each numeric
    column's unit in its field metadata (:mod:`.units`), and the columns
    in one order whatever order the rows came in."""
    import pyarrow as pa

    names = []
    for r in rows:
        for k in r:
            if k not in names:
                names.append(k)
    names.sort(key=_position)
    fields = []
    for n in names:
        if n in ("instance", "samples", "tcal_order", "rank"):
            t = pa.int64()
        elif n in ("outlier", "flagged"):
            t = pa.bool_()
        elif n in _LISTS:
            t = pa.list_(pa.float64())
        elif n in ("problems", "problem_kinds"):
            t = pa.list_(pa.string())
        elif n.endswith("_how") or n in _TEXT:
            t = pa.string()
        else:
            t = pa.float64()
        fields.append(pa.field(n, t, metadata=units_mod.metadata(n)))
    return pa.schema(fields)


_LISTS = {"tcal_coefficients", "adev_tau_s", "adev", "bias_t_c", "bias_before", "bias_after"}
#: The columns of a full row: those of the first tables in their order
#: (the robust z-scores between ``reasons`` and ``status``), then the ones
#: added since, so that a script reading columns by position still works.
_COLUMNS = (
    "unit", "instance", "channel", "si_unit", "static_file", "samples", "model_file",
    "params_file", "firmware", "error", "static_spread", "noise_error",
    "white_noise", "white_noise_lo", "white_noise_hi", "white_noise_how",
    "bias_instability", "bias_instability_lo", "bias_instability_hi", "bias_instability_how",
    "rate_random_walk", "rate_random_walk_lo", "rate_random_walk_hi", "rate_random_walk_how",
    "tcal_order", "tcal_coefficients", "tcal_centre_c", "tcal_scale_c", "tcal_t_ref_c",
    "tcal_t_min_c", "tcal_t_max_c", "tcal_slope", "tcal_residual_rms",
    "held_out_bias_rms_before", "held_out_bias_rms", "held_out_bias_rms_as_loaded",
    "digest", "reasons", "z_", "status", "outlier", "flagged", "rank",
    # Added with the run checks, the journal and the unit page's plots.
    "static_duration_s", "static_rate_hz", "thermal_duration_s", "thermal_rate_hz",
    "thermal_t_low_c", "thermal_t_high_c", "problems", "problem_kinds", "adev_tau_s", "adev",
    "bias_t_c", "bias_before", "bias_after")
_ORDER = {n: i for i, n in enumerate(_COLUMNS)}


def _position(name):
    return (_ORDER["z_"] if name.startswith("z_") else _ORDER.get(name, len(_ORDER)), name)


_TEXT = {"unit", "channel", "si_unit", "static_file", "model_file", "params_file", "firmware",
         "error", "noise_error", "status", "reasons", "digest", "imutherm_version"}
