#!/usr/bin/env python3
"""Writes a ROS 2 MCAP bag of sensor_msgs/msg/Imu at 200 Hz, of about
SIZE_MB megabytes, for bench/mcap_speed.sh: zstd chunks as `ros2 bag
record` writes by default with the mcap storage's "fastwrite" preset off.
The CDR of each message comes from rosbags' serialiser; white noise keeps
zstd from shrinking the file to nothing.

    make_mcap.py OUT.mcap SIZE_MB
"""

import sys

import numpy as np
from mcap.writer import CompressionType, Writer
from rosbags.typesys import Stores, get_typestore

ts = get_typestore(Stores.ROS2_HUMBLE)
M = ts.types
IMU = "sensor_msgs/msg/Imu"


def message(k, g, a):
    t = 1_700_000_000 * 10**9 + k * 5_000_000
    cov = np.zeros(9)
    msg = M[IMU](
        header=M["std_msgs/msg/Header"](
            stamp=M["builtin_interfaces/msg/Time"](sec=t // 10**9, nanosec=t % 10**9), frame_id="imu_link"
        ),
        orientation=M["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0),
        orientation_covariance=cov,
        angular_velocity=M["geometry_msgs/msg/Vector3"](x=g[0], y=g[1], z=g[2]),
        angular_velocity_covariance=cov,
        linear_acceleration=M["geometry_msgs/msg/Vector3"](x=a[0], y=a[1], z=a[2]),
        linear_acceleration_covariance=cov,
    )
    return t, bytes(ts.serialize_cdr(msg, IMU))


def main(out, size_mb):
    rng = np.random.default_rng(7)
    with open(out, "wb") as f:
        w = Writer(f, compression=CompressionType.ZSTD)
        w.start(profile="ros2", library="imutherm bench")
        schema = w.register_schema(name=IMU, encoding="ros2msg", data=b"")
        ch = w.register_channel(topic="/imu/data", message_encoding="cdr", schema_id=schema)
        k = 0
        while f.tell() < size_mb * 1e6:
            g = rng.standard_normal((10000, 3)) * 0.003
            a = rng.standard_normal((10000, 3)) * 0.02 + [0.0, 0.0, 9.80665]
            for i in range(10000):
                t, data = message(k, [float(v) for v in g[i]], [float(v) for v in a[i]])
                w.add_message(ch, log_time=t, publish_time=t, data=data, sequence=k)
                k += 1
        w.finish()
    print(k)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], float(sys.argv[2]))
