#!/usr/bin/env bash
# Fuzzes every parser (docs/fuzzing.md): builds the libFuzzer harnesses of fuzz/ with clang-14 under ASan+UBSan in
# the sanitized build directory (build-asan/, shared with SANITIZE=1 scripts/test.sh; the normal build is not
# touched; FUZZ_BUILD_DIR names another), replays the inputs of fuzz/regressions/, then runs each harness for
# SECONDS (default 5), as many side by side as there are cores (FUZZ_JOBS), and prints their executions. Exit
# status 1 when any harness found something (its input is saved in build-asan/artifacts/).
#   bash scripts/fuzz.sh 5                      # the CI smoke run
#   FUZZ_TARGETS="tape thr" bash scripts/fuzz.sh 600   # some targets, longer
#   FUZZ_RUNS=1000000 bash scripts/fuzz.sh 600  # each target until it has run this many inputs (or 600 s)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
secs="${1:-5}"
dir="${FUZZ_BUILD_DIR:-build-asan}"
all="tape job_toml machine_toml thr svg dxf csv_points units expr options protocol_host protocol_controller image vcd"
all="$all signal_csv"
all="$all drives_toml"
read -r -a targets <<< "${FUZZ_TARGETS:-$all}"

bash scripts/configure-sanitized.sh "$dir"
cmake --build "$dir" --parallel "$(nproc)" --target "${targets[@]/#/fuzz_}"

# Seeds from the examples and the test data, beside the small ones checked in under fuzz/corpus/.
seeds() {  # target -> the files that seed it
  case "$1" in
    job_toml) ls examples/*.toml examples/ch5/*.toml examples/ch6/*.toml ;;
    machine_toml) ls examples/machines/*.toml tests/data/cli/machines/*.toml ;;
    thr) find examples/patterns -name '*.thr' -size -16k ;;
    svg) ls examples/patterns/*.svg tests/data/svg/*.svg ;;
    dxf) ls examples/*.dxf ;;
    image) ls examples/templates/*.png ;;
    drives_toml) ls examples/drives/*.toml ;;
  esac 2> /dev/null || true
}

export ASAN_OPTIONS="detect_leaks=1:${ASAN_OPTIONS:-}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:${UBSAN_OPTIONS:-}"
# One harness: regressions, then the timed run. Prints its lines into $dir/$t.summary; exit status 1 on a finding.
fuzz_one() {
  local t="$1" bin="$dir/fuzz_$1"
  local corpus="$dir/corpus/$t" seed="$dir/seeds/$t" art="$dir/artifacts/$t"
  mkdir -p "$corpus" "$seed" "$art"
  local files f
  mapfile -t files < <(seeds "$t")
  for f in "${files[@]}"; do cp "$f" "$seed/${f//\//_}"; done
  local dirs=("$seed")
  [ -d "fuzz/corpus/$t" ] && dirs+=("fuzz/corpus/$t")
  echo "== fuzz_$t"
  if [ -d "fuzz/regressions/$t" ] && [ -n "$(ls -A "fuzz/regressions/$t")" ]; then
    if ! "$bin" -runs=1 "fuzz/regressions/$t"/* > "$dir/$t.regressions.log" 2>&1; then
      echo "fuzz_$t: a regression input fails again (log: $dir/$t.regressions.log)"
      return 1
    fi
    echo "fuzz_$t: $(ls "fuzz/regressions/$t" | wc -l) regression inputs pass"
  fi
  local limit=(-max_total_time="$secs" -seed=1)  # a fixed seed: the same run on every machine
  [ -n "${FUZZ_RUNS:-}" ] && limit+=(-runs="$FUZZ_RUNS")
  if "$bin" "${limit[@]}" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$art/" \
      "$corpus" "${dirs[@]}" > "$dir/$t.log" 2>&1; then
    local runs rate
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$dir/$t.log")
    rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$dir/$t.log")
    echo "fuzz_$t: $runs executions, $rate/s, corpus $(ls "$corpus" | wc -l) inputs"
  else
    echo "fuzz_$t: FOUND SOMETHING (log: $dir/$t.log; input in $art/)"
    grep -m3 -E 'ERROR|runtime error|terminate|deadly|timeout' "$dir/$t.log" || true
    return 1
  fi
}

# The harnesses run side by side, one a core (FUZZ_JOBS to change that); their lines are printed in order.
jobs_max="${FUZZ_JOBS:-$(nproc)}"
for t in "${targets[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$jobs_max" ]; do wait -n || true; done
  ( if fuzz_one "$t" > "$dir/$t.summary" 2>&1; then echo 0; else echo 1; fi > "$dir/$t.status" ) &
done
wait
failed=()
for t in "${targets[@]}"; do
  cat "$dir/$t.summary"
  [ "$(cat "$dir/$t.status")" = 0 ] || failed+=("$t")
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzzing found problems in: ${failed[*]}"
  exit 1
fi
