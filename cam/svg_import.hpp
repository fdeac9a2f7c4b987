#pragma once
// SVG drawings (svgpp on libxml2): every subpath of every <path> and the basic shapes (rect, with rounded corners,
// circle, ellipse, line, polyline, polygon) become exact segment curves (cam/segments.hpp), one contour per subpath
// in document order, in METRES with y UP. Nested transforms, <svg> viewports (viewBox, preserveAspectRatio),
// units (px = 1/96 in, mm, cm, in, pt, pc, em = 16 px, ex = 8 px) and <use> of shapes and groups are applied
// exactly (arcs stay arcs, Bezier curves stay Bezier curves). The user manual is docs/svg.md.
//
// The outermost <svg>'s width and height give the drawing's physical size; its viewBox and preserveAspectRatio
// (default xMidYMid meet) map user units onto it. Without width and height the user units are px (a missing one
// follows from the viewBox's aspect ratio). SVG's y axis points down; here y' = H - y, H the drawing's height, so
// the drawing's lower left corner is the origin (without any height, H = 0: its top edge lies on the x axis).
//
// Skipped: what is not geometry (text, images, <defs>, <symbol>, <clipPath>, <mask>, <marker>, <pattern> and what
// they hold unless a <use> draws it), elements with display="none" (attribute or style) and everything in them,
// elements whose transform is singular. Refused with one InputError naming the file, the line and the element
// (its id when it has one): not XML, a root that is not an SVG <svg>, a malformed attribute (path data such as
// "M 10 L", a number that is not finite), a zero-size or negative viewBox, a negative width, a <use> of something
// missing, outside the file, of a <symbol> or <svg>, or of itself; and a drawing without any contour.
#include <string>
#include <vector>

#include "cam/segments.hpp"

namespace polarcam {

struct SvgContour {
  CurvePtr curve;        // metres, y up; closed when the subpath closes (Z, or its end is its start)
  std::string id;        // the id of the element it comes from (empty when it has none)
  std::string element;   // the element's name: path, rect, circle, ellipse, line, polyline, polygon
  int line = 0;          // the element's line in the file
  size_t subpath = 0;    // the subpath's index within the element, from 0
};

struct SvgDrawing {
  std::vector<SvgContour> contours;  // in document order
  double width = 0.0;                // the drawing's physical size (m), 0 when it has none
  double height = 0.0;
};

// Reads an SVG file. Throws InputError (the place "FILE:LINE") as above, DeviceError when it cannot be read.
SvgDrawing read_svg(const std::string& path);

// Parses SVG text held in memory; `place` names it in errors (a file name). Never reads another file or the
// network.
SvgDrawing parse_svg(const std::string& text, const std::string& place);

}  // namespace polarcam
