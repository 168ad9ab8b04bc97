# What the throughput benchmarks share, sourced first: strict mode, the
# repository root as the working directory, the release build of imutherm
# under $target, and a timing of `imutherm info` on one file.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
target=${CARGO_TARGET_DIR:-target}
cargo build --release -q -p imutherm

# The best of three runs of `imutherm info FILE`, whole process, page cache
# warm: sets best (wall seconds) and best_rss (peak resident set, kB).
time_info() {
  local file=$1 out secs rss_kb
  cat "$file" > /dev/null # warm the page cache
  best=""
  for _ in 1 2 3; do
    out=$( { /usr/bin/time -f "%e %M" "$target/release/imutherm" info "$file" > /dev/null; } 2>&1 | tail -n 1)
    read -r secs rss_kb <<< "$out"
    if [[ -z $best ]] || awk -v a="$secs" -v b="$best" 'BEGIN{exit !(a<b)}'; then best=$secs; best_rss=$rss_kb; fi
  done
}

# Prints the file's size and what it holds (DESCRIPTION), the best time as
# MB/s, and the peak memory against SAMPLES decoded samples of seven f64.
print_info_speed() {
  local file=$1 description=$2 samples=$3
  awk -v b="$(stat -c %s "$file")" -v s="$best" -v n="$samples" -v rss="$best_rss" -v what="$description" 'BEGIN{
    data = n * 7 * 8
    printf "file           %.0f MB, %s\n", b/1e6, what
    printf "imutherm info  %.2f s (best of 3)  ->  %.0f MB/s\n", s, b/1e6/s
    printf "peak memory    %.0f MB = %.2f x the decoded data (%.0f MB)\n", rss*1024/1e6, rss*1024/data, data/1e6
  }'
}
