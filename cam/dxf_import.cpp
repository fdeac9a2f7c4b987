#include "cam/dxf_import.hpp"

#include <dxflib/dl_creationadapter.h>
#include <dxflib/dl_dxf.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <fstream>
#include <map>
#include <numbers>

#include "cam/error.hpp"
#include "cam/format.hpp"
#include "cam/input_file.hpp"

namespace polarcam {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// A 2-D affine map of the plane: p -> a * p + t (a row-major 2 x 2 matrix).
struct Affine {
  double a[4] = {1, 0, 0, 1};
  Vec2 t{0, 0};
  Vec2 operator()(Vec2 p) const { return Vec2{a[0] * p.x + a[1] * p.y, a[2] * p.x + a[3] * p.y} + t; }
  double det() const { return a[0] * a[3] - a[1] * a[2]; }
  // true when the linear part is a rotation (or reflection) times one scale: circles stay circles
  bool conformal() const {
    return std::abs(a[0] * a[0] + a[2] * a[2] - (a[1] * a[1] + a[3] * a[3])) <= 1e-9 * (a[0] * a[0] + a[2] * a[2]) &&
           std::abs(a[0] * a[1] + a[2] * a[3]) <= 1e-9 * (a[0] * a[0] + a[2] * a[2]);
  }
  Affine then(const Affine& o) const {  // o after this
    Affine r;
    r.a[0] = o.a[0] * a[0] + o.a[1] * a[2];
    r.a[1] = o.a[0] * a[1] + o.a[1] * a[3];
    r.a[2] = o.a[2] * a[0] + o.a[3] * a[2];
    r.a[3] = o.a[2] * a[1] + o.a[3] * a[3];
    r.t = o(t);
    return r;
  }
};

// What a block (or the entities section) holds: pieces in the block's coordinates (metres), each with its layer,
// entities refused by kind, and the inserts of other blocks.
struct Item {
  PathSegment seg;
  std::string layer;
};
struct Insert {
  DL_InsertData d;
  std::string layer;
  bool mirrored = false;
};
struct Block {
  Vec2 base{0, 0};  // metres
  std::vector<Item> items;
  std::vector<std::pair<std::string, std::string>> refused;  // kind, layer
  std::vector<Insert> inserts;
};

class Collector final : public DL_CreationAdapter {
 public:
  explicit Collector(const DxfOptions& o) : o_(o) {}

  Block top;                            // the entities section
  std::string bad_radius;               // the first arc or circle of zero or negative radius, described
  std::map<std::string, Block> blocks;  // by name

  void addBlock(const DL_BlockData& d) override {
    flush_polyline();
    cur_ = &blocks[d.name];
    cur_->base = Vec2{d.bpx, d.bpy} * o_.unit_m;
  }
  void endBlock() override {
    flush_polyline();
    cur_ = &top;
  }
  void addInsert(const DL_InsertData& d) override {
    flush_polyline();
    cur_->inserts.push_back(Insert{d, layer(), mirrored()});
  }
  void addLine(const DL_LineData& d) override {
    PathSegment s;
    s.from = pt(d.x1, d.y1);
    s.to = pt(d.x2, d.y2);
    if (norm(s.to - s.from) > 0) cur_->items.push_back(Item{s, layer()});
  }
  void addArc(const DL_ArcData& d) override {
    double a1 = d.angle1 * kDeg, a2 = d.angle2 * kDeg, sweep = a2 - a1;
    while (sweep <= 0) sweep += 2 * std::numbers::pi;  // DXF arcs run counter-clockwise from angle1 to angle2
    arc(d.cx, d.cy, d.radius, a1, sweep);
  }
  void addCircle(const DL_CircleData& d) override { arc(d.cx, d.cy, d.radius, 0.0, 2 * std::numbers::pi); }
  void addPolyline(const DL_PolylineData& d) override {
    flush_polyline();
    in_poly_ = true;
    poly_layer_ = layer();
    poly_closed_ = d.flags & 1;
    verts_.clear();
  }
  void addVertex(const DL_VertexData& d) override {
    if (in_poly_) verts_.push_back(d);
  }
  void endEntity() override { flush_polyline(); }
  void endSection() override { flush_polyline(); }

  void addSpline(const DL_SplineData&) override { refuse("SPLINE"); }
  void addEllipse(const DL_EllipseData&) override { refuse("ELLIPSE"); }
  void addPoint(const DL_PointData&) override {}
  void addXLine(const DL_XLineData&) override { refuse("XLINE"); }
  void addRay(const DL_RayData&) override { refuse("RAY"); }

