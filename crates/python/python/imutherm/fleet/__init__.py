"""``imutherm.fleet``: every unit of a production line through the same
steps a person runs by hand, on Dask distributed; one Parquet table, each
unit's model and firmware parameters, outliers flagged, a fleet page.

Needs the ``fleet`` extra (``pip install 'imutherm[fleet]'``: Dask
distributed and pyarrow)::

    from imutherm import fleet
    result = fleet.run("units.csv", limits="limits.toml", out="fleet_out")
    result.table            # the path of fleet.parquet
    result.counts           # units, analysed, reused, flagged, failed, table, earlier, ...

``run(..., client=my_client)`` uses an existing ``dask.distributed.Client``;
``scheduler="tcp://host:8786"`` connects to a running cluster; otherwise a
``LocalCluster`` of ``workers`` processes. The command line is
``imutherm-fleet`` (see ``imutherm-fleet --help`` and docs/fleet.md).
"""

import os
from dataclasses import dataclass

from . import limits as limits_mod, manifest, page, screen, table
from .errors import FleetError, FleetInputError, Interrupted
from .manifest import Unit
from .dispatch import Progress, analyse, connect

__all__ = ["FleetError", "FleetInputError", "Interrupted", "Progress", "Result", "Unit", "run"]


@dataclass
class Result:
    """What a fleet run wrote and counted."""

    table: str
    page: str
    rows: list
    counts: dict


def run(units, limits, out, client=None, scheduler=None, workers=None, firmware=None, rate=None,
        order="auto", confidence=0.95, progress=None, prune=False):
    """Analyses every unit of ``units`` (a manifest path, a directory, or a
    list of :class:`Unit`) into ``out``: ``out/fleet.parquet``,
    ``out/fleet.html`` and ``out/units/``. ``limits`` is a TOML file's path
    or a :class:`limits.Limits`. ``firmware`` is the export for units whose
    manifest row names none; ``rate``, ``order`` and ``confidence`` are
    :func:`imutherm.read`'s, :func:`imutherm.tcal_fit`'s and
    :func:`imutherm.noise_terms`'s.

    The table accumulates: units earlier runs put into ``out`` stay in it
    (and in the fleet page and the outlier screen) unless ``prune``, which
    removes those this manifest does not list. A unit whose inputs and
    settings are unchanged since it was analysed is not analysed again;
    each unit is committed as it finishes, so a run stopped in any way
    loses none that finished. A Ctrl-C writes the table of the units
    finished and raises :class:`Interrupted`."""
    if not isinstance(units, (list, tuple)):
        units = manifest.load(units, default_firmware=firmware)
    if isinstance(limits, (str, os.PathLike)):
        limits = limits_mod.load(limits)
    settings = {"rate": None if rate is None else float(rate),
                "order": order if order == "auto" else int(order),
                "confidence": float(confidence)}
    with connect(client, scheduler, workers) as c:
        # Only once the cluster answers: a run that cannot start leaves
        # nothing behind.
        os.makedirs(out, exist_ok=True)
        rows, counts = analyse(units, settings, out, c, progress, prune=prune)
    rows = screen.judge(rows, limits)
    path = table.write(out, rows)
    table.forget(out, table.journal_units(out))
    by_status = {}
    for r in rows:
        by_status.setdefault(r["unit"], set()).add(r["status"])
    counts.update(table=len(by_status),
                  flagged=sum(1 for s in by_status.values() if s != {"pass"}),
                  failed=sum(1 for s in by_status.values() if s & {"fail", "error"}),
                  errors=sum(1 for s in by_status.values() if "error" in s))
    html = page.write(out, rows, limits)
    if counts["interrupted"]:
        raise Interrupted(path, counts)
    return Result(path, html, rows, counts)
