#!/usr/bin/env bash
# Reader throughput on the thesis log format: generates a log of SIZE_MB
# (default 1000) and times `imutherm info` on it, whole process, page cache
# warm. Prints MB/s and peak memory against the decoded f64 data.
#   bench/parse_speed.sh [SIZE_MB]
set -euo pipefail
cd "$(dirname "$0")/.."
size_mb=${1:-1000}
target=${CARGO_TARGET_DIR:-target}
cargo build --release -q -p imutherm
cargo build --release -q -p imu --example make_thesis_log
mkdir -p bench/data
file=bench/data/thesis_${size_mb}mb.txt
[[ -s $file ]] || "$target/release/examples/make_thesis_log" "$file" "$size_mb"
cat "$file" > /dev/null # warm the page cache
bytes=$(stat -c %s "$file")
rows=$(( $(wc -l < "$file") - 4 ))
best=""
for _ in 1 2 3; do
  out=$( { /usr/bin/time -f "%e %M" "$target/release/imutherm" info "$file" > /dev/null; } 2>&1 | tail -n 1)
  read -r secs rss_kb <<< "$out"
  if [[ -z $best ]] || awk -v a="$secs" -v b="$best" 'BEGIN{exit !(a<b)}'; then best=$secs; best_rss=$rss_kb; fi
done
awk -v b="$bytes" -v s="$best" -v r="$rows" -v rss="$best_rss" 'BEGIN{
  data = r * 7 * 8
  printf "file           %.0f MB, %d rows x 7 columns\n", b/1e6, r
  printf "imutherm info  %.2f s (best of 3)  ->  %.0f MB/s\n", s, b/1e6/s
  printf "peak memory    %.0f MB = %.2f x the decoded data (%.0f MB)\n", rss*1024/1e6, rss*1024/data, data/1e6
}'
