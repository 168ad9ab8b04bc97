#!/usr/bin/env bash
# The selected noise model on the static ADIS16405 recordings of
# SMAC-Group/imudata (six runs of 10^6 samples at 100 Hz, about 2.8 h each).
#
# The data are CC BY-NC-SA 4.0 (imudata's LICENSE) and 3 MB each as .rda:
# they are not in this repository. Give the folder holding
# adis_16405_imu1.rda … adis_16405_imu6.rda (imudata's data/ folder):
#
#   bench/imudata/run.sh /path/to/imudata/data [WORK]
#
# Converts each to a gzip CSV (bench/imudata/convert.py, in a virtual
# environment WORK/venv with PyPI's rdata), prints `imutherm noise` on each
# into WORK/adisN.noise.txt and checks every axis with the
# imudata_check example (bench/imudata_check.rs): its Markdown table on
# standard output, status 1 when a rule is broken.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
data="${1:?usage: run.sh IMUDATA_DATA_DIR [WORK]}"
work="${2:-$root/target/imudata}"
mkdir -p "$work"
if ! "$work/venv/bin/python" -c 'import rdata' 2>/dev/null; then
  "${PYTHON:-python3}" -m venv "$work/venv"
  "$work/venv/bin/pip" install --quiet --disable-pip-version-check 'rdata==1.1.0' numpy
fi
(cd "$root" && cargo build --release -q -p imutherm -p analysis --example imudata_check)
files=()
for i in 1 2 3 4 5 6; do
  csv="$work/adis$i.csv.gz"
  [ -s "$csv" ] || "$work/venv/bin/python" "$here/convert.py" "$data/adis_16405_imu$i.rda" "$csv" >&2
  # A run the command refuses (adis4 holds 3 s of motion, which `noise`
  # names and refuses without --allow-motion) keeps its message in the
  # file; the checker below reads every run through the library.
  "$root/target/release/imutherm" noise "$csv" --rate 100 --verbose >"$work/adis$i.noise.txt" 2>&1 ||
    echo "run $i: imutherm noise exited $? (its message is in $work/adis$i.noise.txt)" >&2
  files+=("$csv")
done
"$root/target/release/examples/imudata_check" 100 "${files[@]}"
