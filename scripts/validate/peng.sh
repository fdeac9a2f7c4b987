# J. Peng, "Design and Analysis of a CNC System for Machining and Monitoring", MASc thesis, UBC, 1989: the feed
# drives' following errors, the straight-line error of mismatched axes, the yield per cutting torque and the
# current sensor's bandwidth (docs/feed-drives.md).
#   bash scripts/validate/peng.sh POLARCAM MARKDOWN_FILE
set -euo pipefail
POLARCAM=$1
MD=$2
source "$(dirname "$0")/common.bash"
section "Peng 1989" "J. Peng, *Design and Analysis of a CNC System for Machining and Monitoring*, MASc thesis, University of British Columbia, 1989. The drives of Appendix A with the mismatched guideway friction of Sec. 4.3.2 (examples/drives/peng1989.toml): \`polarcam servo --path diamond --feed '20*sqrt(2) mm/s' --json\` (20 mm/s on each axis, the following errors averaged at steady speed, the contour error along the legs) and \`polarcam servo --report-model --json\` (Eq. 4.101, Eq. 3.64)."

drives=examples/drives/peng1989.toml
# exit status 1: the corners leave the default 0.05 mm tolerance (NO-GO), which is what the thesis shows
dia=$("$POLARCAM" servo --path diamond --feed '20*sqrt(2) mm/s' --drives "$drives" --json || [ $? -eq 1 ])
model=$("$POLARCAM" servo --report-model --drives "$drives" --json)
emit peng.following_error_mm "[0.2789, 0.3267]" "$(jq -c '[.axes[].following_error_mm]' <<<"$dia")" mm \
  "x (B = 0.09) and y (B = 0.3) at 20 mm/s; Eq. 4.85 with Appendix A gives 0.2790 and 0.3269, the simulation the same"
emit peng.diamond_line_error_mm 0.034 "$(jq '.steady_contour_error_mm | fabs' <<<"$dia")" mm \
  "(e_y - e_x) cos 45 deg on a leg of the diamond (Eq. 4.78, 4.91): 0.0339, printed rounded"
emit peng.counts_per_Nm 7.2516 "$(jq '.axes[0].counts_per_Nm' <<<"$model")" "count/(N m)" \
  "Eq. 4.101 with Appendix A gives 7.2574; the simulated yield is the same"
emit peng.current_sensor_bandwidth_Hz 120 "$(jq '.axes[0].current_sensor_bandwidth_Hz' <<<"$model")" Hz \
  "\"about 120 Hz\" read off Fig. 3.19; Eq. 3.52 printed K_t (K_b K_I T_g H_g) where the model has K_t (K_b + K_v K_I T_g H_g)"
# Sec. 4.4.3: the corner splines of the worked example (the diamond's top corner, 1 mm on each axis, 20 mm/s on
# each), from the blended diamond's top corner at (0, 50) mm moved to the example's (150, 150) mm
matched=examples/drives/peng1989_matched.toml
spline_of() {  # spline_of spline|spline2: A* of the top corner's segments, rows x then y, constants moved
  ("$POLARCAM" servo --path diamond --feed '20*sqrt(2) mm/s' --corner "$1" --drives "$matched" --json || [ $? -eq 1 ]) |
    jq -c '[.corner_splines[0].segments[].A_mm | (.[0][3] += 150) | (.[1][3] += 100) | .[][]
            | (. * 1e9 | round / 1e9) + 0]'
}
emit peng.corner_spline "[0, 0, 2, 149, 0, -2, 2, 149]" "$(spline_of spline)" mm \
  "A1* of Eq. 4.144 (rows x, y; s^3, s^2, s, 1)"
emit peng.corner_spline2 "[0, 0, 1, 149, -0.98, 0.97, 1, 149, 0, 0, 1, 150, 0.98, -1.97, 0, 149.99]" \
  "$(spline_of spline2)" mm \
  "A1*, A2* of Eq. 4.148, 4.151; Eq. 4.146, 4.147, 4.149 print 149.0 where P_m = (150, 149.99) gives 149.99"
