#!/usr/bin/env bash
# Regression benchmarks: a handful of figures, each printed next to the one recorded in bench/baseline.tsv.
#   bash scripts/bench.sh            # measure and compare (under two minutes)
#   bash scripts/bench.sh --record   # measure and write the figures to bench/baseline.tsv
# Builds nothing: it runs ./build/polarcam and the benchmark programs there (build them first:
# cmake --build build --target polarcam polarcam_bench_digitize polarcam_bench_area_error).
# Rates are per CPU-second and times are CPU seconds (user + system), so a loaded machine disturbs them less than
# wall time (but the figure named *_wall_*, of two threads: wall seconds); each figure is the best of five runs
# (the error: three, at 10^8 steps two; the report, the front and the maps: one), the run least disturbed by other
# work. On a shared
# machine figures of unchanged code have moved by up to a third: re-run before concluding.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

record=0
case "${1:-}" in
  --record) record=1 ;;
  "") ;;
  *) echo "usage: bash scripts/bench.sh [--record]" >&2; exit 2 ;;
esac

bin=build
baseline=bench/baseline.tsv
for p in polarcam polarcam_bench_digitize polarcam_bench_area_error; do
  if [ ! -x "$bin/$p" ]; then
    echo "bench.sh: $bin/$p is missing: build it first (cmake --build build --target $p)" >&2
    exit 2
  fi
done

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# name, unit ("M/s": higher is better; "s": lower is better), value
results=()
add() { results+=("$1	$2	$3"); printf '.' >&2; }

least() { sort -g | head -1; }

