#!/usr/bin/env bash
# Reading speed on a ROS 2 MCAP bag: writes a bag of SIZE_MB (default 1000)
# of sensor_msgs/msg/Imu at 200 Hz with PyPI mcap and rosbags, then times
# `imutherm info` on it, whole process, page cache warm. Prints MB/s of the
# file and peak memory against the decoded samples: six
# axes and the per-sample time, f64 each.
#   bench/mcap_speed.sh [SIZE_MB]
source "$(dirname "$0")/lib.sh"
size_mb=${1:-1000}
venv=bench/.venv
[[ -x $venv/bin/python ]] || python3 -m venv "$venv"
"$venv/bin/pip" install -q rosbags==0.11.9 mcap==1.6.0 numpy
mkdir -p bench/data
file=bench/data/imu_${size_mb}mb.mcap
[[ -s $file ]] || "$venv/bin/python" bench/make_mcap.py "$file" "$size_mb" > "$file.messages"
messages=$(cat "$file.messages")
time_info "$file"
print_info_speed "$file" "$messages Imu messages" "$messages"
