#pragma once
// The machine-workpiece structure of regenerative chatter (A. B. Dunckley (1978), Active Suppression of Machine Tool
// Chatter, Sec. 2.1.2): two masses in series, the machine (M_m, C_m, K_m) on the bed and the workpiece (M_w, C_w,
// K_w) on the machine, the cutting force F_c acting on the workpiece. G(s) = X_w / F_c (Eq. 2.4-2.5 with the
// corrections of docs/chatter.md: the last denominator term is (C_w s + K_w)^2, B1 = C_w K_m + C_m K_w, as the
// program listings of App. B compute them). Regeneration (Sec. 2.1.3): the depth of cut
// U(t) = U0 - X_w(t) + mu X_w(t - T), so H(s) = 1 - mu e^{-sT} (Eq. 2.8-2.9a), and the characteristic equation of
// the closed loop with the cutting gain K_c (force per depth, N/m) is 1 + K_c H(s) G(s) = 0. SI units throughout.
#include <array>
#include <complex>
#include <vector>

namespace polarcam::process {

// Eq. 2.2-2.3: masses (kg), dampings (N s/m), stiffnesses (N/m).
struct TwoMassStructure {
  double M_m = 0.0, C_m = 0.0, K_m = 0.0;  // the machine, on the bed
  double M_w = 0.0, C_w = 0.0, K_w = 0.0;  // the workpiece, on the machine; the cut acts on it
};

// The cut (Sec. 2.1.3): overlap mu of successive cuts (0..1) and the revolution period T (s).
struct Cut {
  double overlap = 1.0;
  double revolution_period = 0.0;
  double depth = 1e-3;  // the nominal depth of cut U0 (m): only the time-domain simulation uses it
};

// A rational transfer function, coefficients in ascending powers of s.
struct TransferFunction {
  std::vector<double> num, den;
  std::complex<double> operator()(std::complex<double> s) const;
  // G(j w)
  std::complex<double> at(double w) const { return (*this)(std::complex<double>(0.0, w)); }
};

// G(s) = X_w / F_c of the two masses (Eq. 2.5 corrected): num = {A0, A1, A2}, den = {B0, ..., B4}.
TransferFunction workpiece_compliance(const TwoMassStructure& s);

// H(j w) = 1 - mu e^{-j w T} (Eq. 2.12-2.13).
std::complex<double> regeneration(double overlap, double period, double w);

// One mode of vibration: a pair of complex poles -sigma +- j omega_d of G.
struct Mode {
  double omega_n = 0.0;  // undamped natural frequency |p| (rad/s)
  double zeta = 0.0;     // damping ratio sigma / omega_n
  double omega_d = 0.0;  // damped frequency (rad/s)
  double sigma = 0.0;    // decay rate (1/s)
};
// The roots of a transfer function's denominator (Eigen's companion-matrix eigenvalues).
std::vector<std::complex<double>> poles(const TransferFunction& g);
// The modes of a transfer function's denominator, lowest first (Eigen's companion-matrix eigenvalues). Real poles
// (overdamped) are left out.
std::vector<Mode> modes(const TransferFunction& g);
// The undamped modes of the two masses: sqrt of the eigenvalues of M^-1 K (the document's "lower" and "upper"
// resonances, Sec. 2.1.2.2), lowest first.
std::array<double, 2> undamped_frequencies(const TwoMassStructure& s);

// Checks the structure and cut: masses and stiffnesses positive and finite, dampings >= 0, overlap in [0, 1], a
// positive period, every mode damped. InputError naming the key (section.key) otherwise.
void check(const TwoMassStructure& s, const Cut& c);

}  // namespace polarcam::process
