#!/usr/bin/env bash
# Every speed and memory ratio imutherm is held to, in one run, against
# AllanTools 2024.6 and pandas on the same files and against the memory
# bandwidth measured in the same run. Interleaved repetitions, ratio of the
# minima; peak memory from GNU /usr/bin/time -v. See bench/README.md.
#
#   bench/ratios.sh            full sizes (about 15 min on 2 shared cores)
#   bench/ratios.sh --all-n 1000000 --memory-s 28800   the issue's sizes
#   bench/ratios.sh --quick    small sizes, under 2 min once built
set -euo pipefail

usage() {
  cat <<'EOF'
usage: bench/ratios.sh [--quick] [--runs N] [--all-n N] [--memory-s S] [--keep]

  --quick       small sizes (parsing and adev at 10^6, --taus all at 2*10^4, an
                8-minute recording for memory): under two minutes once built
  --runs N      interleaved repetitions of each timed pair (default 3, quick 2)
  --all-n N     samples of the --taus all comparison (default 2*10^5; the
                issue's 10^6 costs 25 times as much, minutes for each tool)
  --memory-s S  seconds of the 1 kHz recording for peak memory (default 7200;
                the issue's 8-hour run is --memory-s 28800, 4 GB of text and
                about 15 min more on 2 shared cores)
  --keep        keep the simulated recording (it is deleted otherwise)

Environment: PYTHON (interpreter for bench/.venv, default python3),
CARGO_TARGET_DIR, TMPDIR (where the simulated recording goes, default /tmp).
EOF
}

quick=0
runs=""
keep=0
all_arg=""
mem_arg=""
while (($#)); do
  case "$1" in
    --quick) quick=1; shift ;;
    --runs) runs="${2:?--runs needs a number}"; shift 2 ;;
    --all-n) all_arg="${2:?--all-n needs a number}"; shift 2 ;;
    --memory-s) mem_arg="${2:?--memory-s needs a number}"; shift 2 ;;
    --keep) keep=1; shift ;;
    -h|--help) usage; exit 0 ;;
    *) echo "unknown argument: $1" >&2; usage >&2; exit 2 ;;
  esac
done

if ((quick)); then
  parse_n=1000000 adev_n=1000000 all_n=20000 total_n=20000 mem_s=480
  runs=${runs:-2}
else
  # Sizes that finish in about 15 min on 2 shared cores. --taus all and the
  # total deviations' octave grid are O(N^2) in all: x25 from 2*10^5 to 10^6.
  parse_n=10000000 adev_n=10000000 all_n=200000 total_n=200000 mem_s=7200
  runs=${runs:-3}
fi
all_n=${all_arg:-$all_n}
mem_s=${mem_arg:-$mem_s}
[[ "$all_n" =~ ^[1-9][0-9]*$ && "$mem_s" =~ ^[1-9][0-9]*$ ]] || { echo "--all-n and --memory-s take positive integers" >&2; exit 2; }
[[ "$runs" =~ ^[1-9][0-9]*$ ]] || { echo "--runs must be a positive integer" >&2; exit 2; }
mem_rate=1000
rate=100

# shellcheck source=bench/allantools_env.sh
source "$(dirname "${BASH_SOURCE[0]}")/allantools_env.sh"
out_dir="$data_dir/ratios"
mkdir -p "$out_dir"

echo "== environment"
ensure_allantools_venv
"$py" -c 'import sys, allantools, numpy, pandas
print("  python %s, allantools %s, numpy %s, pandas %s" % (sys.version.split()[0],
      allantools.__version__, numpy.__version__, pandas.__version__))'
(cd "$root" && cargo build --release -q -p imutherm &&
  cargo build --release -q -p imu --example table_parse &&
  cargo build --release -q -p allan --example allan_per_tau)
