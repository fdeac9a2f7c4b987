# Helpers of the validation parts (sourced, not a part itself).
#   emit ID PAPER POLARCAM UNIT [WHY]     PAPER and POLARCAM are JSON numbers or arrays of numbers
# prints the JSON line and appends a markdown row (one row per element of a list) to $MD.
emit() {
  local id=$1 paper=$2 ours=$3 unit=$4 why=${5:-}
  jq -cn --arg id "$id" --argjson p "$paper" --argjson q "$ours" --arg u "$unit" \
    '{id: $id, paper: $p, polarcam: $q, unit: $u}'
  jq -rn --arg id "$id" --argjson p "$paper" --argjson q "$ours" --arg u "$unit" --arg why "$why" '
    def fmt: if (. | fabs) >= 1e-3 and (. | fabs) < 1e7 then (. * 10000 | round / 10000 | tostring)
             else tostring end;
    def row($name; $a; $b): "| \($name) | \($a | fmt) | \($b | fmt) | \(if $a == 0 then "" else
             (((($b - $a) / $a) * 1000 | round) / 10 | tostring) + " %" end) | \($why) |";
    if ($p | type) == "array" then
      [range(0; $p | length) as $i | row("\($id)[\($i)] (\($u))"; $p[$i]; $q[$i])] | .[]
    else row("\($id) (\($u))"; $p; $q) end' >> "$MD"
}
section() {  # section TITLE INTRO
  { echo "## $1"; echo; echo "$2"; echo; echo "| quantity | paper | polarcam | difference | why they differ |";
    echo "|---|---|---|---|---|"; } >> "$MD"
}
