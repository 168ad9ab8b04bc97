"""Pass/fail limits of a production line, from a TOML file.

::

    # Per sensor (gyro, accel) or per channel (gyro_z, ...): the channel's
    # own table wins. SI units: rad/s and m/s^2 based, per degree C.
    [gyro]
    white_noise_max = 3.0e-4        # N, rad/sqrt(s)
    white_noise_min = 1.0e-5        # a dead axis has none
    tcal_slope_max = 2.0e-3         # |d bias/dT| at T_ref, rad/s/degC
    tcal_residual_rms_max = 2.0e-3  # rad/s

    [accel]
    white_noise_max = 1.5e-2

    [outliers]
    z_max = 5.0                     # robust z (median/MAD) beyond which a unit is an outlier
    terms = ["white_noise", "bias_instability", "tcal_slope"]

    # What the line's runs must be (each optional).
    [run]
    static_duration_min = 3600      # s
    thermal_duration_min = 7200     # s, all thermal runs together
    temperature_span_min = 40       # degC, the temperature model's fitted range
    fit_range = [20, 75]            # degC, that range must cover it
    rate_min = 190                  # Hz, every run
    rate_max = 210
    allow = ["thermal:bad_metadata", "time_gap"]   # reader problems that do not fail a unit

Every key of a sensor's table is ``<metric>_min`` or ``<metric>_max`` for
a metric of the table (:data:`METRICS`); an unknown key is refused with
its table, so a misspelt limit never passes silently. A problem the reader
or the channel checks found in a run (a truncated last line, a gap, a
skipped line, motion, a dead channel: ``problem_kinds``) fails the unit
unless ``[run] allow`` names it, as ``kind`` or ``role:kind``.
"""

import sys

from .errors import FleetInputError

#: The table's columns a limit or the outlier screen may name.
METRICS = ("white_noise", "bias_instability", "rate_random_walk", "tcal_slope",
           "tcal_residual_rms", "held_out_bias_rms")
GROUPS = ("gyro", "accel")
CHANNELS = tuple(f"{g}_{a}" for g in GROUPS for a in "xyz")
#: A robust z beyond 5 is about one in 1.7 million for normal data: among a
#: thousand units times six channels, a good unit is flagged rarely, while
#: the spread of real faults (3x noise, 5x slope) is tens of z.
DEFAULT_Z_MAX = 5.0
DEFAULT_OUTLIER_TERMS = ("white_noise", "bias_instability", "tcal_slope", "tcal_residual_rms")


class Limits:
    """Limits per channel and the outlier screen's settings."""

    def __init__(self, tables=None, z_max=DEFAULT_Z_MAX, outlier_terms=DEFAULT_OUTLIER_TERMS,
                 run=None):
        self.tables = tables or {}
        self.z_max = z_max
        self.outlier_terms = tuple(outlier_terms)
        #: The ``[run]`` table: the run checks and ``allow``.
        self.run = dict(run or {})

    def allows(self, kind):
        """Whether ``[run] allow`` lets a problem of ``kind`` (``role:kind``) pass."""
        allowed = self.run.get("allow", ())
        return kind in allowed or kind.split(":", 1)[-1] in allowed

    def for_channel(self, channel):
        """``{metric: (min, max)}`` for ``channel`` (either may be None)."""
        group = channel.split("_")[0]
        merged = {}
        for table in (self.tables.get(group, {}), self.tables.get(channel, {})):
            for key, v in table.items():
                metric, bound = key.rsplit("_", 1)
                lo, hi = merged.get(metric, (None, None))
                merged[metric] = (v, hi) if bound == "min" else (lo, v)
        return merged

    def settings(self):
        """What the limits are, for the digest that decides a rerun."""
        return {"tables": self.tables, "z_max": self.z_max, "outlier_terms": list(self.outlier_terms),
                "run": self.run}


def _toml():
    if sys.version_info >= (3, 11):
        import tomllib
        return tomllib
    import tomli  # the `fleet` extra installs it below Python 3.11
    return tomli


