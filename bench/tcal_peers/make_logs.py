#!/usr/bin/env python3
"""Thermal calibration logs with a known bias, as PX4 writes them.

    make_logs.py SEED OUT_DIR

writes OUT_DIR/heating.ulg (20 -> 70 °C in 45 min, the fit's run),
OUT_DIR/cooling.ulg (70 -> 20 °C, held out) and OUT_DIR/truth.json: two
IMU instances at 200 Hz, each axis's bias a cubic in temperature drawn
from SEED, MPU-9250 white noise and quantization (gyro ±500 °/s, accel
±8 g, temperature 1/333.87 °C), and one sensor_baro, which PX4's
Tools/process_sensor_caldata.py requires.

The same runs go to OUT_DIR/heating.bin and cooling.bin as ArduPilot
DataFlash logs (with the IMUs' INS_GYRn_ID/INS_ACCn_ID in PARM messages),
IMU messages at 25 Hz of both instances: each the mean of
eight 200 Hz samples, as ArduPilot logs the filtered sensor at the log
rate (the samples, the truth and the random draws are those of the ULogs).

The ULog is written here with `struct`, following docs.px4.io "ULog File
Format" (header, F formats, A subscriptions, D data); pyulog reads it, and
so does imutherm. The topics carry the fields of PX4's msg/SensorGyro.msg,
SensorAccel.msg and SensorBaro.msg that both readers use.
"""

import json
import math
import struct
import sys
from pathlib import Path

import numpy as np

RATE_HZ = 200.0
DURATION_S = 45 * 60.0
G = 9.80665
# MPU-9250 datasheet (PS-MPU-9250A-01 rev 1.1, table 1 and 2): gyro rate
# noise 0.01 °/s/√Hz, sensitivity 65.5 LSB/(°/s) at ±500 °/s; accel noise
# 300 µg/√Hz, 4096 LSB/g at ±8 g; temperature 333.87 LSB/°C.
GYRO_DENSITY = math.radians(0.01)
GYRO_LSB = math.radians(1 / 65.5)
ACCEL_DENSITY = 300e-6 * G
ACCEL_LSB = G / 4096
TEMP_LSB = 1 / 333.87
# The gyro and accelerometer device ids of two ICM-20602-like chips (bus
# SPI, address, device type differ between gyro and accelerometer).
IDS = [(2490378, 2490634), (3407882, 3408138)]
T_MID = 45.0

TOPICS = {
    "sensor_gyro": [("uint64_t", "timestamp"), ("uint64_t", "timestamp_sample"), ("uint32_t", "device_id"),
                    ("float", "x"), ("float", "y"), ("float", "z"), ("float", "temperature"),
                    ("uint32_t", "error_count")],
    "sensor_accel": [("uint64_t", "timestamp"), ("uint64_t", "timestamp_sample"), ("uint32_t", "device_id"),
                     ("float", "x"), ("float", "y"), ("float", "z"), ("float", "temperature"),
                     ("uint32_t", "error_count")],
    "sensor_baro": [("uint64_t", "timestamp"), ("uint64_t", "timestamp_sample"), ("uint32_t", "device_id"),
                    ("float", "pressure"), ("float", "temperature"), ("uint32_t", "error_count")],
}
PACK = {"uint64_t": "Q", "uint32_t": "I", "float": "f"}


def message(kind, body):
    return struct.pack("<HB", len(body), ord(kind)) + body


def write_ulog(path, records):
    """records: (topic, multi_id, fields, rows) with rows a list of tuples."""
    out = bytearray(b"ULog\x01\x12\x35" + bytes([1]) + struct.pack("<Q", 0))
    out += message("B", bytes(40))
    for name, fields in TOPICS.items():
        out += message("F", (name + ":" + "".join(f"{t} {n};" for t, n in fields)).encode())
    key = b"char[12] sys_name"
    out += message("I", bytes([len(key)]) + key + b"imutherm-sim")
    ids = {}
    for msg_id, (topic, multi, _) in enumerate(records):
        ids[(topic, multi)] = msg_id
        out += message("A", struct.pack("<BH", multi, msg_id) + topic.encode())
    # Data in time order, as the logger writes it.
    events = []
    for (topic, multi, rows) in records:
        fmt = "<H" + "".join(PACK[t] for t, _ in TOPICS[topic])
        for row in rows:
            events.append((row[0], struct.pack(fmt, ids[(topic, multi)], *row)))
    events.sort(key=lambda e: e[0])
    for _, body in events:
        out += message("D", body)
    Path(path).write_bytes(bytes(out))


# ArduPilot libraries/AP_Logger/LogStructure.h: HEAD_BYTE1/2, LOG_FORMAT_MSG
# (128) and struct log_Format; AP_InertialSensor's IMU message (LOG_IMU_MSG,
# "QBffffffIIfBBHH", "TimeUS,I,GyrX,GyrY,GyrZ,AccX,AccY,AccZ,EG,EA,T,GH,AH,
# GHz,AHz"), as crates/robotlogs/tests/fixtures/make_fixtures.py writes it.
DF_HEAD = b"\xa3\x95"
DF_IMU_TYPE = 4
DF_IMU_FMT = "QBffffffIIfBBHH"
DF_IMU_LABELS = "TimeUS,I,GyrX,GyrY,GyrZ,AccX,AccY,AccZ,EG,EA,T,GH,AH,GHz,AHz"
DF_DECIMATE = 8
# PARM (LOG_PARAMETER_MSG, "QNf", "TimeUS,Name,Value"): ArduPilot logs its
# parameters at start, the IMUs' INS_GYR_ID/INS_GYR2_ID and INS_ACC_ID/
# INS_ACC2_ID among them (AP_InertialSensor.cpp, var_info).
DF_PARM_TYPE = 64


