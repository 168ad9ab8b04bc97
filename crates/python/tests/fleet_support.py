"""A small simulated production line for the fleet tests: units drawn from
the mpu9250-thesis population (imutherm.simulate's unit=), written as
imutherm's thesis logs, a manifest and limits."""

import numpy as np

import imutherm

#: The thesis log's header (docs/formats: the columns of the thesis's logger).
HEADER = ("mpu_accel_1[m/^2], mpu_accel_2[m/^2], mpu_accel_3[m/^2], mpu_gyro_1[rad/s], "
          "mpu_gyro_2[rad/s], mpu_gyro_3[rad/s], temp[degC]")
ORDER = ("accel_x", "accel_y", "accel_z", "gyro_x", "gyro_y", "gyro_z")
PLANTED = {"U03": "noise-3x", "U07": "slope-5x", "U10": "dead-axis:gyro_z"}
RUNS = {"static": dict(duration=300, profile="constant:34", seed=1),
        "thermal": dict(duration=1200, profile="ramp:20:70:1200", seed=2),
        # The evaluation's ADEV per 5 degC slice costs seconds a run: one
        # short held-out run, within one slice, keeps the tests quick.
        "held_out": dict(duration=120, profile="ramp:40:44:120", seed=3)}
LIMITS = """\
[gyro]
white_noise_min = 1e-6
tcal_residual_rms_max = 1e-2
[accel]
white_noise_min = 1e-6
[outliers]
z_max = 5.0
terms = ["white_noise", "tcal_slope"]
"""


def write_log(path, rec):
    """``rec`` as imutherm's log: its rate in a metadata line, the thesis header,
    one row per sample (10 significant digits: the chip's 16-bit steps exactly)."""
    cols = np.column_stack([rec.channels[c] for c in ORDER] + [rec.temperature])
    with open(path, "w", encoding="utf-8") as f:
        f.write(f"# sample_rate_hz: {rec.rate:g}\n{HEADER}\n")
        np.savetxt(f, cols, fmt="%.10g", delimiter=", ")


def write_unit(folder, uid, defect=None, held_out=False):
    """The runs of unit ``uid`` (a held-out one if asked); returns their
    paths by role."""
    paths = {}
    for role, args in RUNS.items():
        if role == "held_out" and not held_out:
            continue
        rec = imutherm.simulate(preset="mpu9250-thesis", unit=uid, defect=defect, **args)
        paths[role] = folder / f"{uid}_{role}.txt"
        write_log(paths[role], rec)
    return paths


def write_fleet(folder, ids, planted=PLANTED, firmware="px4", held_out=()):
    """Units ``ids`` (those in ``held_out`` with a held-out run) and a
    manifest ``units.csv`` listing them; returns its path."""
    lines = ["unit,static,thermal,held_out,instance,firmware"]
    for uid in ids:
        p = write_unit(folder, uid, planted.get(uid), uid in held_out)
        held = p["held_out"].name if "held_out" in p else ""
        lines.append(f"{uid},{p['static'].name},{p['thermal'].name},{held},,{firmware}")
    manifest = folder / "units.csv"
    manifest.write_text("\n".join(lines) + "\n", encoding="utf-8")
    (folder / "limits.toml").write_text(LIMITS, encoding="utf-8")
    return manifest


def cut_mid_line(source, dest, share):
    """``source`` cut at ``share`` of its bytes, in the middle of a line,
    as a recording stopped by a full disk or a pulled cable leaves it;
    returns ``dest``."""
    data = source.read_bytes()
    at = int(len(data) * share)
    while data[at - 1:at] == b"\n" or data[at:at + 1] == b"\n":
        at += 1  # never on a line's end: the last line must be cut short
    dest.write_bytes(data[:at])
    return dest