  void flush_polyline() {
    if (!in_poly_) return;
    in_poly_ = false;
    const size_t n = verts_.size();
    for (size_t i = 0; i + 1 < n + (poly_closed_ ? 1 : 0); ++i) {
      const DL_VertexData& a = verts_[i];
      const DL_VertexData& b = verts_[(i + 1) % n];
      Vec2 p = pt(a.x, a.y), q = pt(b.x, b.y);
      if (norm(q - p) == 0) continue;
      double bulge = mirrored() ? -a.bulge : a.bulge;
      if (std::abs(bulge) < 1e-12) {
        PathSegment s;
        s.from = p;
        s.to = q;
        cur_->items.push_back(Item{s, poly_layer_});
      } else {
        // bulge = tan(included angle / 4), positive counter-clockwise; the centre sits on the chord's bisector
        double theta = 4 * std::atan(bulge), c = norm(q - p), h = c / (2 * std::tan(theta / 2));
        Vec2 mid = (p + q) / 2, n_left = perp((q - p) / c);
        PathSegment s = make_arc_segment(p, mid + n_left * h, theta);
        s.to = q;
        cur_->items.push_back(Item{s, poly_layer_});
      }
    }
    verts_.clear();
  }

 private:
  std::string layer() { return getAttributes().getLayer(); }
  void refuse(const char* kind) { cur_->refused.emplace_back(kind, layer()); }
  // entities whose extrusion direction points down (0, 0, -1) are drawn mirrored in x
  bool mirrored() {
    const DL_Extrusion* e = getExtrusion();
    return e && e->getDirection()[2] < 0;
  }
  Vec2 pt(double x, double y) { return Vec2{mirrored() ? -x : x, y} * o_.unit_m; }
  void arc(double cx, double cy, double r, double a1, double sweep) {
    if (!(r > 0)) {  // reported after the parse (dxflib calls this; no exception through it)
      if (bad_radius.empty())
        bad_radius = "an ARC or CIRCLE on layer '" + layer() + "' has radius " + significant(r) +
                     " (drawing units): a radius must be positive";
      return;
    }
    const bool m = mirrored();
    if (m) {  // x -> -x: an angle a becomes pi - a and the direction reverses
      a1 = std::numbers::pi - a1;
      sweep = -sweep;
    }
    Vec2 c = Vec2{m ? -cx : cx, cy} * o_.unit_m;
    Vec2 from = c + Vec2{std::cos(a1), std::sin(a1)} * (r * o_.unit_m);
    cur_->items.push_back(Item{make_arc_segment(from, c, sweep), layer()});
  }

  const DxfOptions& o_;
  Block* cur_ = &top;
  bool in_poly_ = false, poly_closed_ = false;
  std::string poly_layer_;
  std::vector<DL_VertexData> verts_;
};

// Draws a block through the map `m`: its pieces on the wanted layer (an entity on layer 0 in a block takes the
// layer of its insert), the refused kinds counted, the inserted blocks drawn recursively.
class Expander {
 public:
  Expander(const Collector& c, const DxfOptions& o, const std::string& file) : c_(c), o_(o), file_(file) {}
  std::vector<PathSegment> segs;
  std::map<std::string, int> refused;