def load(path):
    """Reads a limits file; a bad key or value names the file and the key."""
    toml = _toml()
    try:
        with open(path, "rb") as f:
            doc = toml.load(f)
    except toml.TOMLDecodeError as e:
        raise FleetInputError(f"{path}: {e}") from None
    except OSError as e:
        raise FleetInputError(f"{path}: {e.strerror}") from None
    return parse(doc, str(path))


def parse(doc, path="limits"):
    tables, z_max, terms, run = {}, DEFAULT_Z_MAX, DEFAULT_OUTLIER_TERMS, {}
    for name, table in doc.items():
        if name == "outliers":
            z_max, terms = _outliers(path, table)
            continue
        if name == "run" and isinstance(table, dict):
            run = _run(path, table)
            continue
        if name not in GROUPS + CHANNELS or not isinstance(table, dict):
            raise FleetInputError(f"{path}: [{name}]: expected a table [gyro], [accel], "
                                  f"[outliers], [run] or one per channel ({', '.join(CHANNELS)})")
        for key, v in table.items():
            metric, _, bound = key.rpartition("_")
            if metric not in METRICS or bound not in ("min", "max"):
                raise FleetInputError(f"{path}: [{name}] {key}: expected <metric>_min or "
                                      f"<metric>_max, metric one of {', '.join(METRICS)}")
            if isinstance(v, bool) or not isinstance(v, (int, float)) or v != v:
                raise FleetInputError(f"{path}: [{name}] {key} = {v!r}: expected a number")
        tables[name] = {k: float(v) for k, v in table.items()}
    return Limits(tables, z_max, terms, run)


def _outliers(path, table):
    z_max = table.get("z_max", DEFAULT_Z_MAX)
    terms = table.get("terms", list(DEFAULT_OUTLIER_TERMS))
    unknown = set(table) - {"z_max", "terms"}
    if unknown:
        raise FleetInputError(f"{path}: [outliers] {', '.join(sorted(unknown))}: expected z_max "
                              f"and terms")
    if isinstance(z_max, bool) or not isinstance(z_max, (int, float)) or not z_max > 0:
        raise FleetInputError(f"{path}: [outliers] z_max = {z_max!r}: expected a number above 0")
    if not isinstance(terms, list) or any(t not in METRICS for t in terms):
        raise FleetInputError(f"{path}: [outliers] terms = {terms!r}: expected a list of "
                              f"{', '.join(METRICS)}")
    return float(z_max), tuple(terms)


#: The ``[run]`` table's numbers, with their units.
RUN_NUMBERS = {"static_duration_min": "s", "thermal_duration_min": "s",
               "temperature_span_min": "°C", "rate_min": "Hz", "rate_max": "Hz"}


def _number(v):
    return not isinstance(v, bool) and isinstance(v, (int, float)) and v == v


def _run(path, table):
    run = {}
    for key, v in table.items():
        if key in RUN_NUMBERS:
            if not _number(v) or v < 0:
                raise FleetInputError(f"{path}: [run] {key} = {v!r}: expected a number of "
                                      f"{RUN_NUMBERS[key]}, 0 or more")
            run[key] = float(v)
        elif key == "fit_range":
            if not (isinstance(v, list) and len(v) == 2 and all(map(_number, v)) and v[0] < v[1]):
                raise FleetInputError(f"{path}: [run] fit_range = {v!r}: expected [low, high] in "
                                      f"°C, low below high")
            run[key] = [float(v[0]), float(v[1])]
        elif key == "allow":
            if not isinstance(v, list) or not all(isinstance(k, str) and k for k in v):
                raise FleetInputError(f"{path}: [run] allow = {v!r}: expected a list of problem "
                                      f"kinds (\"time_gap\", \"thermal:bad_line\", ...)")
            run[key] = list(v)
        else:
            raise FleetInputError(f"{path}: [run] {key}: expected one of "
                                  f"{', '.join(list(RUN_NUMBERS) + ['fit_range', 'allow'])}")
    return run
