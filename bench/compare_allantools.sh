#!/usr/bin/env bash
# Times `imutherm adev` against AllanTools 2024.6 on the same files, whole
# process against whole process, and checks that both give the same numbers.
# See bench/README.md.
set -euo pipefail

usage() {
  cat <<'EOF'
usage: bench/compare_allantools.sh [--sizes 1e6,1e7] [--quick] [--runs N] [--no-hyperfine]

  --sizes LIST  sample counts to benchmark, comma separated (default 1e6,1e7)
  --quick       same as --sizes 1e5,1e6
  --runs N      timed runs per tool and size; the best is reported (default 3)
  --no-hyperfine  time with date +%s.%N even when hyperfine is installed

Environment: PYTHON (interpreter for the virtual environment, default python3),
CARGO_TARGET_DIR (honoured when locating the binary), RAYON_NUM_THREADS
(passed through to imutherm, e.g. 1 for a single-core comparison).
EOF
}

sizes="1e6,1e7"
runs=3
use_hyperfine=1
while (($#)); do
  case "$1" in
    --sizes) sizes="${2:?--sizes needs a list}"; shift 2 ;;
    --sizes=*) sizes="${1#--sizes=}"; shift ;;
    --quick) sizes="1e5,1e6"; shift ;;
    --runs) runs="${2:?--runs needs a number}"; shift 2 ;;
    --runs=*) runs="${1#--runs=}"; shift ;;
    --no-hyperfine) use_hyperfine=0; shift ;;
    -h|--help) usage; exit 0 ;;
    *) echo "unknown argument: $1" >&2; usage >&2; exit 2 ;;
  esac
done
[[ "$runs" =~ ^[1-9][0-9]*$ ]] || { echo "--runs must be a positive integer" >&2; exit 2; }

rate=100
# shellcheck source=bench/allantools_env.sh
source "$(dirname "${BASH_SOURCE[0]}")/allantools_env.sh"
out_dir="$data_dir/results"
mkdir -p "$out_dir"

# ---------------------------------------------------------------- Python side
echo "== AllanTools environment ($venv)"
ensure_allantools_venv
"$py" -c 'import sys, allantools, numpy, pandas, scipy
print("  python %s, allantools %s, numpy %s, pandas %s, scipy %s" % (sys.version.split()[0],
      allantools.__version__, numpy.__version__, pandas.__version__, scipy.__version__))'