target_dir="${CARGO_TARGET_DIR:-target}"
[[ "$target_dir" = /* ]] || target_dir="$root/$target_dir"
bin="$target_dir/release/imutherm"
echo "  $("$bin" --version); $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')"
echo "  load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
/usr/bin/time -v true >/dev/null 2>&1 || { echo "GNU /usr/bin/time is needed for peak memory" >&2; exit 1; }

data_file() {
  local n=$1 file="$data_dir/gyro_$1.txt"
  if ! [[ -f "$file" ]] || (($(wc -l <"$file") != n)); then
    "$py" "$bench_dir/make_data.py" "$n" "$file"
  fi
  echo "$file"
}

# Wall seconds of one run of a shell command line.
seconds() {
  local t0 t1
  t0="$(date +%s.%N)"
  bash -c "$1" >/dev/null || { echo "failed: $1" >&2; return 1; }
  t1="$(date +%s.%N)"
  awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.4f", b - a }'
}

# Best of $runs interleaved runs of two command lines: "best_a best_b".
interleaved() {
  local a="" b="" x y
  for ((i = 0; i < runs; i++)); do
    x="$(seconds "$1")"
    y="$(seconds "$2")"
    a="$(awk -v t="$x" -v m="$a" 'BEGIN { print (m == "" || t < m) ? t : m }')"
    b="$(awk -v t="$y" -v m="$b" 'BEGIN { print (m == "" || t < m) ? t : m }')"
  done
  echo "$a $b"
}

ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", a / b }'; }
results=()
row() { results+=("$(printf '%-58s %s' "$1" "$2")"); echo "  $1: $2"; }

# ------------------------------------------------------------------ parsing
echo "== parsing, one column, N = $parse_n (one core each, MB per CPU-second)"
file="$(data_file "$parse_n")"
imu_line="$("$target_dir/release/examples/table_parse" --file "$file")"
imu_mb="$(sed -E 's/.* ([0-9.]+) MB\/CPU-s$/\1/' <<<"$imu_line")"
pd_mb="$("$py" - "$file" <<'EOF'
import os, sys, time
import pandas as pd
path = sys.argv[1]
size = os.path.getsize(path)
best = min(
    (lambda t0: (pd.read_csv(path, header=None, engine="c"), time.process_time() - t0)[1])(time.process_time())
    for _ in range(3)
)
print("%.0f" % (size / 1e6 / best))
EOF
)"
row "parsing MB/CPU-s: imutherm $imu_mb, pandas C parser $pd_mb" "imutherm/pandas $(ratio "$imu_mb" "$pd_mb") (goal >= 1 GB/s per core)"

# ------------------------------------------------------- adev, whole process
echo "== adev --taus octave, whole process, N = $adev_n"
file="$(data_file "$adev_n")"
imu_cmd="$bin adev $file --stat oadev --taus octave --rate $rate --json > $out_dir/imutherm_octave.json"
at_cmd="$py $bench_dir/allantools_oadev.py $file $rate > $out_dir/allantools_octave.json"
read -r imu_s at_s < <(interleaved "$imu_cmd" "$at_cmd")
agree="$("$py" "$bench_dir/compare_outputs.py" "$out_dir/imutherm_octave.json" "$out_dir/allantools_octave.json" "$rate" >/dev/null && echo agree || echo DISAGREE)"
row "adev octave N=$adev_n: imutherm ${imu_s} s, AllanTools+pandas ${at_s} s" "AllanTools/imutherm $(ratio "$at_s" "$imu_s") ($agree; goal >= 10)"

# ------------------------------------------------------ adev --taus all
echo "== adev --taus all, whole process, N = $all_n (one run each: O(N^2))"
file="$(data_file "$all_n")"
imu_s="$(seconds "$bin adev $file --stat oadev --taus all --rate $rate --json > $out_dir/imutherm_all.json")"
at_s="$(seconds "$py $bench_dir/allantools_oadev.py $file $rate all > $out_dir/allantools_all.json")"
agree="$("$py" "$bench_dir/compare_outputs.py" "$out_dir/imutherm_all.json" "$out_dir/allantools_all.json" "$rate" >/dev/null && echo agree || echo DISAGREE)"
row "adev all N=$all_n: imutherm ${imu_s} s, AllanTools+pandas ${at_s} s" "AllanTools/imutherm $(ratio "$at_s" "$imu_s") ($agree; goal >= 10)"

# --------------------------------------- per-tau cost against a memory pass
echo "== O(N) statistics per tau against one memory pass (allan_per_tau, 10^7 points, one thread)"
# The factors where each statistic's reads change character: m = 2 and 3
# read the decimated points of the non-overlapped sums across shared
# lines, from m = 1024 MDEV's oldest streams come from L2, and a large m
# that is not a multiple of 2048 keeps OADEV's overlapped sums in block
# order.
pass_m="1,2,3,16,256,1024,3000,4096"
per_tau="$(ALLAN_PER_TAU_M="$pass_m" "$target_dir/release/examples/allan_per_tau" 20000)"
sed 's/^/  /' <<<"$per_tau"
# The worst averaging factor of each statistic, in passes of the memory
# bandwidth measured in the same run.
while read -r stat worst at; do
  row "per tau, $stat, worst of m = ${pass_m//,/, }" "$worst passes at m = $at (goal <= 1.5)"
done < <(awk '/against one memory pass/ { on = 1; next } /^-- / { on = 0 }
  on && $1 ~ /^(oadev|mdev|hdev)$/ { if (!($1 in w) || $4 > w[$1]) { w[$1] = $4; m[$1] = $2 } }
  END { for (s in w) print s, w[s], m[s] }' <<<"$per_tau" | sort)

# ------------------------------------------------------ total deviations
echo "== total deviations, octave taus, whole process, N = $total_n"
file="$(data_file "$total_n")"
for stat in totdev mtotdev ttotdev htotdev theo1; do
  s="$(seconds "$bin adev $file --stat $stat --taus octave --rate $rate --json")"
  row "$stat octave N=$total_n" "${s} s (goal at 10^6: <= 10 s)"
done

# ------------------------------------------------------------------ memory
rows_n=$((mem_s * mem_rate))
rec="${TMPDIR:-/tmp}/imutherm_ratios_cooling.txt"
echo "== peak memory on a simulated cooling run: $mem_s s at $mem_rate Hz ($rows_n rows x 7 columns) in $rec"
"$bin" simulate --preset mpu9250-thesis --profile cooling:100:20:1800 --duration "$mem_s" --rate "$mem_rate" \
  --allow-large -o "$rec" --overwrite 2>/dev/null
decoded=$((rows_n * 7 * 8))
report_dir="$out_dir/report"
for cmd in "noise $rec" "thermal $rec" "report $rec --out $report_dir"; do
  /usr/bin/time -v -o "$out_dir/time.txt" bash -c "$bin $cmd >/dev/null 2>&1" || { echo "failed: $cmd" >&2; exit 1; }
  kb="$(awk -F: '/Maximum resident set size/ { print $2 + 0 }' "$out_dir/time.txt")"
  wall="$(awk -F': ' '/Elapsed \(wall clock\)/ { print $2 }' "$out_dir/time.txt")"
  row "peak RSS ${cmd%% *}: $((kb / 1024)) MiB in $wall, decoded $((decoded / 1048576)) MiB" \
    "$(awk -v k="$kb" -v d="$decoded" 'BEGIN { printf "%.2f", k * 1024 / d }')x the data (goal <= 1.3)"
done
((keep)) || rm -f "$rec"

echo
echo "== ratios ($(nproc) cores; load average at end: $(cut -d' ' -f1-3 /proc/loadavg); best of $runs interleaved runs)"
for r in "${results[@]}"; do
  echo "$r"
done