  void draw(const Block& b, const Affine& m, const std::string& insert_layer, int depth) {
    auto layer_of = [&](const std::string& l) { return (depth > 0 && l == "0") ? insert_layer : l; };
    auto take = [&](const std::string& l) { return !o_.layer || layer_of(l) == *o_.layer; };
    for (const auto& [kind, l] : b.refused)
      if (take(l)) ++refused[kind];
    for (const Item& it : b.items) {
      if (!take(it.layer)) continue;
      PathSegment s = it.seg;
      if (s.kind == PathSegment::Kind::arc) {
        if (!m.conformal())
          throw InputError("an INSERT of block '" + name_ + "' scales x and y differently and the block holds arcs; " +
                           "explode the insert in the CAD program", file_);
        Vec2 to = m(s.to);
        s = make_arc_segment(m(s.from), m(s.center), m.det() < 0 ? -s.sweep : s.sweep);
        s.to = to;
      } else {
        s.from = m(s.from);
        s.to = m(s.to);
      }
      segs.push_back(s);
    }
    for (const Insert& ins : b.inserts) {
      const DL_InsertData& d = ins.d;
      auto it = c_.blocks.find(d.name);
      if (it == c_.blocks.end())
        throw InputError("an INSERT names block '" + d.name + "', which the drawing does not define", file_);
      if (depth >= 16)
        throw InputError("block '" + d.name + "' is inserted more than 16 deep (inserts itself?)", file_);
      if (d.cols > 1 || d.rows > 1)
        throw InputError("the INSERT of block '" + d.name + "' is an array of " + std::to_string(d.cols) + " x " +
                             std::to_string(d.rows) + " copies, which polarcam does not read; explode it in the CAD program",
                         file_);
      if (!(std::isfinite(d.sx) && std::isfinite(d.sy) && d.sx != 0 && d.sy != 0))
        throw InputError("the INSERT of block '" + d.name + "' has a zero or non-finite scale", file_);
      // block coordinates -> insert: (p - base) scaled, rotated, moved to the insertion point
      const double a = d.angle * kDeg, c = std::cos(a), s = std::sin(a);
      Affine local;
      local.a[0] = c * d.sx;
      local.a[1] = -s * d.sy;
      local.a[2] = s * d.sx;
      local.a[3] = c * d.sy;
      const Vec2 base = it->second.base;
      local.t = Vec2{d.ipx, d.ipy} * o_.unit_m - Vec2{local.a[0] * base.x + local.a[1] * base.y,
                                                       local.a[2] * base.x + local.a[3] * base.y};
      if (ins.mirrored) {  // the insert's own extrusion (0, 0, -1): x -> -x after placing
        local.a[0] = -local.a[0];
        local.a[1] = -local.a[1];
        local.t.x = -local.t.x;
      }
      const std::string saved = name_;
      name_ = d.name;
      draw(it->second, local.then(m), layer_of(ins.layer), depth + 1);
      name_ = saved;
    }
  }

