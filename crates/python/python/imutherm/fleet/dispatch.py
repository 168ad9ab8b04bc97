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
import logging
import os
import signal
import sys
import time

from . import table, unit as unit_mod
from .errors import FleetError

UNITS_DIR = "units"
#: How long a scheduler named by address has to answer.
CONNECT_TIMEOUT = "20s"


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
            c = Client(scheduler, timeout=CONNECT_TIMEOUT)
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
    with _ignoring_ctrl_c():
        # Dask's warnings of its own (a task cancelled by Ctrl-C, a worker
        # killed at close while mid-unit) are not the line's business: a
        # unit that fails is a row saying why.
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                               dashboard_address=None, env=env, silence_logs=logging.ERROR)
    with cluster, Client(cluster) as c:
        yield c


@contextlib.contextmanager
def _ignoring_ctrl_c():
    """SIGINT ignored while the local workers start: a Ctrl-C at a
    terminal reaches every process of its group, and the driver alone is
    to answer it (keep what finished, close the cluster); a worker process
    inherits the ignored signal, so it neither dies mid-unit nor prints a
    traceback. Outside the main thread signals cannot be set: nothing
    changes."""
    try:
        before = signal.signal(signal.SIGINT, signal.SIG_IGN)
    except ValueError:
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, before)


def analyse(units, settings, out_dir, client, progress=None, prune=False):
    """Analyses the units of the manifest that need it, committing each
    unit's rows as it finishes; returns ``(rows, counts)`` where ``rows``
    are the whole table's measurement rows: the manifest's units (reused
    or new) and, unless ``prune``, the units earlier runs into ``out_dir``
    hold that this manifest does not list. A Ctrl-C stops the run after
    the units finished so far (``counts["interrupted"]``)."""
    before = table.previous_rows(out_dir)
    units_dir = os.path.join(out_dir, UNITS_DIR)
    os.makedirs(units_dir, exist_ok=True)
    table.remove_leftovers(out_dir)
    listed = {u.id for u in units}
    others = {uid: rows for uid, rows in before.items() if uid not in listed}
    pruned = sorted(others) if prune else []
    if prune:
        _remove_units(out_dir, {uid: others.pop(uid) for uid in pruned})
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
    analysed = 0
    try:
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
            table.commit(out_dir, u.id, rows)
            rows_by_unit[u.id] = rows
            analysed += 1
            bar.update()
        interrupted = False
    except KeyboardInterrupt:
        interrupted = True
        with contextlib.suppress(Exception):
            client.cancel(list(futures))
    bar.close()
    # A unit not reached keeps its earlier rows, if any: the next run,
    # seeing their digest differ, analyses it.
    for u in units:
        if u.id not in rows_by_unit and u.id in before:
            rows_by_unit[u.id] = [_measurements(r) for r in before[u.id]]
    ordered = [r for u in units if u.id in rows_by_unit for r in rows_by_unit[u.id]]
    ordered += [_measurements(r) for uid in sorted(others) for r in others[uid]]
    finished = sum(1 for u in units if u.id in rows_by_unit and
                   all(r.get("digest") == digests[u.id] for r in rows_by_unit[u.id]))
    return ordered, {"units": len(units), "analysed": analysed, "reused": len(units) - len(todo),
                     "earlier": len(others), "pruned": len(pruned), "finished": finished,
                     "interrupted": interrupted}


def _remove_units(out_dir, rows_by_unit):
    """Removes pruned units' files: their model and parameter files (the
    names their rows give, in ``units/`` only: a table moved from another
    folder never removes files there), their page and their journal
    entry."""
    units_dir = os.path.join(out_dir, UNITS_DIR)
    for uid, rows in rows_by_unit.items():
        names = {os.path.basename(r[k]) for r in rows for k in ("model_file", "params_file")
                 if r.get(k)}
        for name in names | {f"{uid}.html"}:
            with contextlib.suppress(FileNotFoundError):
                os.unlink(os.path.join(units_dir, name))
    table.forget(out_dir, rows_by_unit)


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
