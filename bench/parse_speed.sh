#!/usr/bin/env bash
# Reader throughput on the thesis log format: generates a log of SIZE_MB
# (default 1000) and times `imutherm info` on it, whole process, page cache
# warm. Prints MB/s and peak memory against the decoded f64 data.
#   bench/parse_speed.sh [SIZE_MB]
source "$(dirname "$0")/lib.sh"
size_mb=${1:-1000}
cargo build --release -q -p imu --example make_thesis_log
mkdir -p bench/data
file=bench/data/thesis_${size_mb}mb.txt
[[ -s $file ]] || "$target/release/examples/make_thesis_log" "$file" "$size_mb"
rows=$(( $(wc -l < "$file") - 4 ))
time_info "$file"
print_info_speed "$file" "$rows rows x 7 columns" "$rows"
