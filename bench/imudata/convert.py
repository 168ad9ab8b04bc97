"""Converts one ADIS16405 recording of SMAC-Group/imudata (an R `imu`
object in an .rda file) into a gzip-compressed CSV that imutherm reads.

The data set's own documentation (imudata, R/data.R, `adis_16405_imu1`)
gives 100 Hz; the columns are `Gyro. X/Y/Z` and `Accel. X/Y/Z`. Their
units are not stored in the object: the gyro steps of 0.05 and the
accelerometer steps of 0.00333 are the ADIS16405's own resolutions in
°/s and g (Analog Devices, ADIS16405 data sheet, Table 1: 0.05 °/s/LSB,
3.33 mg/LSB), so the header says deg/s and g and imutherm converts them.

usage: convert.py IN.rda OUT.csv.gz
"""

import gzip
import sys
import warnings

import numpy as np
import rdata

NAMES = {
    "Gyro. X": "gyro_x[deg/s]",
    "Gyro. Y": "gyro_y[deg/s]",
    "Gyro. Z": "gyro_z[deg/s]",
    "Accel. X": "acc_x[g]",
    "Accel. Y": "acc_y[g]",
    "Accel. Z": "acc_z[g]",
}
GYRO_LSB = 0.05
ACCEL_LSB = 0.00333


def main(src: str, dst: str) -> None:
    with warnings.catch_warnings():
        # The `imu` class has no Python constructor: read as its matrix.
        warnings.simplefilter("ignore")
        objects = rdata.conversion.convert(rdata.parser.parse_file(src))
    if len(objects) != 1:
        sys.exit(f"{src}: {len(objects)} objects, expected one imu matrix")
    (matrix,) = objects.values()
    columns = [str(c) for c in matrix.coords[matrix.dims[1]].values]
    unknown = [c for c in columns if c not in NAMES]
    if unknown:
        sys.exit(f"{src}: unknown columns {unknown}")
    values = np.asarray(matrix.values, dtype=float)
    # The units above are read from the steps: say so if they do not hold.
    for j, c in enumerate(columns):
        lsb = GYRO_LSB if c.startswith("Gyro") else ACCEL_LSB
        steps = np.round(values[:, j] / lsb)
        worst = np.max(np.abs(values[:, j] - steps * lsb))
        if worst > 1e-3 * lsb:
            sys.exit(f"{src}: column {c} is not in steps of {lsb} (off by {worst:g})")
    if not np.all(np.isfinite(values)):
        sys.exit(f"{src}: non-finite values")
    with gzip.open(dst, "wt", compresslevel=6) as out:
        out.write(",".join(NAMES[c] for c in columns) + "\n")
        np.savetxt(out, values, fmt="%.5f", delimiter=",")
    print(f"{dst}: {values.shape[0]} samples of {len(columns)} channels")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
