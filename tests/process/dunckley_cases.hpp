#pragma once
// A. B. Dunckley (1978), Active Suppression of Machine Tool Chatter, Sec. 2.2.1-2.2.4: the machine of every example
// (M_m = 0.03, C_m = 0.1, K_m = 120 000; C_w = 0.01 as in the program listings of App. B), the cut (mu = 1,
// T = 0.2) and the systems 1, 2, 3, 4 and 7 of Sec. 2.2.4.2-2.2.4.3 with the limiting gains and chatter
// frequencies the document reads off its polar plots. Typed from the document for the tests; the library never
// sees these numbers.
#include "process/structure.hpp"

namespace polarcam::test {

struct DunckleyCase {
  int system;            // the document's system number
  double M_w, K_w;       // the workpiece
  double paper_gain;     // K_c limit, Sec. 2.2.4.2
  double paper_rad_s;    // chatter frequency, Sec. 2.2.4.3
};

inline constexpr DunckleyCase kDunckleyCases[5] = {
    {1, 0.09, 12000.0, 420.0, 348.0},   {2, 0.03, 12000.0, 230.0, 601.0},  {3, 0.01, 12000.0, 13.0, 1028.0},
    {4, 0.09, 120000.0, 40.0, 782.0},   {7, 0.09, 1200000.0, 250.0, 972.0},
};

inline process::TwoMassStructure dunckley_structure(const DunckleyCase& c) {
  return {0.03, 0.1, 120000.0, c.M_w, 0.01, c.K_w};
}

}  // namespace polarcam::test
