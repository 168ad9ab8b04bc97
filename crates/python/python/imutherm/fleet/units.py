"""The unit of every numeric column of the fleet's table. A column holds
both sensors' rows, so a term's unit follows the row's ``si_unit``
(``rad/s`` for a gyro, ``m/s^2`` for an accelerometer): white noise is a
density, rad/√s and m/s/√s, a slope is per degree C."""

GYRO, ACCEL = "rad/s", "m/s^2"


def _by_sensor(gyro, accel):
    return {GYRO: gyro, ACCEL: accel}


SAME = _by_sensor(GYRO, ACCEL)
DENSITY = _by_sensor("rad/√s", "m/s/√s")
RANDOM_WALK = _by_sensor("rad/s/√s", "m/s^2/√s")
PER_DEGREE = _by_sensor("rad/s/°C", "m/s^2/°C")

#: Column -> its unit (a string), or the unit by the row's ``si_unit``.
COLUMNS = {
    "instance": "1", "samples": "1", "tcal_order": "1", "rank": "1",
    "static_spread": SAME,
    "white_noise": DENSITY, "white_noise_lo": DENSITY, "white_noise_hi": DENSITY,
    "bias_instability": SAME, "bias_instability_lo": SAME, "bias_instability_hi": SAME,
    "rate_random_walk": RANDOM_WALK, "rate_random_walk_lo": RANDOM_WALK,
    "rate_random_walk_hi": RANDOM_WALK,
    "tcal_coefficients": SAME, "tcal_centre_c": "°C", "tcal_scale_c": "°C", "tcal_t_ref_c": "°C",
    "tcal_t_min_c": "°C", "tcal_t_max_c": "°C", "tcal_slope": PER_DEGREE,
    "tcal_residual_rms": SAME, "held_out_bias_rms_before": SAME, "held_out_bias_rms": SAME,
    "held_out_bias_rms_as_loaded": SAME,
    "static_duration_s": "s", "static_rate_hz": "Hz", "thermal_duration_s": "s",
    "thermal_rate_hz": "Hz", "thermal_t_low_c": "°C", "thermal_t_high_c": "°C",
    "adev_tau_s": "s", "adev": SAME, "bias_t_c": "°C", "bias_before": SAME, "bias_after": SAME,
}
#: The robust z-scores (``z_<term>``) are numbers of spreads.
Z = "1"


def of(column, si_unit=None):
    """The unit of ``column`` in a row of ``si_unit`` ('' if unknown)."""
    u = Z if column.startswith("z_") else COLUMNS.get(column, "")
    return u.get(si_unit, "") if isinstance(u, dict) else u


def metadata(column):
    """The Parquet field metadata of ``column``: ``unit`` (a sentence
    where it follows the sensor) and ``unit.<si_unit>`` for each sensor;
    None for a column without a unit."""
    u = Z if column.startswith("z_") else COLUMNS.get(column)
    if u is None:
        return None
    if isinstance(u, str):
        return {"unit": u}
    meta = {"unit": f"{u[GYRO]} (gyro rows, si_unit {GYRO}), {u[ACCEL]} (accel rows, si_unit "
                    f"{ACCEL})"}
    meta.update({f"unit.{k}": v for k, v in u.items()})
    return meta