# A Google Benchmark counter (the best of 5 repetitions), in millions per second.
gbench() {  # name program filter counter-column
  local name=$1 prog=$2 filter=$3 col=$4
  "$bin/$prog" --benchmark_filter="$filter" --benchmark_min_time=0.3 --benchmark_repetitions=5 \
    --benchmark_format=csv 2>/dev/null >"$tmp/gb.csv"
  local v
  v=$(awk -F, -v col="$col" 'NR == 1 {for (i = 1; i <= NF; ++i) if ($i == col || $i == "\"" col "\"") c = i; next}
                             /^"BM_/ && !/_(mean|median|stddev|cv)"/ {if ($c > m) m = $c}
                             END {if (m > 0) printf "%.3f", m / 1e6}' "$tmp/gb.csv")
  [ -n "$v" ] || { echo "bench.sh: no figure from $prog $filter" >&2; exit 1; }
  add "$name" M/s "$v"
}

# Runs a command, its output dropped: exit status 0 or 1 (a NO-GO verdict) accepted, anything else ends the run.
run_ok() {
  local rc=0
  "$@" >/dev/null 2>"$tmp/err" || rc=$?
  if [ "$rc" -gt 1 ]; then
    echo "bench.sh: '$*' failed (exit $rc):" >&2
    cat "$tmp/err" >&2
    exit 1
  fi
}

# CPU seconds (user + system) of a command, the least of $runs runs (bash's `times`: millisecond resolution).
cpu() {  # name runs command...
  local name=$1 runs=$2
  shift 2
  for _ in $(seq "$runs"); do
    (
      run_ok "$@"
      times
    ) >"$tmp/times" || exit 1
    # second line: the children's user and system time, as 0m0.123s 0m0.004s
    awk 'NR == 2 {for (i = 1; i <= 2; ++i) {split($i, p, "m"); sub("s", "", p[2]); v += p[1] * 60 + p[2]} printf "%.3f\n", v}' \
      "$tmp/times"
  done | least >"$tmp/v"
  add "$name" s "$(cat "$tmp/v")"
}

# Wall seconds of a command, the least of $runs runs (for a figure that uses two threads: its CPU time is the
# same as one thread's or more).
wall() {  # name runs command...
  local name=$1 runs=$2
  shift 2
  for _ in $(seq "$runs"); do
    local t0 t1
    t0=$(date +%s%N)
    run_ok "$@"
    t1=$(date +%s%N)
    awk -v a="$t0" -v b="$t1" 'BEGIN {printf "%.3f\n", (b - a) / 1e9}'
  done | least >"$tmp/v"
  add "$name" s "$(cat "$tmp/v")"
}

gbench digitize_limacon_thesis_grid polarcam_bench_digitize 'BM_LimaconThesis/tape:0$' steps_per_s
gbench digitize_limacon_100x polarcam_bench_digitize 'BM_Limacon100x/tape:0$' steps_per_s
gbench digitize_spline_100x polarcam_bench_digitize 'BM_Spline10k100x/tape:0$' steps_per_s
gbench area_error_meter_limacon_10x polarcam_bench_area_error 'BM_AreaError/0/10$' items_per_second

# The 100x limacon as users run it, and the same job on a 1 in / 16-steps grid (22 steps: the start-up).
sed -e 's/^radial_resolution = .*/radial_resolution = "1 in"/' -e 's/^angular_steps_per_rev = .*/angular_steps_per_rev = 16/' \
  bench/jobs/limacon_100x.toml >"$tmp/coarse.toml"
cpu cli_digitize_limacon_100x 5 "$bin/polarcam" digitize bench/jobs/limacon_100x.toml --json
cpu cli_digitize_startup 5 "$bin/polarcam" digitize "$tmp/coarse.toml" --json
cpu cli_optimize_limacon 5 "$bin/polarcam" optimize examples/limacon.toml --json
cpu cli_report_witch_grinding 1 "$bin/polarcam" report examples/ch6/witch_grinding.toml -o "$tmp/report.html"
cpu cli_pareto_witch_grinding 1 "$bin/polarcam" optimize examples/ch6/witch_grinding.toml --objective pareto
# the exact area error and deviation of the 100x limacon's tape (2.2 M steps), and a 101 x 101 pole map
"$bin/polarcam" digitize bench/jobs/limacon_100x.toml -o "$tmp/limacon_100x.tape" --quiet >/dev/null
cpu cli_error_limacon_100x 3 "$bin/polarcam" error "$tmp/limacon_100x.tape" --job bench/jobs/limacon_100x.toml --json --threads 1
wall cli_error_limacon_100x_wall_2threads 3 "$bin/polarcam" error "$tmp/limacon_100x.tape" --job bench/jobs/limacon_100x.toml --json --threads 2
cpu cli_map_witch_101 1 "$bin/polarcam" optimize examples/witch.toml --map "$tmp/map.csv" --map-size 101 --quiet
# the two goals' own figures, wall time on two threads: `error` at 10^8 steps (its tape, 200 MB, digitized first and
# removed after) and the 401 x 401 map
"$bin/polarcam" digitize bench/jobs/limacon_1e8.toml -o "$tmp/limacon_1e8.tape" --quiet >/dev/null
wall cli_error_limacon_1e8_wall_2threads 2 "$bin/polarcam" error "$tmp/limacon_1e8.tape" --job bench/jobs/limacon_1e8.toml --json --threads 2
rm -f "$tmp/limacon_1e8.tape"
wall cli_map_witch_401_wall_2threads 1 "$bin/polarcam" optimize examples/witch.toml --map "$tmp/map.csv" --map-size 401 --threads 2 --quiet
echo >&2

if [ "$record" = 1 ]; then
  {
    printf '# figures of scripts/bench.sh, recorded %s on %s (%s cores)\n' "$(date -u +%Y-%m-%d)" \
      "$(grep -m1 'model name' /proc/cpuinfo | sed 's/.*: //')" "$(nproc)"
    printf '# name\tunit\tvalue\n'
    printf '%s\n' "${results[@]}"
  } >"$baseline"
  echo "recorded in $baseline:"
fi

printf '%-32s %12s %12s %8s\n' figure now recorded change
for line in "${results[@]}"; do
  IFS=$'\t' read -r name unit value <<<"$line"
  old=""
  [ -f "$baseline" ] && old=$(awk -F'\t' -v n="$name" '$1 == n {print $3}' "$baseline")
  if [ -z "$old" ]; then
    printf '%-32s %8s %-3s %12s %8s\n' "$name" "$value" "$unit" "-" "-"
    continue
  fi
  # change as "better by / worse by" percent: rates up are better, times down are better
  change=$(awk -v a="$value" -v b="$old" -v u="$unit" 'BEGIN {
    if (b == 0) {print "-"; exit}
    r = (u == "s") ? b / a : a / b
    printf "%+.0f%%", (r - 1) * 100 }')
  printf '%-32s %8s %-3s %8s %-3s %8s\n' "$name" "$value" "$unit" "$old" "$unit" "$change"
done
echo "(change: + better, - worse than recorded; rates are per CPU-second, times CPU seconds but *_wall_* ones)"
