#!/usr/bin/env bash
# Reproduces the comparison tables of docs/compare.md with the polarcam executable: `polarcam compare` on every
# example job (the thesis's test contours and the standard test pieces), the Cartesian machine once as a DDA
# control of the thesis's era and once with exact step times. Prints Markdown.
# Usage: bash scripts/compare-table.sh [path/to/polarcam]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bin=$(realpath "${1:-./build/polarcam}")
jobs="limacon witch serpentine circle testpiece_square testpiece_diamond testpiece_circle"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# get SECTION KEY < json: a number or string of the "polar" or "cartesian" member
get() {
  awk -v sec="$1" -v key="$2" '
    /^  "[a-z_]+": \{/ { match($0, /"[a-z_]+"/); cur = substr($0, RSTART + 1, RLENGTH - 2); next }
    /^  [}\]]/ { cur = "" }
    cur == sec && index($0, "    \"" key "\": ") == 1 { v = $0; sub(/^[^:]*: /, "", v); sub(/,$/, "", v); gsub(/"/, "", v); print v; exit }'
}
# winners < json: the winner of each verdict, in order, as P, C or =
winners() { grep '^      "winner": ' | sed -e 's/.*: "//' -e 's/".*//' -e 's/^polar$/P/' -e 's/^cartesian$/C/' -e 's/^tie$/=/' | paste -sd' ' -; }
f() { printf "%.${2}f" "$1"; }

for m in dda exact; do
  for j in $jobs; do "$bin" compare "examples/$j.toml" --method "$m" --json > "$tmp/$j.$m.json"; done
done

for m in dda exact; do
  if [ "$m" = dda ]; then
    echo "### Cartesian machine: DDA control (lines and arcs within BLU/4, 5 kHz interrupts)"
  else
    echo "### Cartesian machine: exact step times"
  fi
  echo
  echo "Each cell: polar / Cartesian."
  echo
  echo "| job | steps | time (s) | speed RMS dev. (mm/s) | area error (mm²) | deviation (mm) | highest step rate (Hz) | tape (kB) | worst resolution (mm) |"
  echo "|---|---|---|---|---|---|---|---|---|"
  for j in $jobs; do
    x="$tmp/$j.$m.json"
    pc() { echo "$(f "$(get polar "$1" < "$x")" "$2") / $(f "$(get cartesian "$1" < "$x")" "$2")"; }
    kb() { get "$1" tape_bytes < "$x" | awk '{ printf "%.1f", $1 / 1000 }'; }
    mms() { get "$1" speed_rms_dev_mps < "$x" | awk '{ printf "%.3g", $1 * 1000 }'; }
    echo "| $j | $(get polar steps_total < "$x") / $(get cartesian steps_total < "$x") | $(pc duration_s 3) |" \
         "$(mms polar) / $(mms cartesian) |" \
         "$(pc area_error_mm2 3) | $(pc deviation_max_mm 4) | $(pc max_step_rate_hz 0) | $(kb polar) / $(kb cartesian) |" \
         "$(pc resolution_worst_mm 4) |"
  done
  echo
done

echo "### Which machine wins, per attribute"
echo
echo "P: the polar machine, C: the Cartesian one, =: a tie. Attributes in the order of the report: contouring speed,"
echo "contouring time, area error, largest deviation, resolution at the worst point, highest step rate, tape size,"
echo "speed scaling without reprocessing (x2), size scaling by one axis (x1/2)."
echo
echo "| job | against the DDA control | against exact step times |"
echo "|---|---|---|"
for j in $jobs; do
  echo "| $j | $(winners < "$tmp/$j.dda.json") | $(winners < "$tmp/$j.exact.json") |"
done
