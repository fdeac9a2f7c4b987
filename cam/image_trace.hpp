#pragma once
// Template images to contours: a scanned or drawn template (PNG, or the netpbm PBM/PGM formats) thresholded into
// ink and paper and traced by potrace (P. Selinger's "Potrace: a polygon-based tracing algorithm") into closed
// contours of exact lines and cubic Bezier curves (cam/segments.hpp): outer outlines and holes each a contour of
// their own. The user manual is docs/copy-mode.md.
//
// Coordinates: METRES, y UP, the image's lower left corner at the origin; pixel (column i, row j counted from the
// top) covers [i, i + 1] x [H - j - 1, H - j] pixel sizes. A pixel is ink when its gray level (0 black .. 1 white:
// colour turned to gray by the ITU-R BT.709 luminance weights in linear light and encoded as sRGB gray, as libpng
// does; any transparency composited onto white paper) is below the threshold; `invert` swaps ink and paper.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "cam/segments.hpp"

namespace polarcam {

// An image as 8-bit luminance, rows from the top.
struct GrayImage {
  int width = 0, height = 0;
  std::vector<uint8_t> luminance;       // width x height, 0 black .. 255 white
  std::optional<double> pixel_size_m;   // from the file's resolution (a PNG's pHYs chunk), when it states one
};

struct TraceOptions {
  std::optional<double> pixel_size_m;  // m per pixel; else the image's own resolution (refused when it has none)
  double threshold = 0.5;              // ink below this luminance, in (0, 1]
  bool invert = false;                 // light ink on dark paper
  int despeckle = 2;                   // outlines enclosing at most this many pixels are dropped (0: none)
  double corner_threshold = 1.0;       // potrace's alphamax: 0 all corners .. 4/3 all smooth
  double curve_tolerance = 0.2;        // potrace's curve optimisation tolerance (pixels); 0 leaves curves as fitted
};

struct TracedContour {
  CurvePtr curve;      // closed, metres, y up
  bool hole = false;   // the boundary of paper inside ink (potrace's '-' paths)
  long area_px = 0;    // pixels it encloses (of the bitmap path)
};

struct Tracing {
  std::vector<TracedContour> contours;  // potrace's order: every outline followed by the outlines inside it
  int width_px = 0, height_px = 0;
  double pixel_size_m = 0.0;
  long ink_px = 0;                      // pixels counted as ink
  double width_m() const { return width_px * pixel_size_m; }
  double height_m() const { return height_px * pixel_size_m; }
};

// True for the file types read as images (by extension, case-insensitive): .png, .pbm, .pgm.
bool is_image_file(const std::string& path);

// Reads a PNG (any colour type and depth) or a PBM/PGM (P1, P2, P4, P5, by the file's signature, not its name).
// At most 2^28 pixels. Throws InputError naming the file and what is wrong (not an image, damaged, truncated,
// empty), DeviceError when it cannot be read.
GrayImage read_image(const std::string& path);
// The same from bytes in memory; `place` names them in errors.
GrayImage parse_image(const std::string& bytes, const std::string& place);

// Traces the image. Throws InputError (`place` naming the image) for options out of range, an image without a
// pixel size when none is given, an image that is all ink ("check --threshold or --invert") or has no contour.
Tracing trace_image(const GrayImage& image, const TraceOptions& o, const std::string& place);

// The tracing as an SVG document whose width and height are its physical size in millimetres and whose user
// unit is the millimetre (viewBox 0 0 W H): one <path> per contour, in order, ids "outline-N" / "hole-N".
// Coordinates in mm with 6 decimals; the same tracing gives the same bytes.
std::string tracing_svg(const Tracing& t, const std::string& title);

}  // namespace polarcam