 private:
  const Collector& c_;
  const DxfOptions& o_;
  const std::string& file_;
  std::string name_;
};

// A pass over the group-code / value pairs before dxflib reads them: dxflib reads a missing number as 0, a "nan"
// as NaN, and a file cut short or with one line missing (every later pair shifted by one line) as whatever the
// shifted pairs happen to say. This pass refuses each, naming the line: group codes must be integers, the values
// of real-valued codes finite numbers, the entities polarcam draws must carry their coordinates, and the file must
// end with EOF.
bool is_real_code(long c) {
  return (c >= 10 && c <= 59) || (c >= 110 && c <= 149) || (c >= 210 && c <= 239) || (c >= 460 && c <= 469) ||
         (c >= 1010 && c <= 1059);
}
bool is_int_code(long c) {
  return (c >= 60 && c <= 79) || (c >= 90 && c <= 99) || (c >= 170 && c <= 179) || (c >= 270 && c <= 289) ||
         (c >= 370 && c <= 389) || (c >= 400 && c <= 409) || (c >= 1060 && c <= 1071);
}
std::string trim(std::string s) {
  while (!s.empty() && (s.back() == '\r' || s.back() == ' ' || s.back() == '\t')) s.pop_back();
  size_t i = s.find_first_not_of(" \t");
  return i == std::string::npos ? std::string() : s.substr(i);
}

struct EntityCheck {
  std::string kind;
  size_t line = 0;  // of its "0" code
  std::map<long, int> count;
  long long vertices = 0;  // an LWPOLYLINE's vertex count (group code 90), where it gives one (has_vertices)
  bool has_vertices = false;
};

void check_entity(const EntityCheck& e, const std::string& file) {
  struct Need {
    long code;
    const char* what;
  };
  std::vector<Need> need;
  if (e.kind == "LINE") need = {{10, "start x"}, {20, "start y"}, {11, "end x"}, {21, "end y"}};
  else if (e.kind == "ARC")
    need = {{10, "centre x"}, {20, "centre y"}, {40, "radius"}, {50, "start angle"}, {51, "end angle"}};
  else if (e.kind == "CIRCLE") need = {{10, "centre x"}, {20, "centre y"}, {40, "radius"}};
  else if (e.kind == "VERTEX") need = {{10, "x"}, {20, "y"}};
  else if (e.kind == "INSERT") need = {{2, "block name"}, {10, "insertion x"}, {20, "insertion y"}};
  else if (e.kind == "LWPOLYLINE") need = {{10, "vertex x"}, {20, "vertex y"}};
  for (const Need& n : need) {
    auto it = e.count.find(n.code);
    if (it == e.count.end())
      throw InputError("the " + e.kind + " starting here has no " + n.what + " (group code " + std::to_string(n.code) +
                           "): the entity is damaged or a line is missing",
                       file + ":" + std::to_string(e.line));
  }
  if (e.kind == "LWPOLYLINE") {
    const int nx = e.count.at(10), ny = e.count.at(20);
    if (nx != ny)
      throw InputError("the LWPOLYLINE starting here has " + std::to_string(nx) + " x and " + std::to_string(ny) +
                           " y coordinates (group codes 10 and 20): the entity is damaged or a line is missing",
                       file + ":" + std::to_string(e.line));
    // dxflib keeps as many vertices as group code 90 declares and drops the others without a word
    if (e.has_vertices && e.vertices != nx)
      throw InputError("the LWPOLYLINE starting here declares " + std::to_string(e.vertices) +
                           " vertices (group code 90) but has " + std::to_string(nx) +
                           ": the entity is damaged or a line is missing",
                       file + ":" + std::to_string(e.line));
  }
}

void prevalidate(const std::string& file) {
  std::ifstream in(file, std::ios::binary | std::ios::ate);
  const long long bytes = std::max<long long>(0, static_cast<long long>(in.tellg()));
  in.seekg(0);
  std::string code_text, value;
  size_t line = 0;
  std::string section;        // the section being read
  bool in_section = false, expect_section_name = false, eof = false;
  std::optional<EntityCheck> ent;
  std::string record;  // the name of the record being read (group code 0)
  auto close_entity = [&] {
    if (ent) check_entity(*ent, file);
    ent.reset();
  };
  while (std::getline(in, code_text)) {
    ++line;
    const size_t code_line = line;
    code_text = trim(code_text);
    if (code_text.empty() && in.peek() == EOF) break;  // a final blank line
    long code = 0;
    {
      const char* b = code_text.c_str();
      char* end = nullptr;
      errno = 0;
      code = std::strtol(b, &end, 10);
      if (code_text.empty() || *end != '\0' || errno != 0)
        throw InputError("'" + code_text.substr(0, 40) + "' stands where a group code (an integer) belongs: a line " +
                             "is missing or extra above here, or this is not a DXF file",
                         file + ":" + std::to_string(code_line));
    }
    if (!std::getline(in, value))
      throw InputError("the file ends after a group code without its value: the file is truncated",
                       file + ":" + std::to_string(code_line));
    ++line;
    value = trim(value);
    const std::string where = file + ":" + std::to_string(line);
    if (is_real_code(code)) {
      char* end = nullptr;
      double v = std::strtod(value.c_str(), &end);
      if (value.empty() || *end != '\0')
        throw InputError("'" + value.substr(0, 40) + "' is not a number (group code " + std::to_string(code) +
                             " holds a real number): a line is missing or extra above here",
                         where);
      if (!std::isfinite(v))
        throw InputError("'" + value + "' is not a finite number (group code " + std::to_string(code) + ")", where);
    } else if (is_int_code(code)) {
      char* end = nullptr;
      errno = 0;
      const long long v = std::strtoll(value.c_str(), &end, 10);
      if (value.empty() || *end != '\0' || errno != 0)
        throw InputError("'" + value.substr(0, 40) + "' is not an integer (group code " + std::to_string(code) +
                             "): a line is missing or extra above here",
                         where);
      // Codes 72-79 and 90-99 of an entity count its vertices, knots, control points or edges, and dxflib makes
      // arrays of that size before it reads them (also of an entity outside any section): no count exceeds the
      // lines of the file.
      // dxflib reads an entity by its name in whatever section it stands (a misspelt ENTITIES too), so the
      // entities that carry counts are checked everywhere.
      const bool counted_kind = record == "LWPOLYLINE" || record == "POLYLINE" || record == "SPLINE" ||
                                record == "HATCH" || record == "LEADER" || record == "MLINE" || record == "MTEXT";
      if ((ent || !in_section || counted_kind) && ((code >= 72 && code <= 79) || (code >= 90 && code <= 99)) &&
          (v > bytes / 2 || v < INT_MIN))
        throw InputError("'" + value.substr(0, 40) + "' (group code " + std::to_string(code) + " of the " +
                             (ent ? ent->kind : counted_kind ? record : std::string("record")) +
                             ") is a count larger than this file of " +
                             std::to_string(bytes) + " bytes can hold: the entity is damaged",
                         where);
      if (ent && ent->kind == "LWPOLYLINE" && code == 90) {
        ent->vertices = v;  // a negative count too: dxflib would drop the entity without a word
        ent->has_vertices = true;
      }
    }
    if (code == 0) {
      close_entity();
      record = value;
      if (value == "EOF") {
        eof = true;
        break;
      }
      if (value == "SECTION") {
        in_section = expect_section_name = true;
      } else if (value == "ENDSEC") {
        in_section = false;
        section.clear();
      } else if (value.empty() || !std::isalpha(static_cast<unsigned char>(value[0])))
        throw InputError("'" + value.substr(0, 40) + "' is not an entity or record name (group code 0): a line is " +
                             "missing or extra above here",
                         where);
      else if (in_section && (section == "ENTITIES" || section == "BLOCKS"))
        ent = EntityCheck{value, code_line, {}};
    } else if (code == 2 && expect_section_name) {
      section = value;
      expect_section_name = false;
    } else if (ent) {
      ++ent->count[code];
    }
  }
  if (!eof)
    throw InputError("the file ends at line " + std::to_string(line) + " without the EOF record: it is truncated", file);
  // dxflib does not stop at the EOF record: it reads on to the end of the file, unchecked. Only white space (and
  // an old editor's end-of-file mark, Ctrl-Z) may follow it.
  for (std::string rest; std::getline(in, rest);) {
    ++line;
    for (char c : rest)
      if (!std::isspace(static_cast<unsigned char>(c)) && c != '\x1a')
        throw InputError("text after the EOF record: remove everything after the line 'EOF'",
                         file + ":" + std::to_string(line));
  }
}

PathSegment reversed(PathSegment s) {
  std::swap(s.from, s.to);
  s.sweep = -s.sweep;
  return s;
}

}  // namespace

