"""Flight controllers' logs of two IMUs through a temperature change, as
PX4 and ArduPilot write them, for the tests of every instance at once.

Each IMU's bias is a known cubic of its temperature, different per axis and
instance, with white noise; the second IMU sits 1.5 degC warmer on the
board. The formats follow the flight stacks' own definitions, as
bench/tcal_peers/make_logs.py writes them for the peer benchmark:

* ULog: docs.px4.io "ULog File Format" (header, F formats, A
  subscriptions, D data); the topics carry the fields of PX4's
  msg/SensorGyro.msg and SensorAccel.msg that imutherm reads, each instance
  with its own ``device_id``.
* DataFlash: ArduPilot libraries/AP_Logger/LogStructure.h (FMT, PARM
  ``QNf``) and AP_InertialSensor's IMU message ``QBffffffIIfBBHH``, with the
  IMUs' INS_GYRn_ID/INS_ACCn_ID in PARM messages, as ArduPilot logs its
  parameters at start.
"""

import struct

import numpy as np

#: Low, so that the evaluations of the tests take seconds; the firmware's
#: correction does not depend on the rate.
RATE_HZ = 5.0
MINUTES = 20
G = 9.80665
#: Gyro and accelerometer device ids of the two IMUs (ICM-20602-like).
IDS = [(2490378, 2490634), (3407882, 3408138)]


def bias(instance, k, t):
    """The true bias of ``instance``'s gyro (k < 3) or accelerometer (k >= 3)
    axis k % 3 at ``t`` degC: a cubic about 40 degC."""
    d = t - 40.0
    s = 1.0 if instance == 0 else -0.7
    a = k % 3 + 1.0
    scale = 1.0 if k < 3 else 10.0
    return scale * s * (3e-3 * a + 2e-4 * a * d - 4e-6 * d * d + 2e-7 * a * d ** 3)


def run(heating, seed):
    """Per instance, (temperature, six channels: gyro x-z, accel x-z)."""
    rng = np.random.default_rng(seed)
    n = int(MINUTES * 60 * RATE_HZ)
    frac = 1.0 - np.exp(-np.arange(n) / (n / 3.0))
    # The held-out cooling stays within the range the heating covers.
    t = 20.0 + 40.0 * frac if heating else 57.0 - 35.0 * frac
    out = []
    for i in range(len(IDS)):
        ti = t + 1.5 * i
        chans = []
        for k in range(6):
            rest, sigma = (-G, 2e-3) if k == 5 else ((0.0, 2e-4) if k < 3 else (0.0, 2e-3))
            chans.append(rest + bias(i, k, ti) + sigma * rng.standard_normal(n))
        out.append((np.round(ti / 0.01) * 0.01, chans))
    return out


def stamps_us(n):
    return [1_000_000 + int(j * 1e6 / RATE_HZ) for j in range(n)]


_TOPIC = [("uint64_t", "timestamp"), ("uint64_t", "timestamp_sample"), ("uint32_t", "device_id"),
          ("float", "x"), ("float", "y"), ("float", "z"), ("float", "temperature"),
          ("uint32_t", "error_count")]
_PACK = {"uint64_t": "Q", "uint32_t": "I", "float": "f"}


def _message(kind, body):
    return struct.pack("<HB", len(body), ord(kind)) + body


def write_ulog(path, sims):
    out = bytearray(b"ULog\x01\x12\x35" + bytes([1]) + struct.pack("<Q", 0))
    out += _message("B", bytes(40))
    for name in ("sensor_gyro", "sensor_accel"):
        out += _message("F", (name + ":" + "".join(f"{t} {n};" for t, n in _TOPIC)).encode())
    subs = []
    for i in range(len(sims)):
        for name in ("sensor_gyro", "sensor_accel"):
            out += _message("A", struct.pack("<BH", i, len(subs)) + name.encode())
            subs.append((i, name))
    fmt = "<H" + "".join(_PACK[t] for t, _ in _TOPIC)
    us = stamps_us(len(sims[0][0]))
    for j, s in enumerate(us):
        for msg_id, (i, name) in enumerate(subs):
            temp, chans = sims[i]
            axes = chans[0:3] if name == "sensor_gyro" else chans[3:6]
            dev = IDS[i][0] if name == "sensor_gyro" else IDS[i][1]
            out += _message("D", struct.pack(fmt, msg_id, s, s, dev, *(float(a[j]) for a in axes),
                                             float(temp[j]), 0))
    with open(path, "wb") as f:
        f.write(bytes(out))


_HEAD = b"\xa3\x95"
_IMU_FMT = "QBffffffIIfBBHH"


def _fmt(msg_type, name, fmt, labels):
    size = 3 + struct.calcsize("<" + fmt.replace("n", "4s").replace("N", "16s").replace("Z", "64s"))
    return _HEAD + struct.pack("<BBB4s16s64s", 128, msg_type, size, name.encode(), fmt.encode(),
                               labels.encode())


def write_dataflash(path, sims):
    out = bytearray(_fmt(128, "FMT", "BBnNZ", "Type,Length,Name,Format,Columns"))
    out += _fmt(4, "IMU", _IMU_FMT, "TimeUS,I,GyrX,GyrY,GyrZ,AccX,AccY,AccZ,EG,EA,T,GH,AH,GHz,AHz")
    out += _fmt(64, "PARM", "QNf", "TimeUS,Name,Value")
    us = stamps_us(len(sims[0][0]))
    for i, (gid, aid) in enumerate(IDS):
        suffix = "" if i == 0 else str(i + 1)
        for name, value in ((f"INS_GYR{suffix}_ID", gid), (f"INS_ACC{suffix}_ID", aid)):
            out += _HEAD + struct.pack("<BQ16sf", 64, us[0], name.encode(), float(value))
    for j, s in enumerate(us):
        for i, (temp, chans) in enumerate(sims):
            out += _HEAD + struct.pack("<B" + _IMU_FMT, 4, s, i, *(float(c[j]) for c in chans),
                                       0, 0, float(temp[j]), 1, 1, 1000, 1000)
    with open(path, "wb") as f:
        f.write(bytes(out))


def write_all(directory):
    """heating.ulg, cooling.ulg, heating.bin and cooling.bin in
    ``directory``: the same two runs in both formats."""
    for name, heating, seed in (("heating", True, 11), ("cooling", False, 12)):
        sims = run(heating, seed)
        write_ulog(directory / f"{name}.ulg", sims)
        write_dataflash(directory / f"{name}.bin", sims)
