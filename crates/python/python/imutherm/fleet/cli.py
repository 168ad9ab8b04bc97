"""``imutherm-fleet``: the fleet from a shell. Usage errors exit 2 (as
argparse does), a run that cannot start or finish exits 1, a run stopped
by Ctrl-C exits 130 (128 + SIGINT, as a shell reports it) after saying
what it kept; a unit that fails is a row of the table, never a failed
run."""

import argparse
import sys

EXAMPLES = """\
examples:
  imutherm-fleet units.csv --limits limits.toml --out fleet_out
  imutherm-fleet units/ --limits limits.toml --out fleet_out --workers 8 --firmware px4
  imutherm-fleet units.parquet --limits limits.toml --out fleet_out --scheduler tcp://10.0.0.5:8786

UNITS is a manifest (CSV or Parquet; columns unit, static, thermal, held_out,
instance, firmware) or a folder of unit folders (static*, thermal*, held_out*).
A rerun into the same --out analyses only units whose inputs or settings changed;
units already in --out that the manifest does not list stay, unless --prune.
Each unit is kept as it finishes: after a Ctrl-C or a crash, run the same
command again to analyse the rest.
"""


#: The exit status of a run stopped by Ctrl-C.
INTERRUPTED = 130


def parser():
    p = argparse.ArgumentParser(
        prog="imutherm-fleet", epilog=EXAMPLES, formatter_class=argparse.RawDescriptionHelpFormatter,
        description="Noise terms and temperature model of every unit of a production line on "
                    "Dask: one Parquet table, each unit's model and firmware parameters, pass/fail "
                    "against limits, outliers of the fleet flagged, a fleet page.")
    p.add_argument("units", metavar="UNITS", help="manifest (.csv, .parquet) or folder of units")
    p.add_argument("--limits", required=True, metavar="LIMITS.toml", help="pass/fail limits")
    p.add_argument("--out", required=True, metavar="DIR", help="output folder")
    p.add_argument("--scheduler", metavar="tcp://HOST:PORT",
                   help="a running Dask scheduler (default: a local cluster)")
    p.add_argument("--workers", type=_positive_int, metavar="N",
                   help="local cluster's worker processes (default: one per core)")
    p.add_argument("--firmware", choices=("px4", "ardupilot"),
                   help="export for units whose manifest names no firmware")
    p.add_argument("--rate", type=float, metavar="HZ", help="sample rate of files that carry none")
    p.add_argument("--order", default="auto", type=_order, metavar="N|auto",
                   help="temperature polynomial order (default: auto)")
    p.add_argument("--prune", action="store_true",
                   help="remove from --out the units this manifest does not list (by default "
                        "the table keeps every unit earlier runs put there)")
    return p


def _positive_int(text):
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a whole number") from None
    if n < 1:
        raise argparse.ArgumentTypeError(f"{n}: at least 1")
    return n


def _order(text):
    return text if text == "auto" else _positive_int(text)


def main(argv=None):
    args = parser().parse_args(argv)
    if args.scheduler is not None and args.workers is not None:
        parser().error("--workers sizes a local cluster: not with --scheduler")
    try:
        import dask.distributed  # noqa: F401
        import pyarrow  # noqa: F401
    except ImportError as e:
        print(f"imutherm-fleet: {e.name} is not installed: pip install 'imutherm[fleet]'",
              file=sys.stderr)
        return 1
    from . import run
    from .errors import FleetError, Interrupted

    try:
        result = run(args.units, args.limits, args.out, scheduler=args.scheduler,
                     workers=args.workers, firmware=args.firmware, rate=args.rate,
                     order=args.order, prune=args.prune)
    except Interrupted as e:
        print(f"imutherm-fleet: {e}", file=sys.stderr)
        return INTERRUPTED
    except KeyboardInterrupt:
        # A second Ctrl-C while the table of the first was written, or one
        # before any unit ran: every unit finished is in the journal.
        print(f"imutherm-fleet: interrupted: the units finished so far are kept in {args.out}; "
              f"run the same command again to analyse the others", file=sys.stderr)
        return INTERRUPTED
    except FleetError as e:
        print(f"imutherm-fleet: {e}", file=sys.stderr)
        return 1
    c = result.counts
    earlier = f"; {c['earlier']} more from earlier runs" if c["earlier"] else ""
    pruned = f"; {c['pruned']} pruned" if c["pruned"] else ""
    print(f"{c['units']} units ({c['analysed']} analysed, {c['reused']} unchanged){earlier}"
          f"{pruned}: the table holds {c['table']} units, {c['table'] - c['flagged']} pass, "
          f"{c['flagged']} flagged ({c['failed']} out of limits or failed, {c['errors']} with "
          f"errors)")
    print(f"table: {result.table}")
    print(f"page: {result.page}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
