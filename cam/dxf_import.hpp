#pragma once
// DXF drawings (dxflib): LINE, ARC, CIRCLE and POLYLINE / LWPOLYLINE entities (bulges become arcs) of the
// entities section, optionally of one layer, chained end to end into one path of lines and arcs. The entities
// may come in any order and direction; a drawing with several separate chains is an error asking for a layer.
// SPLINE, ELLIPSE and other curved entities are refused by name (convert them to polylines in the CAD program).
#include <optional>
#include <string>
#include <vector>

#include "cam/path.hpp"

namespace polarcam {

struct DxfOptions {
  double unit_m = 1e-3;                // metres per drawing unit
  std::optional<std::string> layer;    // only this layer
  double join_tolerance = 1e-6;        // drawing units: ends closer than this are joined
};

struct DxfPath {
  std::vector<PathSegment> segments;   // in travel order, metres
  bool closed = false;
  size_t entities = 0;                 // entities used
};

// Throws InputError naming the file for an unreadable drawing, unsupported entities, gaps, or several chains.
DxfPath read_dxf_path(const std::string& path, const DxfOptions& opt);

}  // namespace polarcam
