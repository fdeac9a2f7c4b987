#!/usr/bin/env bash
# Reproduces the tables of docs/table-4-1.md (Table 4.1 of the thesis, pole placement for minimum area error) with
# the polarcam executable: for the witch, the limacon and the serpentine of examples/, the area error of both
# stepping rules and F1 at the thesis's poles, at the F1 + Hooke-Jeeves optimum and at the exact-area + NLopt
# optimum. Prints Markdown. Usage: bash scripts/table-4-1.sh [path/to/polarcam]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bin=$(realpath "${1:-./build/polarcam}")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/machines"
cp examples/machines/fahim1983.toml "$tmp/machines/"

# the value of a top-level key in polarcam's JSON output
val() { grep -m1 "^  \"$1\":" | sed -e 's/^[^:]*: //' -e 's/,$//'; }
num() { printf "%.${2}f" "$1"; }

# job NAME BASE C BETA RULE: a copy of examples/BASE.toml with another placement (C and BETA with units) and rule
job() {
  sed -e "s|^C = .*|C = \"$3\"|" -e "s|^beta = .*|beta = \"$4\"|" -e '/^rule = /d' \
      -e "s|^\[motion\]|[motion]\nrule = \"$5\"|" "examples/$2.toml" > "$tmp/$1.toml"
}
# rule_of FILE RULE: a copy of a written job with another rule
rule_of() {
  sed -e '/^rule = /d' -e "s|^\[motion\]|[motion]\nrule = \"$2\"|" "$1" > "${1%.toml}_$2.toml"
}
# area FILE: exact area error (mm^2) of the job's tape; f1 FILE: F1 on 100 chords
area() { "$bin" digitize "$1" -o "$tmp/t.tape" > /dev/null && "$bin" error "$tmp/t.tape" --job "$1" --json | val area_error_mm2; }
f1() { "$bin" digitize "$1" -o "$tmp/t.tape" > /dev/null && "$bin" error "$tmp/t.tape" --job "$1" --json | val F1_chords; }

row() {  # row LABEL BASE C BETA [THESIS_AREA]: areas of both rules at a placement given in units
  job r_n "$2" "$3" "$4" nearest
  job r_t "$2" "$3" "$4" thesis
  printf "| %s | %s | %s | %s | %s | %s | %s |\n" "$1" "$3" "$4" "$(num "$(f1 "$tmp/r_n.toml")" 4)" \
    "$(num "$(area "$tmp/r_n.toml")" 3)" "$(num "$(area "$tmp/r_t.toml")" 3)" "${5:-}"
}

optrow() {  # optrow LABEL BASE RULE OPTIONS...: optimise, then both rules at the optimum
  local label=$1 base=$2 rule=$3
  shift 3
  job o "$base" "$(grep -m1 '^C = ' "examples/$base.toml" | sed 's/^C = "\(.*\)"/\1/')" \
    "$(grep -m1 '^beta = ' "examples/$base.toml" | sed 's/^beta = "\(.*\)"/\1/')" "$rule"
  local out
  out=$("$bin" optimize "$tmp/o.toml" --json --write-job "$tmp/best.toml" "$@")
  rule_of "$tmp/best.toml" nearest
  rule_of "$tmp/best.toml" thesis
  printf "| %s | %s mm | %s rad | %s | %s | %s | %s evaluations, %s s |\n" "$label" "$(num "$(echo "$out" | val C_mm)" 2)" \
    "$(num "$(echo "$out" | val beta_rad)" 4)" "$(num "$(f1 "$tmp/best_nearest.toml")" 4)" \
    "$(num "$(area "$tmp/best_nearest.toml")" 3)" "$(num "$(area "$tmp/best_thesis.toml")" 3)" \
    "$(echo "$out" | val evaluations)" "$(num "$(echo "$out" | val wall_s)" 2)"
}

header() {
  echo
  echo "### $1"
  echo
  echo "| placement | C | beta | F1 | area, nearest (mm^2) | area, thesis rule (mm^2) | thesis's area, or the search |"
  echo "|---|---|---|---|---|---|---|"
}

# The three searches of every contour: the thesis's F1 + Hooke-Jeeves, and the exact area with NLopt by both rules.
searches() {
  optrow "F1 + Hooke-Jeeves from the example's pole" "$1" nearest --objective f1 --method hooke-jeeves
  optrow "exact area + NLopt, nearest rule" "$1" nearest --objective area --method nlopt
  optrow "exact area + NLopt, thesis rule" "$1" thesis --objective area --method nlopt
}

header "Witch of Agnesi, a = 21.59 cm, x = -20.32 .. 20.32 cm"
row "Table 4.1, F1 optimum (= exact optimum)" witch "15.46 cm" "1.236 rad" "2.59 mm^2"
row "Table 4.1, F1 optimum, mirror" witch "15.46 cm" "1.905 rad" "2.59 mm^2"
searches witch

header "Limacon, a = 5.08 cm, b = 7.62 cm (pole inside)"
row "Table 4.1, F1 optimum as printed (beta = 2 pi)" limacon "0.86 cm" "0 rad" "4.05 mm^2"
row "Table 4.1, F1 optimum, O1 seen from O (beta = pi)" limacon "0.86 cm" "pi rad" "4.05 mm^2"
row "Table 4.1, exact optimum as printed (beta = 2 pi)" limacon "1.27 cm" "0 rad" "4.01 mm^2"
row "Table 4.1, exact optimum, O1 seen from O (beta = pi)" limacon "1.27 cm" "pi rad" "4.01 mm^2"
searches limacon

header "Serpentine, a = 1.27 cm, b = 7.62 cm, x = -7.62 .. 7.62 cm (only r <= r_max)"
row "Table 4.1, F1 optimum (= exact optimum)" serpentine "5.37 cm" "4.247 rad" "4.563 mm^2"
row "Table 4.1, F1 optimum, other" serpentine "5.37 cm" "1.105 rad" "4.563 mm^2"
searches serpentine

# The thesis does not state the x-range of its open curves: the area at its poles for x = -6 in .. 6 in
echo
echo "### Witch and serpentine at the thesis's poles, x = -15.24 .. 15.24 cm (6 in each side)"
echo
echo "| contour | C | beta | area, nearest (mm^2) | area, thesis rule (mm^2) | thesis |"
echo "|---|---|---|---|---|---|"
for spec in "witch|15.46 cm|1.236 rad|2.59 mm^2" "serpentine|5.37 cm|4.247 rad|4.563 mm^2"; do
  IFS='|' read -r base C beta thesis <<< "$spec"
  for rule in nearest thesis; do
    job "x_$rule" "$base" "$C" "$beta" "$rule"
    sed -i -e 's|^x_from = .*|x_from = "-15.24 cm"|' -e 's|^x_to = .*|x_to = "15.24 cm"|' "$tmp/x_$rule.toml"
  done
  printf "| %s | %s | %s | %s | %s | %s |\n" "$base" "$C" "$beta" "$(num "$(area "$tmp/x_nearest.toml")" 3)" \
    "$(num "$(area "$tmp/x_thesis.toml")" 3)" "$thesis"
done
