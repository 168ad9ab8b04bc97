"""``imutherm.fleet``: every unit of a production line through the same
steps a person runs by hand, on Dask distributed; one Parquet table, each
unit's model and firmware parameters, outliers flagged, a fleet page.

Needs the ``fleet`` extra (``pip install 'imutherm[fleet]'``: Dask
distributed and pyarrow)::

    from imutherm import fleet
    result = fleet.run("units.csv", limits="limits.toml", out="fleet_out")
    result.table            # the path of fleet.parquet
    result.counts           # units, analysed, reused, flagged, failed

``run(..., client=my_client)`` uses an existing ``dask.distributed.Client``;
``scheduler="tcp://host:8786"`` connects to a running cluster; otherwise a
``LocalCluster`` of ``workers`` processes. The command line is
``imutherm-fleet`` (see ``imutherm-fleet --help`` and docs/fleet.md).
"""

import os
from dataclasses import dataclass

from . import limits as limits_mod, manifest, page, screen, table
from .errors import FleetError, FleetInputError
from .manifest import Unit
from .dispatch import Progress, analyse, connect

__all__ = ["FleetError", "FleetInputError", "Progress", "Result", "Unit", "run"]


@dataclass
class Result:
    """What a fleet run wrote and counted."""

    table: str
    page: str
    rows: list
    counts: dict


def run(units, limits, out, client=None, scheduler=None, workers=None, firmware=None, rate=None,
        order="auto", confidence=0.95, progress=None):
    """Analyses every unit of ``units`` (a manifest path, a directory, or a
    list of :class:`Unit`) and writes ``out/fleet.parquet``,
    ``out/fleet.html`` and ``out/units/``. ``limits`` is a TOML file's path
    or a :class:`limits.Limits`. ``firmware`` is the export for units whose
    manifest row names none; ``rate``, ``order`` and ``confidence`` are
    :func:`imutherm.read`'s, :func:`imutherm.tcal_fit`'s and
    :func:`imutherm.noise_terms`'s. Units whose inputs and settings are
    unchanged since the last run into ``out`` are not analysed again."""
    if not isinstance(units, (list, tuple)):
        units = manifest.load(units, default_firmware=firmware)
    if isinstance(limits, (str, os.PathLike)):
        limits = limits_mod.load(limits)
    settings = {"rate": None if rate is None else float(rate),
                "order": order if order == "auto" else int(order),
                "confidence": float(confidence)}
    os.makedirs(out, exist_ok=True)
    with connect(client, scheduler, workers) as c:
        rows, counts = analyse(units, settings, out, c, progress)
    rows = screen.judge(rows, limits)
    path = table.write(out, rows)
    flagged = {r["unit"] for r in rows if r["flagged"]}
    counts.update(flagged=len(flagged),
                  failed=len({r["unit"] for r in rows if r["status"] in ("fail", "error")}),
                  errors=len({r["unit"] for r in rows if r["status"] == "error"}))
    html = page.write(out, rows, limits)
    return Result(path, html, rows, counts)
