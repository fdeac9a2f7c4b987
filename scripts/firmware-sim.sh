#!/usr/bin/env bash
# Builds the reference firmware, runs it in simavr and plays a job's tape to it twice — on a clean link and with
# 1 % of the bytes dropped and 1 % corrupted each way — then reads the step/dir pins back into a tape with
# `polarcam capture --encoding step-dir` (the decoder a logic analyser's recording goes through) and compares that
# tape with the job's, as tapes (`capture --compare`).
#
#   scripts/firmware-sim.sh JOB [POLARCAM] [OUTDIR]
#
# POLARCAM defaults to ./build/polarcam, OUTDIR to ./firmware-sim. Leaves in OUTDIR: job.tape (the job digitized,
# speed scale 1), clean.vcd and faulty.vcd (the pins), clean.json and faulty.json (what play reported),
# clean.tape and faulty.tape (the pins decoded), clean.capture.json and faulty.capture.json (the decoding and the
# comparison) and summary.txt, whose last line is the summary as one JSON object. SPEED=K plays at speed scale K
# (default 1);
# TOLERANCE=T accepts step times within T controller ticks (default 1); TOLERANCE_FAULTY=T for the faulty link
# (default TOLERANCE; "inf" checks only that every step is there, in order, in its direction); SEED=N seeds the
# faulty link's errors (default 7); UNDERRUNS=N fails a run whose controller stopped for want of items more than N
# times (default: any number). A run that fails while the simulator was starved of CPU (more than 5 ms behind the
# wall clock) is run again, up to twice. Needs avr-gcc, avr-libc, simavr's library (Debian: gcc-avr avr-libc binutils-avr
# libsimavr-dev libelf-dev). Exit status 0 when both runs pass.
set -euo pipefail

job=${1:?usage: scripts/firmware-sim.sh JOB [POLARCAM] [OUTDIR]}
polarcam=${2:-./build/polarcam}
out=${3:-./firmware-sim}
speed=${SPEED:-1}
tolerance=${TOLERANCE:-1}
tolerance_faulty=${TOLERANCE_FAULTY:-$tolerance}
max_underruns=${UNDERRUNS:-}
root=$(cd "$(dirname "$0")/.." && pwd)
polarcam=$(cd "$(dirname "$polarcam")" && pwd)/$(basename "$polarcam")
mkdir -p "$out"
out=$(cd "$out" && pwd)
fw="$out/build-avr"

make -s -C "$root/firmware" OUT="$fw" all harness >"$out/build.log"
"$polarcam" digitize "$job" -o "$out/job.tape" >/dev/null

sim_pid=
cleanup() { if [ -n "$sim_pid" ]; then kill "$sim_pid" 2>/dev/null || true; wait "$sim_pid" 2>/dev/null || true; fi; }
trap cleanup EXIT

run() {  # NAME FAULTS TOLERANCE
  local name=$1 faults=$2 tol=$3 pty=
  rm -f "$out/$name.vcd" "$out/$name.pty" "$out/$name.tape" "$out/$name.capture.json" "$out/$name.capture.log"
  local args=()
  if [ -n "$faults" ]; then args=(--faults "$faults"); fi
  "$fw/fw_sim" "$fw/polarcam_fw.elf" "$out/$name.vcd" "${args[@]}" >"$out/$name.pty" 2>"$out/$name.sim.log" &
  sim_pid=$!
  for _ in $(seq 100); do
    pty=$(head -n 1 "$out/$name.pty" 2>/dev/null || true)
    if [ -n "$pty" ]; then break; fi
    sleep 0.1
  done
  if [ -z "$pty" ]; then echo "firmware-sim: the simulator did not start (see $out/$name.sim.log)" >&2; return 3; fi
  local status=0
  "$polarcam" play "$out/job.tape" --port "$pty" --speed-scale "$speed" --json >"$out/$name.json" 2>"$out/$name.play.log" || status=$?
  kill "$sim_pid"
  wait "$sim_pid" || true
  sim_pid=
  if [ "$status" != 0 ]; then
    echo "firmware-sim: $name: play failed (exit $status): $(tail -n 1 "$out/$name.play.log")" >&2
    return 1
  fi
  # the pins as a tape (time 0 at the LED's rising edge: schedule tick 0), compared with the job's tape: every
  # step, in order, axis and direction, on the controller's tick within TOL ticks of its time / SPEED
  local tick tol_time
  tick=$(tick_ns "$out/$name.json")
  if [ "$tol" = inf ]; then tol_time="1000 s"; else tol_time="$(awk -v t="$tol" -v k="$tick" 'BEGIN { printf "%.0f", t * k }') ns"; fi
  local cstatus=0
  "$polarcam" capture "$out/$name.vcd" --encoding step-dir --origin run -o "$out/$name.tape" \
    --compare "$out/job.tape" --speed-scale "$speed" --tick "$tick ns" --tolerance "$tol_time" --json \
    >"$out/$name.capture.json" 2>"$out/$name.capture.log" || cstatus=$?
  if [ "$cstatus" = 1 ]; then
    echo "firmware-sim: $name: the pins' tape differs from the job's (see $out/$name.capture.json)" >&2
    status=1
  elif [ "$cstatus" != 0 ]; then
    echo "firmware-sim: $name: capture failed (exit $cstatus): $(tail -n 1 "$out/$name.capture.log")" >&2
    status=1
  fi
  local underruns
  underruns=$(field "$out/$name.json" underruns)
  if [ -n "$max_underruns" ] && [ "${underruns:-0}" -gt "$max_underruns" ]; then
    echo "firmware-sim: $name: $underruns underruns (at most $max_underruns accepted)" >&2
    status=1
  fi
  return "$status"
}

