# B. K. Fussell, D. P. Gagne, "Self-Directed Control of End Milling", WL-TR-91-4027, 1991: Table 1's tool
# stiffness and the constant of Eq. 18.
#   bash scripts/validate/fussell.sh POLARCAM MARKDOWN_FILE
set -euo pipefail
POLARCAM=$1
MD=$2
source "$(dirname "$0")/common.bash"
section "Fussell & Gagne 1991" "B. K. Fussell, D. P. Gagne, *Self-Directed Control of End Milling*, WL-TR-91-4027, 1991. Table 1's tool (12.7 mm, 44.5 mm, 4 flutes, high-speed steel) from \`polarcam limits examples/process/fussell_table1.toml --json\`; the constant of Eq. 18 from the same output."

lim=$("$POLARCAM" limits examples/process/fussell_table1.toml --json)
emit fussell.tool.stiffness_N_per_cm 90200 "$(jq '.stiffness_N_per_m / 100' <<<"$lim")" N/cm \
  "3 E I / L^3 with E = 207 GPa; the table's value needs 207.5 GPa"
emit fussell.eq18.constant 7.95e-9 "$(jq '.eq18_constant' <<<"$lim")" "(in, lbf, rpm, hp)" \
  "the printed constant carries Eq. 15's tooth speed 2 pi D; the tooth circumference is pi D, which gives 3.15e-9"
emit fussell.eq18.constant_2piD 7.95e-9 "$(jq '.eq18_constant_printed_2piD' <<<"$lim")" "(in, lbf, rpm, hp)" \
  "the printed constant reproduced with the printed 2 pi D"
