"""The fleet's table: one Parquet file, one row per unit, instance and
channel, and what decides whether a unit needs analysing again."""

import hashlib
import json
import os

import imutherm

from .errors import FleetError
from .files import write_atomic

TABLE = "fleet.parquet"


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
    h.update(json.dumps({"version": imutherm.__version__, "settings": settings,
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
    """The rows of an earlier run's table, by unit id; empty without one."""
    path = os.path.join(out_dir, TABLE)
    if not os.path.exists(path):
        return {}
    import pyarrow.parquet as pq

    try:
        previous = pq.read_table(path)
    except (OSError, ValueError) as e:
        raise FleetError(f"{path}: not a table imutherm-fleet can read ({e}): move it, or "
                         f"choose another output folder") from None
    if not {"unit", "digest"} <= set(previous.column_names):
        raise FleetError(f"{path} exists and was not written by imutherm-fleet: move it, or "
                         f"choose another output folder")
    by_unit = {}
    for row in previous.to_pylist():
        by_unit.setdefault(row["unit"], []).append(row)
    return by_unit


def reusable(rows, digest):
    """Whether an earlier run's rows of a unit stand: same digest, no error."""
    return (digest is not None and rows and all(r.get("digest") == digest for r in rows)
            and not any(r.get("error") for r in rows))


def write(out_dir, rows):
    """Writes the table atomically; returns its path."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    path = os.path.join(out_dir, TABLE)
    table = pa.Table.from_pylist(rows, schema=_schema(rows))
    sink = pa.BufferOutputStream()
    pq.write_table(table, sink)
    write_atomic(path, sink.getvalue().to_pybytes())
    return path


def _schema(rows):
    """Column types fixed where a column may be all null (a fleet of one
    failing unit still writes numbers as doubles, not nulls)."""
    import pyarrow as pa

    names = []
    for r in rows:
        for k in r:
            if k not in names:
                names.append(k)
    fields = []
    for n in names:
        if n in ("instance", "samples", "tcal_order", "rank"):
            t = pa.int64()
        elif n in ("outlier", "flagged"):
            t = pa.bool_()
        elif n == "tcal_coefficients":
            t = pa.list_(pa.float64())
        elif n.endswith("_how") or n in _TEXT:
            t = pa.string()
        else:
            t = pa.float64()
        fields.append(pa.field(n, t))
    return pa.schema(fields)


_TEXT = {"unit", "channel", "si_unit", "static_file", "model_file", "params_file", "firmware",
         "error", "noise_error", "status", "reasons", "digest", "imutherm_version"}
