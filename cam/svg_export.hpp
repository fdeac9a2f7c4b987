#pragma once
// The tool path as an SVG drawing, in millimetres: what the machine draws (the path itself, sampled finely
// enough that the drawing stays within a chord tolerance of it; a theta-rho path is a Curve whose segments are
// the spirals the table draws, so it is sampled as those spirals), the moves that connect drawn parts, the work
// area circle, the pole, and markers at the start and the end. y points up (the drawing is flipped by a
// transform), the machine pole is the origin. The output depends only on the input: fixed decimals, no dates.
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "cam/curve.hpp"
#include "cam/theta_rho_path.hpp"

namespace polarcam {

// One polyline of the drawing (metres, machine frame): drawn by the tool, or a connecting move between drawn
// parts (shown dashed, in its own group).
struct SvgPolyline {
  std::vector<Vec2> points;
  bool drawn = true;
};

struct SvgOptions {
  std::optional<double> work_radius;  // m: the work area's outer circle (and the drawing's extent) when given
  double work_radius_min = 0.0;       // m: the inner circle of an annular work area, when above 0
  double margin = 0.005;              // m around the drawing
  std::string title;                  // the document's <title> (escaped)
};

// Points along the curve, its ends and breakpoints included, such that every chord lies within `chord_tol` (m)
// of the curve piece it replaces (each piece starts as 16 chords, or fewer when the curve has more than 256
// pieces (a long polyline: down to one each); each chord is bisected until 15 points of the piece lie within the
// tolerance of it and it turns by less than a sixteenth of a turn). Throws InputError for a tolerance that is not positive.
std::vector<Vec2> sample_curve(const Curve& c, double chord_tol);

// The same for a theta-rho polyline (rho in metres): each segment sampled as the spiral piece it is.
std::vector<Vec2> sample_theta_rho(const std::vector<ThetaRho>& v, double chord_tol);

// The SVG document: width and height in mm, a viewBox in mm, groups "work-area", "connecting", "path" and
// "markers" (start: a filled circle, end: a square, both at the ends of the drawn parts; the pole: a cross).
// Coordinates are written in mm with 4 decimals.
std::string svg_document(const std::vector<SvgPolyline>& lines, const SvgOptions& o);
// The same written to a stream (a large drawing is never held whole).
void write_svg_document(std::ostream& out, const std::vector<SvgPolyline>& lines, const SvgOptions& o);

}  // namespace polarcam
