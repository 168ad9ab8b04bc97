"""The units of a fleet: a manifest (CSV or Parquet) or a directory.

A manifest has one row per unit; its columns (a header names them):

* ``unit`` -- the unit's id (a serial number), unique;
* ``static`` -- the static run the noise terms are read from;
* ``thermal`` -- the run(s) the temperature model is fitted on, ``;``
  between several;
* ``held_out`` -- optional: a run left out of the fit, evaluated;
* ``instance`` -- optional: the IMU instance(s) of a robot log, ``;``
  between several (each is fitted and exported on its own);
* ``firmware`` -- optional: ``px4`` or ``ardupilot`` (the run's default
  otherwise).

Relative paths are relative to the manifest's folder. A directory holds
one folder per unit (its name is the id) with files named ``static*``,
``thermal*`` and optionally ``held_out*``.

Ids are unique without regard to case: ``sn-0001`` and ``SN-0001`` would
name the same files on a file system that ignores case (macOS, Windows).
A CSV row with more fields than the header names is refused, naming the
fields, as a column shifted by a stray comma would be read wrongly.
"""

import csv
import os
import re
from dataclasses import dataclass, field
from typing import List, Optional

from .errors import FleetInputError

COLUMNS = ("unit", "static", "thermal", "held_out", "instance", "firmware")
FIRMWARE = ("px4", "ardupilot")
#: A unit id names its files: letters, digits, '.', '_', '-', not first a '.'.
ID = re.compile(r"[A-Za-z0-9_-][A-Za-z0-9._-]*")


@dataclass(frozen=True)
class Unit:
    """One unit and where its runs lie."""

    id: str
    static: str
    thermal: List[str]
    held_out: Optional[str] = None
    instances: List[Optional[int]] = field(default_factory=lambda: [None])
    firmware: Optional[str] = None


def load(source, default_firmware=None):
    """The units of ``source``: a manifest file or a directory of units."""
    source = os.fspath(source)
    if os.path.isdir(source):
        return _directory(source, default_firmware)
    if not os.path.exists(source):
        raise FleetInputError(f"{source}: no such manifest or directory")
    if source.lower().endswith(".parquet"):
        return _rows(source, _parquet_rows(source), default_firmware)
    with open(source, newline="", encoding="utf-8") as f:
        reader = csv.DictReader(f)
        rows = [(reader.line_num, r) for r in reader]
        header = reader.fieldnames or []
    _check_header(source, header)
    return _rows(source, rows, default_firmware)


def _parquet_rows(path):
    import pyarrow.parquet as pq

    table = pq.read_table(path)
    _check_header(path, table.column_names)
    # Row k of the table is "row k" in messages (no line numbers in Parquet).
    return [(k + 1, {c: ("" if v is None else str(v)) for c, v in r.items()})
            for k, r in enumerate(table.to_pylist())]


def _check_header(path, header):
    missing = [c for c in ("unit", "static", "thermal") if c not in header]
    if missing:
        raise FleetInputError(f"{path}: line 1: the manifest has no column {', '.join(missing)} "
                              f"(columns: {', '.join(COLUMNS)})")
    unknown = [c for c in header if c not in COLUMNS]
    if unknown:
        raise FleetInputError(f"{path}: line 1: unknown column {', '.join(unknown)} "
                              f"(columns: {', '.join(COLUMNS)})")


def _rows(path, rows, default_firmware):
    base = os.path.dirname(os.path.abspath(path))
    where = "row" if path.lower().endswith(".parquet") else "line"
    units, seen = [], {}
    for line, r in rows:
        at = f"{path}: {where} {line}"
        uid = (r.get("unit") or "").strip()
        if not uid:
            raise FleetInputError(f"{at}: no unit id")
        if not ID.fullmatch(uid):
            raise FleetInputError(f"{at}: unit id '{uid}': it names the unit's files, so only "
                                  f"letters, digits, '.', '_' and '-' (not first a '.')")
        extra = r.get(None)
        if extra:
            shown = ", ".join(f"'{v}'" for v in extra)
            raise FleetInputError(f"{at}: unit {uid}: {len(extra)} more field"
                                  f"{'s' if len(extra) > 1 else ''} than the header names: {shown} (columns: {', '.join(COLUMNS)})")
        key = uid.casefold()
        if key in seen:
            other, first = seen[key]
            same = "" if other == uid else f" as {other} (ids may not differ only in case)"
            raise FleetInputError(f"{at}: unit {uid} already on {where} {first}{same}")
        seen[key] = (uid, line)
        units.append(_unit(at, base, uid, r, default_firmware))
    if not units:
        raise FleetInputError(f"{path}: the manifest lists no unit")
    return units


def _paths(base, text):
    return [os.path.join(base, p.strip()) for p in (text or "").split(";") if p.strip()]


def _unit(at, base, uid, r, default_firmware):
    static = _paths(base, r.get("static"))
    if len(static) != 1:
        raise FleetInputError(f"{at}: unit {uid}: give one static run (found {len(static)})")
    thermal = _paths(base, r.get("thermal"))
    if not thermal:
        raise FleetInputError(f"{at}: unit {uid}: no thermal run")
    held = _paths(base, r.get("held_out"))
    if len(held) > 1:
        raise FleetInputError(f"{at}: unit {uid}: one held-out run at most (found {len(held)})")
    instances = []
    for s in (r.get("instance") or "").split(";"):
        if s.strip():
            try:
                instances.append(int(s))
            except ValueError:
                raise FleetInputError(f"{at}: unit {uid}: instance '{s.strip()}' is not a "
                                      f"whole number") from None
    firmware = (r.get("firmware") or "").strip().lower() or default_firmware
    if firmware is not None and firmware not in FIRMWARE:
        raise FleetInputError(f"{at}: unit {uid}: firmware '{firmware}': expected px4 or ardupilot")
    return Unit(uid, static[0], thermal, held[0] if held else None, instances or [None], firmware)


def _directory(root, default_firmware):
    units, seen = [], {}
    for name in sorted(os.listdir(root)):
        folder = os.path.join(root, name)
        if not os.path.isdir(folder):
            continue
        if name.casefold() in seen:
            raise FleetInputError(f"{folder}: unit {name}: the same id as {seen[name.casefold()]} "
                                  f"but for case (ids may not differ only in case)")
        seen[name.casefold()] = name
        files = sorted(os.listdir(folder))
        pick = lambda prefix: [os.path.join(folder, f) for f in files if f.startswith(prefix)]
        static, thermal, held = pick("static"), pick("thermal"), pick("held_out")
        at = f"{folder}"
        if len(static) != 1:
            raise FleetInputError(f"{at}: unit {name}: one file named static* expected "
                                  f"(found {len(static)})")
        if not thermal:
            raise FleetInputError(f"{at}: unit {name}: no file named thermal*")
        if len(held) > 1:
            raise FleetInputError(f"{at}: unit {name}: one file named held_out* at most")
        units.append(Unit(name, static[0], thermal, held[0] if held else None, [None],
                          default_firmware))
    if not units:
        raise FleetInputError(f"{root}: no unit folder (one folder per unit, holding static*, "
                              f"thermal* and optionally held_out*)")
    return units
