"""The fleet on Dask distributed: one task per unit, the table assembled
on the client as units finish.

A worker killed mid-unit loses nothing: the scheduler releases the tasks
it was processing and runs them again elsewhere, until a task has seen
more than ``distributed.scheduler.allowed-failures`` workers die under it
(distributed's ``Scheduler.remove_worker``, which then errs it with
``KilledWorker``: that unit becomes a row with the error), the
unit's files are written by rename so a killed write leaves only a scratch
file (removed at the next run), and the table holds each unit once,
keyed by its id, whichever attempt finished it.
"""

import contextlib
import os
import sys
import time

from . import table, unit as unit_mod
from .files import remove_scratch
from .errors import FleetError

UNITS_DIR = "units"


@contextlib.contextmanager
def connect(client=None, scheduler=None, workers=None):
    """The user's ``Client``, a client of the scheduler at ``scheduler``
    (``tcp://host:port``), or a ``LocalCluster`` of ``workers`` processes
    (one thread each, so a worker holds one unit's data at a time)."""
    if client is not None:
        yield client
        return
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError:
        raise FleetError("dask.distributed is not installed: pip install 'imutherm[fleet]'") from None

    if scheduler is not None:
        try:
            c = Client(scheduler, timeout="20s")
        except OSError as e:
            raise FleetError(f"cannot reach the Dask scheduler at {scheduler}: {e}") from None
        with c:
            yield c
        return
    cores = os.cpu_count() or 1
    n = workers or cores
    # imutherm's statistics spread over a rayon pool as large as the
    # machine: N workers each taking every core would fight for them, so
    # each worker's pool gets its share (RAYON_NUM_THREADS, read by rayon
    # when its global pool starts, in the worker's own process). A value
    # the user set is kept.
    env = {} if "RAYON_NUM_THREADS" in os.environ else {"RAYON_NUM_THREADS": str(max(1, cores // n))}
    with LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None,
                      env=env) as cluster, Client(cluster) as c:
        yield c


def analyse(units, settings, out_dir, client, progress=None):
    """Analyses the units that need it; returns ``(rows, counts)`` where
    ``rows`` are every unit's measurement rows (reused or new)."""
    before = table.previous_rows(out_dir)
    units_dir = os.path.join(out_dir, UNITS_DIR)
    os.makedirs(units_dir, exist_ok=True)
    remove_scratch(units_dir)
    rows_by_unit, todo, digests = {}, [], {}
    for u in units:
        d = table.unit_digest(u, settings)
        digests[u.id] = d
        old = before.get(u.id)
        if table.reusable(old, d):
            rows_by_unit[u.id] = [_measurements(r) for r in old]
        else:
            todo.append(u)
    bar = progress or Progress(len(todo))
    from dask.distributed import as_completed

    futures = {}
    for u in todo:
        f = client.submit(unit_mod.analyse, u, settings, units_dir, pure=False,
                          key=f"imutherm-unit-{u.id}-{digests[u.id] or 'unread'}-{time.time_ns()}")
        futures[f] = u
    for f in as_completed(futures):
        u = futures[f]
        try:
            rows = f.result()
        except Exception as e:  # noqa: BLE001 (a task the cluster gave up on is its unit's row)
            rows = [unit_mod.error_row(u, e)]
        for r in rows:
            r["digest"] = digests[u.id]
        rows_by_unit[u.id] = rows
        bar.update()
    bar.close()
    ordered = [r for u in units for r in rows_by_unit[u.id]]
    return ordered, {"units": len(units), "analysed": len(todo), "reused": len(units) - len(todo)}


def _measurements(row):
    """An earlier row without its judgement, which is made afresh."""
    return {k: v for k, v in row.items()
            if k not in ("status", "reasons", "outlier", "flagged", "rank") and not k.startswith("z_")}


class Progress:
    """A bar on stderr: redrawn in place on a terminal, a line per tenth
    of the units otherwise (a log file keeps every line)."""

    def __init__(self, total, stream=None):
        self.total, self.done = total, 0
        self.stream = stream or sys.stderr
        self.tty = self.stream.isatty()
        self.started = time.monotonic()

    def update(self):
        self.done += 1
        step = max(1, self.total // 10)
        if self.tty or self.done % step == 0 or self.done == self.total:
            width = 30
            full = width * self.done // max(1, self.total)
            rate = self.done / max(1e-9, time.monotonic() - self.started)
            line = (f"[{'=' * full}{' ' * (width - full)}] {self.done}/{self.total} units, "
                    f"{rate:.2f} units/s")
            self.stream.write(("\r" + line) if self.tty else line + "\n")
            self.stream.flush()

    def close(self):
        if self.tty and self.total:
            self.stream.write("\n")
            self.stream.flush()
