# M. A. Elbestawi, "A Study of an Adaptive Control Constraint System for Milling", PhD thesis, McMaster
# University, 1980: Table 5.1 (Sec. 5.10), the lumped force model's numbers of Sec. 4.4 and case A of Sec. 4.5.
#   bash scripts/validate/elbestawi.sh POLARCAM MARKDOWN_FILE
set -euo pipefail
POLARCAM=$1
MD=$2
source "$(dirname "$0")/common.bash"
section "Elbestawi 1980" "M. A. Elbestawi, *A Study of an Adaptive Control Constraint System for Milling*, PhD thesis, McMaster University, 1980. Table 5.1 (Sec. 5.10): the rapid feed per tooth f_tr = 0.9 (sigma_S/E) L^2/d, rows L = 50, 75, 100 mm, columns d = 6.25, 12.5 (2 teeth), 18.75, 25 mm (4 teeth), from \`polarcam limits examples/process/elbestawi_table_5_1.toml --diameter D --length L\`. The lumped force model (Sec. 4.4, case A of Sec. 4.5) from \`polarcam cut-force\`."

tool=examples/process/elbestawi_table_5_1.toml
ours=()
for L in 50 75 100; do
  for d in 6.25 12.5 18.75 25; do
    ours+=("$("$POLARCAM" limits "$tool" --diameter "$d mm" --length "$L mm" --json | jq '.rapid_feed_per_tooth_mm')")
  done
done
emit elbestawi.table_5_1.ftr_mm "[2.6,1.3,0.9,0.6,5.8,2.9,1.9,1.4,10.2,5.1,3.4,2.6]" \
  "[$(IFS=,; echo "${ours[*]}")]" mm \
  "the table uses Eq. 5.35's 0.0064 L^2/d, which needs E = 210.9 GPa; the thesis's E = 30e6 lb/in^2 gives 0.00653 (+2.0 %); the table rounds to 0.1 mm"

sec44=$("$POLARCAM" cut-force --teeth 4 --spindle-speed "500 rpm" --radial-depth "20 mm" --axial-depth "10 mm" \
  --force "4200 N" --feed-per-tooth "0.1 mm" --json)
emit elbestawi.sec4_4.K 6.3 "$(jq '.K_N_per_mm2_per_mm_per_s' <<<"$sec44")" "N/mm^2/(mm/s)" ""
emit elbestawi.sec4_4.C 1260 "$(jq '.C_N_per_mm_per_s[0]' <<<"$sec44")" "N/(mm/s)" ""
emit elbestawi.sec4_4.tau_s 0.030 "$(jq '.tau_s' <<<"$sec44")" s ""

casea=$("$POLARCAM" cut-force --teeth 4 --spindle-speed "500 rpm" --radial-depth "20 mm" --axial-depth "2.5 mm" \
  --axial-depth "10 mm" --specific-force "205 N/mm^3" --feed-speed "12.7 mm/s" --json)
emit elbestawi.case_a.forces_N "[3900,15600]" "$(jq -c '.forces_N' <<<"$casea")" N \
  "printed rounded: 205 * 20 * 2.5 * 12.7 * 0.030 = 3905 N and four times that at the step"
