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

# The band controller (Sec. V-VI) from `polarcam simulate bands`: the feed it settles at before the depth step
# with the bands of Tables 2, 3 and 4, and the limit cycle at a high effective gain.
feeds=()
for f in fussell_trial1 fussell_cut1 fussell_cut2; do
  feeds+=("$("$POLARCAM" simulate bands "examples/process/$f.toml" --json | jq '.settled_feed_before_step_in_per_min')")
done
emit fussell.bands.feeds_in_per_min "[24,10.8,24]" "[$(IFS=,; echo "${feeds[*]}")]" in/min \
  "\`polarcam simulate bands examples/process/fussell_{trial1,cut1,cut2}.toml\`: trial one, cut one, cut two; the report prints the tooth bands (Tables 2-4), not the feeds: Eq. 19 makes their lower edges 24, 10.8, 24 in/min (upper 28, 13.2, 28); the controller holds inside the band, past the lower edge by the steps it takes during the drive's and the filter's lag"
lc=examples/process/fussell_limit_cycle.toml
cycles=()
for step in 0.001 0.002 0.004 0.01; do   # 5, 10, 20, 50 (in/min)/s at 50 in/min and 100 Hz
  cycles+=("$("$POLARCAM" simulate bands "$lc" --axial-depth "0.15 in" --step "$step" --json | jq 'if .limit_cycle then 1 else 0 end')")
done
cycles+=("$("$POLARCAM" simulate bands "$lc" --json | jq 'if .limit_cycle then 1 else 0 end')")
emit fussell.limit_cycle "[0,0,0,0,1]" "[$(IFS=,; echo "${cycles[*]}")]" "1 = limit cycle" \
  "\`polarcam simulate bands examples/process/fussell_limit_cycle.toml\` with --axial-depth, --step: 0.15 in axial depth at 5, 10, 20, 50 (in/min)/s, then 0.25 in at 50 (in/min)/s; the report does not give these tests' bands: a 25 lbf total-force band (195-220 lbf) is assumed"