tick_ns() { sed -n 's/^ *"tick_ns": \([0-9.]*\).*/\1/p' "$1"; }
field() { sed -n "s/^ *\"$2\": \([^,]*\),*$/\1/p" "$1" | head -n 1; }
# a run's summary as JSON members: the comparison's figures (capture --compare) and play's
members() {
  local c="$out/$1.capture.json" p="$out/$1.json"
  [ -f "$c" ] || c=/dev/null
  [ -f "$p" ] || p=/dev/null
  local v
  for k in steps_expected steps_seen mismatches max_time_error_ns tick_ns; do
    v=$(field "$c" "$k")
    printf '"%s": %s, ' "$k" "${v:-null}"
  done
  for k in underruns retransmissions; do
    v=$(field "$p" "$k")
    printf '"%s": %s, ' "$k" "${v:-null}"
  done
  v=$(field "$c" result)
  printf '"result": %s' "${v:-\"none\"}"
}

# How far a run's simulator fell behind the wall clock, in ms (fw_sim's last line): a simulator starved of CPU by
# other work on the machine delivers the host's bytes and its acknowledgements late, and the host, which keeps
# real time, retransmits and the board's queue runs short.
lag_ms() { sed -n 's/.*at most \([0-9.]*\) ms behind the wall clock.*/\1/p' "$out/$1.sim.log" | tail -n 1; }
# A run that fails while its simulator was starved (more than 5 ms behind) is the machine's, not the firmware's:
# it is run again, up to twice, and says so; a run that fails with the simulator on time fails at once.
run_checked() {  # NAME FAULTS TOLERANCE
  local attempt lag
  for attempt in 1 2 3; do
    if run "$@"; then return 0; fi
    lag=$(lag_ms "$1")
    if [ -z "$lag" ] || ! awk -v l="$lag" 'BEGIN { exit !(l > 5) }' || [ "$attempt" = 3 ]; then return 1; fi
    echo "firmware-sim: $1: the simulator fell $lag ms behind the wall clock (a loaded machine): running it again" >&2
  done
}

status=0
run_checked clean "" "$tolerance" || status=1
run_checked faulty "drop=0.01,corrupt=0.01,seed=${SEED:-7}" "$tolerance_faulty" || status=1

{
  echo "job $job, speed scale $speed, tolerance $tolerance tick(s) clean, $tolerance_faulty faulty"
  for name in clean faulty; do
    c="$out/$name.capture.json"
    if [ -f "$c" ] && grep -q '"comparison"' "$c"; then
      echo "$name: steps_expected $(field "$c" steps_expected) steps_seen $(field "$c" steps_seen) mismatches $(field "$c" mismatches) max_time_error_ns $(field "$c" max_time_error_ns) max_raw_error_ns $(field "$c" max_raw_error_ns) max_jitter_ns $(field "$c" max_jitter_ns) result $(field "$c" result | tr -d '"')"
    else
      echo "$name: no comparison"
    fi
    [ -f "$out/$name.json" ] && echo "$name: play retransmissions $(field "$out/$name.json" retransmissions), NAKs $(field "$out/$name.json" naks), underruns $(field "$out/$name.json" underruns), bytes sent $(field "$out/$name.json" bytes_sent), duration $(field "$out/$name.json" duration_s) s, wall $(field "$out/$name.json" wall_s) s"
    grep -h '^fw_sim' "$out/$name.sim.log" 2>/dev/null | sed "s/^/$name: /"
  done
  echo "{$(members clean), \"faulty_link\": {$(members faulty)}}"
} | tee "$out/summary.txt"
exit "$status"
