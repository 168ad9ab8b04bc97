#!/usr/bin/env bash
# Reading speed on a ROS 2 MCAP bag: writes a bag of SIZE_MB (default 1000)
# of sensor_msgs/msg/Imu at 200 Hz with PyPI mcap and rosbags, then times
# `imutherm info` on it, whole process, page cache warm. Prints MB/s of the
# file and peak memory (/usr/bin/time -v) against the decoded samples: six
# axes and the per-sample time, f64 each.
#   bench/mcap_speed.sh [SIZE_MB]
set -euo pipefail
cd "$(dirname "$0")/.."
size_mb=${1:-1000}
target=${CARGO_TARGET_DIR:-target}
cargo build --release -q -p imutherm
venv=bench/.venv
[[ -x $venv/bin/python ]] || python3 -m venv "$venv"
"$venv/bin/pip" install -q rosbags==0.11.9 mcap==1.6.0 numpy
mkdir -p bench/data
file=bench/data/imu_${size_mb}mb.mcap
[[ -s $file ]] || "$venv/bin/python" bench/make_mcap.py "$file" "$size_mb" > "$file.messages"
messages=$(cat "$file.messages")
cat "$file" > /dev/null # warm the page cache
bytes=$(stat -c %s "$file")
best=""
for _ in 1 2 3; do
  log=$(mktemp)
  /usr/bin/time -v "$target/release/imutherm" info "$file" > /dev/null 2> "$log"
  secs=$(awk -F': ' '/Elapsed \(wall clock\)/ {n=split($2,p,":"); s=0; for(i=1;i<=n;i++) s=s*60+p[i]; print s}' "$log")
  rss_kb=$(awk -F': ' '/Maximum resident set size/ {print $2}' "$log")
  rm -f "$log"
  if [[ -z $best ]] || awk -v a="$secs" -v b="$best" 'BEGIN{exit !(a<b)}'; then best=$secs; best_rss=$rss_kb; fi
done
awk -v b="$bytes" -v s="$best" -v n="$messages" -v rss="$best_rss" 'BEGIN{
  data = n * 7 * 8
  printf "file           %.0f MB, %d Imu messages\n", b/1e6, n
  printf "imutherm info  %.2f s (best of 3)  ->  %.0f MB/s\n", s, b/1e6/s
  printf "peak memory    %.0f MB = %.2f x the decoded data (%.0f MB)\n", rss*1024/1e6, rss*1024/data, data/1e6
}'
