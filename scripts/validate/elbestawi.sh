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

# The A/C loop (Ch. 5): the closed-loop poles of Eq. 5.21 for the root loci of Sec. 5.7, and the feed of the
# impact simulation of Sec. 5.5, from `polarcam simulate ac`.
ac=examples/process/elbestawi_ac_sec5_7.toml
ks7030=$("$POLARCAM" simulate ac "$ac" --json)
ks2285=$("$POLARCAM" simulate ac "$ac" --spindle-stiffness "2285 N/mm" --json)
kc86=$("$POLARCAM" simulate ac "$ac" --cutting-stiffness "3465 N/mm" --json)    # K'_C = 86.625 N/(mm/s)
kc346=$("$POLARCAM" simulate ac "$ac" --cutting-stiffness "13860 N/mm" --json)  # K'_C = 346.5 N/(mm/s)
emit elbestawi.eq5_21.roots "[-7.864,2.2481,-1.806,-6.509,7.026]" \
  "[$(jq '.eq5_21.poles[0].re' <<<"$ks7030"),$(jq '.eq5_21.poles[0].im' <<<"$ks7030"),$(jq '.eq5_21.poles[0].re' <<<"$kc86"),$(jq '.eq5_21.poles[0].re' <<<"$kc346"),$(jq '.eq5_21.poles[0].im' <<<"$kc346")]" \
  1/s "\`polarcam simulate ac examples/process/elbestawi_ac_sec5_7.toml\` with --spindle-stiffness, --cutting-stiffness: K_S = 7030 N/mm (re, im), K'_C = 86.625 (slowest root), K'_C = 346.5 (re, im); from the stated parameters with the pole at K_S/K'_C (the print's (s + K_S) is a typo); the printed roots are, to the printed digits, those of the printed transfer functions, whose zero (25.0 for K_ac/B = 25.4), gains and poles are 1-4 % off the stated parameters"
emit elbestawi.eq5_21.zeta "[0.96,0.64,0.67]" \
  "[$(jq '.eq5_21.dominant_damping' <<<"$ks7030"),$(jq '.eq5_21.dominant_damping' <<<"$ks2285"),$(jq '.eq5_21.dominant_damping' <<<"$kc346")]" "" \
  "K_S = 7030, K_S = 2285, K'_C = 346.5; the printed values come from the printed transfer functions (zero 25.0 where K_ac/B is 25.4, gains and poles 1-4 % off the stated parameters): at K_S = 2285 those give 0.641; the printed roots -6.509 +/- j7.026 themselves have zeta 0.680"
sec55=$("$POLARCAM" simulate ac examples/process/elbestawi_ac_sec5_5.toml --json)
emit elbestawi.sec5_5.steady_feed_mm_per_min 365 "$(jq '.final_feed_mm_per_min' <<<"$sec55")" mm/min \
  "\`polarcam simulate ac examples/process/elbestawi_ac_sec5_5.toml\`: the lumped force settles at F_nom / (K_C tau) = 1340 N / (9100 N/mm * 25 ms) = 353 mm/min; the thesis simulated its tooth-level force (Eq. 5.7-5.8), and 365 mm/min is 220 N/(mm/s), 3 % below K_C tau"
