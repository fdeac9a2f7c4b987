#pragma once
// The dual-input describing function of the chatter suppressor's quantiser (A. B. Dunckley (1978), Active
// Suppression of Machine Tool Chatter, Sec. 3.2 and the program of App. B.4). With an exact model and an ideal
// stepper (Fig. 3.3) the cut sees the quantisation error of the tool's position: y(x) = x - Q(x), Q the quantiser
// with output steps D at the switching levels +-(2i - 1) H / 2 (i = 1, 2, ...). For an input x = B + A sin(theta)
// (Eq. 3.4), the DC gain (the mean of y over B) and the AC gain (the fundamental of y over A; y is single-valued,
// so its quadrature part is zero) are, as program B.4 computes them (docs/chatter.md lists the printed slips):
//   N_dc = 1 - (D / B) sum_i [p((c_i + B) / A) - p((c_i - B) / A)],   p(d) = asin(d) / pi, clipped to +-1/2
//   N_ac = 1 - (D / A) sum_i [q((c_i + B) / A) + q((c_i - B) / A)],   q(d) = (2 / pi) sqrt(1 - d^2), 0 for |d| > 1
// with c_i = (2i - 1) H / 2.
namespace polarcam::process {

struct DualInputGains {
  double dc = 0.0;  // N_dc: the output's mean over B (at B = 0 its limit, the slope of the mean)
  double ac = 0.0;  // N_ac: the output's fundamental over A
};

// D, H > 0, A > 0, B finite; InputError otherwise. At B = 0 the DC gain is the limit B -> 0 (infinite where a
// switching level equals A exactly).
DualInputGains quantiser_error_didf(double A, double B, double D, double H);

}  // namespace polarcam::process
