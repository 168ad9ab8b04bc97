#!/usr/bin/env python3
"""Writes N rows of a 7-column IMU table (time and six axes) to standard output.

    gen_rows.py 10000000 | imutherm info -

A large, legitimate text to read through a pipe, whose size the reader
cannot know beforehand: the case the columns' cap for a stream must admit.
"""

import sys

n = int(sys.argv[1]) if len(sys.argv) > 1 else 10**7
out = sys.stdout
out.write("time[s],accel_x[m/s^2],accel_y[m/s^2],accel_z[m/s^2],gyro_x[rad/s],gyro_y[rad/s],gyro_z[rad/s]\n")
# Distinct values cycling with a prime period, so the rows are not all alike.
axes = [
    "%.5f,%.5f,9.%05d,%.6f,%.6f,%.6f"
    % ((k % 97) * 1e-3, (k % 89) * 1e-3, k % 99991, (k % 83) * 1e-5, (k % 79) * 1e-5, (k % 73) * 1e-5)
    for k in range(10007)
]
buf = []
for i in range(n):
    buf.append("%d.%02d,%s\n" % (i // 100, i % 100, axes[i % 10007]))
    if len(buf) == 100000:
        out.write("".join(buf))
        buf = []
out.write("".join(buf))