# ------------------------------------------------------------------ Rust side
echo "== building imutherm"
(cd "$root" && cargo build --release -p imutherm)
target_dir="${CARGO_TARGET_DIR:-target}"
# cargo resolves a relative CARGO_TARGET_DIR against the directory it runs in.
[[ "$target_dir" = /* ]] || target_dir="$root/$target_dir"
bin="$target_dir/release/imutherm"
[[ -x "$bin" ]] || { echo "no binary at $bin" >&2; exit 1; }
echo "  $("$bin" --version) at $bin"

# ----------------------------------------------------------------------- data
ns=()
IFS=',' read -r -a size_list <<<"$sizes"
for s in "${size_list[@]}"; do
  # printf turns 1e6 into 1000000 and rejects anything that is not a number.
  n="$(printf '%.0f' "$s" 2>/dev/null)" || { echo "bad size: $s" >&2; exit 2; }
  ((n >= 100)) || { echo "size too small: $s" >&2; exit 2; }
  ns+=("$n")
done

echo "== data ($data_dir)"
for n in "${ns[@]}"; do
  file="$data_dir/gyro_$n.txt"
  if [[ -f "$file" ]] && (($(wc -l <"$file") == n)); then
    echo "  reusing $file"
  else
    echo "  writing $file"
    "$py" "$bench_dir/make_data.py" "$n" "$file"
  fi
done

# --------------------------------------------------------------------- timing
have_hyperfine=0
((use_hyperfine)) && command -v hyperfine >/dev/null 2>&1 && have_hyperfine=1
have_time=0
/usr/bin/time -v true >/dev/null 2>&1 && have_time=1
echo "== machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo 2>/dev/null | cut -d: -f2- | sed 's/^ *//')"
if ((have_hyperfine)); then
  echo "   timing with $(hyperfine --version), best of $runs runs"
else
  echo "   timing with date +%s.%N (hyperfine not installed or not wanted), best of $runs runs"
fi
((have_time)) || echo "   /usr/bin/time -v not available: peak RSS not measured"

# Peak RSS in MiB of one run of a shell command line, or "n/a".
peak_rss() {
  if ((have_time)); then
    /usr/bin/time -v -o "$out_dir/time.txt" bash -c "$1" || { echo "failed: $1" >&2; return 1; }
    awk -F: '/Maximum resident set size/ { printf "%.0f", $2 / 1024 }' "$out_dir/time.txt"
  else
    bash -c "$1" || { echo "failed: $1" >&2; return 1; }
    echo "n/a"
  fi
}

# Best wall time in seconds of $runs runs of a shell command line.
best_of() {
  local best="" t0 t1
  for ((i = 0; i < runs; i++)); do
    t0="$(date +%s.%N)"
    bash -c "$1" || { echo "failed: $1" >&2; return 1; }
    t1="$(date +%s.%N)"
    best="$(awk -v a="$t0" -v b="$t1" -v best="$best" \
      'BEGIN { t = b - a; if (best == "" || t < best) best = t; printf "%.4f", best }')"
  done
  echo "$best"
}

rows=()
status=0
for n in "${ns[@]}"; do
  file="$data_dir/gyro_$n.txt"
  imu_json="$out_dir/imutherm_$n.json"
  at_json="$out_dir/allantools_$n.json"
  imu_cmd="$(printf '%q' "$bin") adev $(printf '%q' "$file") --stat oadev --taus octave --rate $rate --json > $(printf '%q' "$imu_json")"
  at_cmd="$(printf '%q' "$py") $(printf '%q' "$bench_dir/allantools_oadev.py") $(printf '%q' "$file") $rate > $(printf '%q' "$at_json")"

  echo "== N = $n"
  # One untimed run of each: the outputs to compare, the peak memory, and a
  # warm page cache for the timed runs, so neither tool pays for the disk.
  imu_rss="$(peak_rss "$imu_cmd")"
  at_rss="$(peak_rss "$at_cmd")"
  if "$py" "$bench_dir/compare_outputs.py" "$imu_json" "$at_json" "$rate"; then
    agree="yes"
  else
    agree="NO"
    status=1
  fi
  "$py" -c 'import json, sys
r = json.load(open(sys.argv[1]))
print("  AllanTools inside the process: read %.2f s, oadev %.2f s" % (r["read_seconds"], r["compute_seconds"]))' "$at_json"

  if ((have_hyperfine)); then
    hyperfine --runs "$runs" --export-json "$out_dir/hyperfine_$n.json" \
      -n imutherm "$imu_cmd" -n allantools "$at_cmd" >&2
    read -r imu_s at_s < <("$py" -c 'import json, sys
r = {x["command"]: x["min"] for x in json.load(open(sys.argv[1]))["results"]}
print("%.4f %.4f" % (r["imutherm"], r["allantools"]))' "$out_dir/hyperfine_$n.json")
  else
    imu_s="$(best_of "$imu_cmd")"
    at_s="$(best_of "$at_cmd")"
  fi
  ratio="$(awk -v a="$at_s" -v b="$imu_s" 'BEGIN { printf "%.1f", a / b }')"
  rows+=("$(printf '%10s  %12s  %14s  %6s  %14s  %16s  %5s' \
    "$n" "$imu_s" "$at_s" "$ratio" "$imu_rss" "$at_rss" "$agree")")
done

echo
echo "OADEV, octave taus, rate $rate Hz; seconds are wall time of the whole process, best of $runs runs;"
echo "ratio = AllanTools / imutherm (above 1: imutherm is faster); RSS = peak resident memory."
printf '%10s  %12s  %14s  %6s  %14s  %16s  %5s\n' \
  "N" "imutherm [s]" "AllanTools [s]" "ratio" "imutherm [MiB]" "AllanTools [MiB]" "agree"
for row in "${rows[@]}"; do
  echo "$row"
done
if ((status)); then
  echo "WARNING: imutherm and AllanTools disagree (see above); the timings compare different results." >&2
fi
exit "$status"
