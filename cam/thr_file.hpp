#pragma once
// The theta-rho (.thr) pattern file of polar sand tables (Sisyphus, Oasis, Dune Weaver, Sandify):
//   one vertex per line, "theta rho" separated by spaces, tabs or a comma; theta in radians, cumulative (it may
//   exceed 2 pi and may decrease); rho in 0..1 of the table's radius. '#' starts a comment (a whole line or the
//   rest of one; "//" too), blank lines are skipped, CRLF line ends are accepted. Consecutive vertices are joined
//   by the segment linear in theta and rho (cam/theta_rho_path.hpp).
// Reading merges repeated vertices (the same theta and rho as the one before) and counts them; a rho outside
// [0, 1], a field that is not a number or a line without exactly two numbers is an InputError naming the line.
#include <cstddef>
#include <iosfwd>
#include <string>
#include <vector>

#include "cam/theta_rho_path.hpp"

namespace polarcam {

struct ThrPattern {
  std::vector<ThetaRho> vertices;  // rho normalised (0..1), repeats merged
  size_t lines = 0;                // lines in the file
  size_t points = 0;               // vertices read (before merging)
  size_t merged = 0;               // repeated vertices merged
  std::vector<size_t> line_of;     // the file line of each vertex kept (1-based)
};

// Parses a pattern; `place` names the source in errors ("FILE:LINE: ..."). Throws InputError.
ThrPattern parse_thr(std::istream& in, const std::string& place);
// Reads a pattern file (InputError when it cannot be opened, is empty or malformed).
ThrPattern read_thr(const std::string& path);

// Statistics of a pattern (polarcam check): vertices normalised as parse_thr returns them.
struct ThrStats {
  size_t vertices = 0;
  double theta_min = 0, theta_max = 0;   // rad
  double rho_min = 0, rho_max = 0;       // 0..1
  size_t centre_touches = 0;             // vertices at rho = 0 (inside the first and last)
  double length = 0;                     // path length in table radii (sum of the spiral pieces)
  double start_rho = 0, end_rho = 0;
};
ThrStats thr_stats(const std::vector<ThetaRho>& v);

// Writes vertices (rho normalised) one per line, each number as the shortest text that reads back to the same
// double; `comment` lines are written first, each after "# ".
void write_thr(std::ostream& out, const std::vector<ThetaRho>& v, const std::vector<std::string>& comment);

}  // namespace polarcam