def df_fmt(msg_type, name, fmt, labels):
    size = 3 + struct.calcsize("<" + fmt.replace("n", "4s").replace("N", "16s").replace("Z", "64s"))
    return DF_HEAD + struct.pack("<BBB4s16s64s", 128, msg_type, size, name.encode(), fmt.encode(), labels.encode())


def write_dataflash(path, stamps, sims):
    """sims: per instance (temp, gyro[3], accel[3]) at 200 Hz, logged as the
    means of DF_DECIMATE samples."""
    out = bytearray(df_fmt(128, "FMT", "BBnNZ", "Type,Length,Name,Format,Columns"))
    out += df_fmt(DF_IMU_TYPE, "IMU", DF_IMU_FMT, DF_IMU_LABELS)
    out += df_fmt(DF_PARM_TYPE, "PARM", "QNf", "TimeUS,Name,Value")
    for inst, (gid, aid) in enumerate(IDS):
        suffix = "" if inst == 0 else str(inst + 1)
        for name, value in ((f"INS_GYR{suffix}_ID", gid), (f"INS_ACC{suffix}_ID", aid)):
            out += DF_HEAD + struct.pack("<BQ16sf", DF_PARM_TYPE, int(stamps[0]), name.encode(), float(value))
    m = len(stamps) // DF_DECIMATE
    mean = lambda x: np.asarray(x[: m * DF_DECIMATE]).reshape(m, DF_DECIMATE).mean(axis=1)
    us = stamps[DF_DECIMATE - 1 :: DF_DECIMATE][:m]
    cols = [(mean(temp), [mean(g) for g in gyro], [mean(a) for a in accel]) for temp, gyro, accel in sims]
    fmt = "<B" + DF_IMU_FMT
    for j in range(m):
        for inst, (temp, gyro, accel) in enumerate(cols):
            out += DF_HEAD + struct.pack(fmt, DF_IMU_TYPE, int(us[j]), inst, *(float(g[j]) for g in gyro),
                                         *(float(a[j]) for a in accel), 0, 0, float(temp[j]), 1, 1, 1000, 1000)
    Path(path).write_bytes(bytes(out))


def profile(heating):
    t = np.arange(int(DURATION_S * RATE_HZ)) / RATE_HZ
    # The board approaches its end temperature with a 15 min time constant.
    frac = (1 - np.exp(-t / 900.0)) / (1 - math.exp(-DURATION_S / 900.0))
    temp = 20 + 50 * frac if heating else 70 - 50 * frac
    return t, temp


def truth(rng):
    """Per instance, sensor and axis: cubic coefficients in (T − T_MID)."""
    out = []
    for _ in IDS:
        gyro = [[rng.uniform(-0.02, 0.02), rng.uniform(-3e-4, 3e-4), rng.uniform(-6e-6, 6e-6),
                 rng.uniform(-3e-7, 3e-7)] for _ in range(3)]
        accel = [[rng.uniform(-0.2, 0.2), rng.uniform(-3e-3, 3e-3), rng.uniform(-6e-5, 6e-5),
                  rng.uniform(-3e-6, 3e-6)] for _ in range(3)]
        out.append({"gyro": gyro, "accel": accel})
    return out


def bias(coeffs, temp):
    d = temp - T_MID
    return coeffs[0] + coeffs[1] * d + coeffs[2] * d**2 + coeffs[3] * d**3


def run(rng, tru, heating):
    t, temp_true = profile(heating)
    n = len(t)
    stamps = (1_000_000 + t * 1e6).astype(np.uint64)
    records, sims = [], []
    for i, ((gid, aid), tr) in enumerate(zip(IDS, tru)):
        temp = np.round((temp_true + rng.normal(0, 0.02, n)) / TEMP_LSB) * TEMP_LSB
        gyro = [np.round((bias(tr["gyro"][k], temp_true) + rng.normal(0, GYRO_DENSITY * math.sqrt(RATE_HZ), n))
                         / GYRO_LSB) * GYRO_LSB for k in range(3)]
        grav = [0.0, 0.0, -G]
        accel = [np.round((grav[k] + bias(tr["accel"][k], temp_true)
                           + rng.normal(0, ACCEL_DENSITY * math.sqrt(RATE_HZ), n)) / ACCEL_LSB) * ACCEL_LSB
                 for k in range(3)]
        sims.append((temp, gyro, accel))
        records.append(("sensor_gyro", i, [(int(s), int(s), gid, float(gyro[0][j]), float(gyro[1][j]),
                                             float(gyro[2][j]), float(temp[j]), 0) for j, s in enumerate(stamps)]))
        records.append(("sensor_accel", i, [(int(s), int(s), aid, float(accel[0][j]), float(accel[1][j]),
                                              float(accel[2][j]), float(temp[j]), 0) for j, s in enumerate(stamps)]))
    baro_every = int(RATE_HZ / 10)
    records.append(("sensor_baro", 0, [(int(s), int(s), 4653081, 1013.25, float(temp_true[j * baro_every]), 0)
                                       for j, s in enumerate(stamps[::baro_every])]))
    return records, stamps, sims


def main():
    seed, out = int(sys.argv[1]), Path(sys.argv[2])
    out.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(seed)
    tru = truth(rng)
    for name, heating in (("heating", True), ("cooling", False)):
        records, stamps, sims = run(rng, tru, heating)
        write_ulog(out / f"{name}.ulg", records)
        write_dataflash(out / f"{name}.bin", stamps, sims)
    (out / "truth.json").write_text(json.dumps({"t_mid_c": T_MID, "ids": IDS, "instances": tru}, indent=1))


if __name__ == "__main__":
    main()
