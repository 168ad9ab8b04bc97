#!/usr/bin/env bash
# Simulator speed: 10^7 samples (6 axes + temperature) of the mpu9250-thesis
# preset, generated in memory, then written as an imutherm log (to /dev/null
# and to a file). Prints samples per second.
#   bench/simulate.sh [SAMPLES]
source "$(dirname "$0")/lib.sh"
samples=${1:-10000000}
cargo build --release -q -p imusim --example throughput
"$target/release/examples/throughput" "$samples"
duration=$(awk -v n="$samples" 'BEGIN{printf "%.3f", n/100}')
for out in /dev/null bench/data/simulated.txt; do
  mkdir -p bench/data
  start=$(date +%s.%N)
  "$target/release/imutherm" simulate --duration "$duration" --rate 100 -o "$out" 2>/dev/null
  end=$(date +%s.%N)
  awk -v s="$start" -v e="$end" -v n="$samples" -v o="$out" \
    'BEGIN{printf "imutherm simulate -o %-26s %.2f s: %.2f M samples/s\n", o, e-s, n/(e-s)/1e6}'
done
rm -f bench/data/simulated.txt