DxfPath read_dxf_path(const std::string& path, const DxfOptions& opt) {
  open_input_file(path, "cannot open the DXF file");  // a probe: dxflib opens the file itself
  prevalidate(path);
  Collector col(opt);
  DL_Dxf dxf;
  if (!dxf.in(path, &col)) throw InputError("not a readable DXF file", path);
  col.flush_polyline();
  if (!col.bad_radius.empty()) throw InputError(col.bad_radius, path);
  Expander ex(col, opt, path);
  ex.draw(col.top, Affine{}, "0", 0);
  if (!ex.refused.empty()) {
    std::string kinds;
    for (const auto& [k, n] : ex.refused) kinds += (kinds.empty() ? "" : ", ") + std::to_string(n) + " " + k;
    throw InputError("unsupported entities (" + kinds +
                     "); polarcam reads LINE, ARC, CIRCLE and POLYLINE/LWPOLYLINE: convert curves to polylines", path);
  }
  std::vector<PathSegment>& all = ex.segs;
  if (all.empty())
    throw InputError("no LINE, ARC, CIRCLE or POLYLINE entities" + (opt.layer ? " on layer '" + *opt.layer + "'" : ""), path);

  // chain the pieces end to end, in any order and direction
  const double tol = opt.join_tolerance * opt.unit_m;
  std::vector<bool> used(all.size(), false);
  std::vector<PathSegment> chain{all[0]};
  used[0] = true;
  size_t n_used = 1;
  for (bool grew = true; grew;) {
    grew = false;
    for (size_t i = 0; i < all.size(); ++i) {
      if (used[i]) continue;
      const Vec2 head = chain.front().from, tail = chain.back().to;
      if (norm(chain.back().to - chain.front().from) <= tol && chain.size() > 1) break;  // closed already
      PathSegment s = all[i];
      if (norm(s.from - tail) <= tol) {
        chain.push_back(s);
      } else if (norm(s.to - tail) <= tol) {
        chain.push_back(reversed(s));
      } else if (norm(s.to - head) <= tol) {
        chain.insert(chain.begin(), s);
      } else if (norm(s.from - head) <= tol) {
        chain.insert(chain.begin(), reversed(s));
      } else {
        continue;
      }
      used[i] = true;
      ++n_used;
      grew = true;
    }
  }
  if (n_used != all.size())
    throw InputError("the drawing holds " + std::to_string(all.size() - n_used) +
                     " entities that do not join the first chain of " + std::to_string(n_used) +
                     "; give 'layer' to pick one contour, or close the gaps", path);
  for (size_t i = 1; i < chain.size(); ++i) chain[i].from = chain[i - 1].to;  // snap joints within tolerance
  DxfPath out;
  out.closed = norm(chain.back().to - chain.front().from) <= tol;
  if (out.closed) chain.back().to = chain.front().from;
  out.entities = all.size();
  out.segments = std::move(chain);
  return out;
}

}  // namespace polarcam
