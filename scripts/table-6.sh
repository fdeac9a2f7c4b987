#!/usr/bin/env bash
# Reproduces the tables of docs/optimum-loading.md (Tables 6.1 and 6.2 of the thesis, pole placement for balanced
# axis torque and the largest load and speed) with the polarcam executable: for the four contours of examples/ch6
# under an inertial load (two masses) and grinding (two depths of cut), the balanced-torque objective at the job's
# pole and at the optimum `polarcam optimize --objective balanced` finds, the largest torque ratio of each axis
# there, and what `polarcam capacity` gives at the optimum (largest load at the job's speed, largest speed at the
# job's load, and the speed at which a motor reaches its top step rate). Prints Markdown.
# Usage: bash scripts/table-6.sh [path/to/polarcam]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bin=$(realpath "${1:-./build/polarcam}")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/machines" "$tmp/ch6"
cp examples/machines/fahim1983.toml "$tmp/machines/"

# the value of a top-level key in polarcam's JSON output
val() { grep -m1 "^  \"$1\":" | sed -e 's/^[^:]*: //' -e 's/,$//'; }
# the value of a key of the "start" object of `optimize --json`
start_val() { sed -n '/^  "start": {/,/^  }/p' | grep -m1 "^    \"$1\":" | sed -e 's/^[^:]*: //' -e 's/,$//'; }
num() { if [ "$1" = null ]; then printf "inf"; else printf "%.${2}f" "$1"; fi; }

# row BASE LOADKEY LOADVALUE LABEL
row() {
  local base=$1 key=$2 value=$3 label=$4
  sed -e "s|^$key = .*|$key = \"$value\"|" "examples/ch6/$base.toml" > "$tmp/ch6/job.toml"
  local opt cap
  opt=$("$bin" optimize "$tmp/ch6/job.toml" --objective balanced --json --write-job "$tmp/ch6/best.toml")
  cap=$("$bin" capacity "$tmp/ch6/best.toml" --json)
  local measure load_key load_fmt
  measure=$(echo "$cap" | val load_measure | tr -d '"')
  if [ "$measure" = mass ]; then load_key=max_mass_kg; load_fmt="%.0f kg"; else load_key=max_depth_mm; load_fmt="%.3f mm"; fi
  printf "| %s | %s | %s | %s mm, %s rad | %s | %s | %s | %s | %s | %s cm/s | %s cm/s | %s s |\n" \
    "${base%%_*}" "$label" "$(num "$(echo "$opt" | start_val balanced_objective)" 4)" \
    "$(num "$(echo "$opt" | val C_mm)" 1)" "$(num "$(echo "$opt" | val beta_rad)" 3)" \
    "$(num "$(echo "$opt" | val objective)" 4)" \
    "$(num "$(echo "$opt" | val max_torque_ratio_radial)" 4)" "$(num "$(echo "$opt" | val max_torque_ratio_angular)" 4)" \
    "$(echo "$opt" | val verdict | tr -d '"')" \
    "$(printf "$load_fmt" "$(echo "$cap" | val "$load_key")")" \
    "$(num "$(echo "$cap" | val max_speed_mps | awk '{print $1 * 100}')" 3)" \
    "$(num "$(echo "$cap" | val max_speed_step_rate_mps | awk '{print $1 * 100}')" 3)" \
    "$(num "$(echo "$opt" | val wall_s)" 2)"
}

header() {
  echo "| contour | load | objective at the job's pole | optimum pole (C, beta) | objective | max ratio R | max ratio theta | verdict | largest load at the job's speed | largest speed (torque) | speed at the top step rate | search time |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
}

echo "#### Table 6.1: inertial load, V_t = 1.524 cm/s (3 ft/min), safety factor 1.2"
echo
header
for c in circle witch limacon serpentine; do
  row "${c}_inertial" mass "43.77 kg" "43.77 kg (3 slug)"
  row "${c}_inertial" mass "145.9 kg" "145.9 kg (10 slug)"
done
echo
echo "#### Table 6.2: grinding, V_t = 1.016 cm/s (2 ft/min), safety factor 1.2"
echo
header
for c in circle witch limacon serpentine; do
  row "${c}_grinding" depth "0.001 in" "depth 0.0254 mm (0.001 in)"
  row "${c}_grinding" depth "0.002 in" "depth 0.0508 mm (0.002 in)"
done
