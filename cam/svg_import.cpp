// SVG import: the one translation unit that includes svgpp (heavy to compile) and libxml2. svgpp walks the
// document and parses every attribute; the contexts here keep the current transform, collect each shape's
// subpaths in user units as exact segments and, when the element ends, map them into metres with y up.
#include "cam/svg_import.hpp"

#include <libxml/parser.h>
#include <libxml/tree.h>

#include <svgpp/policy/xml/libxml2.hpp>
#include <svgpp/svgpp.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <mutex>
#include <numbers>
#include <sstream>

#include "cam/error.hpp"
#include "cam/format.hpp"
#include "cam/input_file.hpp"

namespace polarcam {
namespace {

namespace tag = svgpp::tag;

constexpr double kMetresPerPx = 0.0254 / 96.0;  // CSS: 96 px to the inch
constexpr size_t kMaxUses = 100000;              // <use> expansions in one drawing (a guard against blow-ups)

// A problem found while reading the document: the message and, when known, the element it concerns. svgpp adds
// the element it was reading to a fault that has none (its exception interception, add_element_info below).
struct Fault {
  std::string message;
  xmlNode* node = nullptr;
};

std::string local_name(const xmlNode* n) {
  const char* name = reinterpret_cast<const char*>(n->name);
  const char* colon = std::strrchr(name, ':');
  return colon ? colon + 1 : name;
}

std::string attribute(const xmlNode* n, const char* name, const char* ns = nullptr) {
  xmlChar* v = ns ? xmlGetNsProp(n, reinterpret_cast<const xmlChar*>(name), reinterpret_cast<const xmlChar*>(ns))
                  : xmlGetNoNsProp(n, reinterpret_cast<const xmlChar*>(name));
  if (!v) return {};
  std::string s(reinterpret_cast<const char*>(v));
  xmlFree(v);
  return s;
}

std::string element_id(const xmlNode* n) { return attribute(n, "id"); }

// "<path id="wing">", or "<path>" without an id.
std::string describe(const xmlNode* n) {
  std::string id = element_id(n);
  return "<" + local_name(n) + (id.empty() ? "" : " id=\"" + id + "\"") + ">";
}

// <switch> draws its first direct child that carries no condition (requiredFeatures, requiredExtensions,
// systemLanguage): conditions are not evaluated.
bool in_switch_not_chosen(const xmlNode* n) {
  const xmlNode* sw = n->parent;
  if (!sw || sw->type != XML_ELEMENT_NODE || local_name(sw) != "switch") return false;
  for (const xmlNode* c = sw->children; c; c = c->next) {
    if (c->type != XML_ELEMENT_NODE) continue;
    if (xmlHasProp(c, reinterpret_cast<const xmlChar*>("requiredFeatures")) ||
        xmlHasProp(c, reinterpret_cast<const xmlChar*>("requiredExtensions")) ||
        xmlHasProp(c, reinterpret_cast<const xmlChar*>("systemLanguage")))
      continue;
    return c != n;
  }
  return true;
}

// Text quoted in a message: on one line, at most `max` bytes.
std::string one_line(std::string v, size_t max) {
  for (char& ch : v)
    if (static_cast<unsigned char>(ch) < 0x20) ch = ' ';
  if (v.size() > max) {
    size_t cut = max - 3;
    while (cut > 0 && (static_cast<unsigned char>(v[cut]) & 0xC0) == 0x80) --cut;  // not inside a UTF-8 character
    v = v.substr(0, cut) + "...";
  }
  return v;
}
std::string short_value(const std::string& v) { return one_line(v, 40); }

// What the whole traversal shares: the output, the ids, the <use> references being expanded.
struct Shared {
  SvgDrawing* out = nullptr;
  std::map<std::string, xmlNode*> ids;
  std::vector<std::string> use_stack;
  size_t uses = 0;
};

// ---- the error policy: svgpp's complaints become faults ------------------------------------------------------

class BaseContext;

struct ErrorPolicy {
  typedef BaseContext context_type;  // every context derives from it
  typedef Fault intercepted_exception_type;

  template <class XMLElement>
  static bool add_element_info(Fault& e, XMLElement const& element) {
    if (!e.node) e.node = element;
    throw;
  }
  // Elements and attributes svgpp does not know (other vocabularies, data-* attributes): not geometry.
  template <class C, class E, class N>
  static bool unknown_element(C const&, E const&, N const&) { return true; }
  template <class C, class A, class N, class NS>
  static bool unknown_attribute(C const&, A const&, N const&, NS, tag::source::attribute) { return true; }
  template <class C, class A, class N>
  static bool unknown_attribute(C const&, A const&, N const&, tag::source::css) { return true; }
  template <class C, class Id>
  static bool unexpected_attribute(C const&, Id, tag::source::attribute) { return true; }
  template <class C, class E>
  static bool unexpected_element(C const&, E const&) { return true; }

  template <class C, class AttributeTag>
  static bool required_attribute_not_found(C const&, AttributeTag) {
    throw Fault{std::string("lacks its attribute \"") + svgpp::attribute_name<char>::get<AttributeTag>() +
                "\"; add it"};
  }
  template <class C, class AttributeTag, class Value>
  static bool parse_failed(C const&, AttributeTag, Value const& value) {
    const std::string name = svgpp::attribute_name<char>::get<AttributeTag>();
    std::string v(boost::begin(value), boost::end(value));
    throw Fault{"its attribute \"" + name + "\" cannot be read (\"" + short_value(v) + "\"); " + example(name)};
  }
  static std::string example(const std::string& name) {
    if (name == "d") return "write path data as SVG does, e.g. d=\"M 10 20 L 30 40 Z\", with finite numbers";
    if (name == "transform") return "write transforms as SVG does, e.g. transform=\"translate(10 20) rotate(30)\"";
    if (name == "points") return "write pairs of finite numbers, e.g. points=\"0,0 10,0 10,10\"";
    if (name == "viewBox") return "write four finite numbers, e.g. viewBox=\"0 0 100 50\"";
    return "write a finite number with an optional unit, e.g. \"10\" or \"5mm\"";
  }
  template <class C, class AttributeTag>
  static bool negative_value(C const&, AttributeTag) {
    throw Fault{std::string("its attribute \"") + svgpp::attribute_name<char>::get<AttributeTag>() +
                "\" is negative; make it zero or more"};
  }
};

// ---- preserveAspectRatio -------------------------------------------------------------------------------------

struct Align {
  bool none = false, slice = false;
  double fx = 0.5, fy = 0.5;  // where the viewBox sits in the spare room: 0 min, 0.5 mid, 1 max
};
inline void align_of(tag::value::xMinYMin, Align& a) { a.fx = 0, a.fy = 0; }
inline void align_of(tag::value::xMidYMin, Align& a) { a.fx = 0.5, a.fy = 0; }
inline void align_of(tag::value::xMaxYMin, Align& a) { a.fx = 1, a.fy = 0; }
inline void align_of(tag::value::xMinYMid, Align& a) { a.fx = 0, a.fy = 0.5; }
inline void align_of(tag::value::xMidYMid, Align& a) { a.fx = 0.5, a.fy = 0.5; }
inline void align_of(tag::value::xMaxYMid, Align& a) { a.fx = 1, a.fy = 0.5; }
inline void align_of(tag::value::xMinYMax, Align& a) { a.fx = 0, a.fy = 1; }
inline void align_of(tag::value::xMidYMax, Align& a) { a.fx = 0.5, a.fy = 1; }
inline void align_of(tag::value::xMaxYMax, Align& a) { a.fx = 1, a.fy = 1; }
inline void slice_of(tag::value::meet, Align& a) { a.slice = false; }
inline void slice_of(tag::value::slice, Align& a) { a.slice = true; }

// ---- contexts ------------------------------------------------------------------------------------------------

class BaseContext {
 public:
  typedef svgpp::factory::length::unitless<> length_factory_type;

  // The root <svg>.
  BaseContext(Shared& sh, xmlNode* node) : sh_(&sh), node_(node), root_(true), is_svg_(true) {
    lf_.set_absolute_units_coefficient(96, tag::length_units::in());
    lf_.set_em_coefficient(16);
    lf_.set_ex_coefficient(8);
    // a percentage on the outermost <svg> has nothing to be a percentage of: NaN, read as absent
    lf_.set_viewport_size(std::nan(""), std::nan(""));
  }
  // An element inside `parent`.
  BaseContext(BaseContext& parent, xmlNode* node)
      : sh_(parent.sh_), node_(node), skipped_(in_switch_not_chosen(node)), ctm_(parent.ctm()), lf_(parent.lf_),
        is_svg_(local_name(node) == "svg") {}

  length_factory_type const& length_factory() const { return lf_; }
  bool hidden() const { return hidden_ || skipped_; }
  void on_exit_element() { establish_viewport(); }

  // transforms: svgpp joins an element's list into one matrix
  void transform_matrix(const boost::array<double, 6>& m) {
    for (double v : m)
      if (!std::isfinite(v)) fail("its transform has a number that is not finite; write finite numbers");
    ctm_ = ctm_ * Affine2{m[0], m[1], m[2], m[3], m[4], m[5]};
  }

  void set(tag::attribute::display, tag::value::none) { hidden_ = true; }
  template <class Value>
  void set(tag::attribute::display, Value) { hidden_ = false; }  // a later value (style over attribute) wins

  // the viewport of an <svg> (x and y of an inner one; width, height, viewBox, preserveAspectRatio)
  void set(tag::attribute::x, double v) { x_ = v; }
  void set(tag::attribute::y, double v) { y_ = v; }
  void set(tag::attribute::width, double v) { width_ = v; }
  void set(tag::attribute::height, double v) { height_ = v; }
  void set(tag::attribute::viewBox, double x, double y, double w, double h) {
    has_viewbox_ = true;
    viewbox_[0] = x, viewbox_[1] = y, viewbox_[2] = w, viewbox_[3] = h;
  }
  void set(tag::attribute::preserveAspectRatio, bool, tag::value::none) { align_.none = true; }
  template <class AlignTag, class MeetOrSlice>
  void set(tag::attribute::preserveAspectRatio, bool, AlignTag a, MeetOrSlice m) {
    align_.none = false;
    align_of(a, align_);
    slice_of(m, align_);
  }
  // everything else an element may carry is not geometry
  template <class... Args>
  void set(Args&&...) {}

  [[noreturn]] void fail(const std::string& message) const { throw Fault{message, node_}; }

 protected:
  Affine2 ctm() {
    establish_viewport();
    return ctm_;
  }

  Shared* sh_;
  xmlNode* node_;
  bool root_ = false;
  bool hidden_ = false;   // display="none" (or an inner <svg> of no size)
  bool skipped_ = false;  // a child of <switch> other than the one it draws
  Affine2 ctm_;  // user units of this element -> metres, y up
  length_factory_type lf_;

 private:
  // An <svg>'s viewport, once its attributes are read (when its first child is entered, or when it ends): the map
  // of its user units onto its parent's (the root: onto metres with y up), and the size percentages of its
  // content refer to.
  void establish_viewport() {
    if (!is_svg_ || viewport_done_) return;
    viewport_done_ = true;
    // NaN: absent (a percentage on the outermost <svg> has nothing to be a percentage of, and reads as NaN)
    double w = width_, h = height_;
    if (!root_) {
      if (std::isnan(w)) w = lf_.create_length(100, tag::length_units::percent(), tag::length_dimension::width());
      if (std::isnan(h)) h = lf_.create_length(100, tag::length_units::percent(), tag::length_dimension::height());
      if (!std::isfinite(w) || !std::isfinite(h) || !std::isfinite(x_) || !std::isfinite(y_))
        fail("its position or size is not a finite number; give x, y, width and height in finite numbers");
    }
    if (std::isinf(w) || std::isinf(h)) fail("its width or height is not a finite number; write finite numbers");
    if (w < 0 || h < 0) fail("has a negative width or height; make them positive");
    if (has_viewbox_) {
      for (double v : viewbox_)
        if (!std::isfinite(v)) fail("its viewBox has a number that is not finite; write four finite numbers");
      if (!(viewbox_[2] > 0) || !(viewbox_[3] > 0))
        fail("its viewBox has zero or negative width or height; give it a positive size (viewBox=\"x y width height\")");
      if (root_) {  // a missing size follows from the viewBox (user units are px)
        const double vw = viewbox_[2], vh = viewbox_[3];
        if (std::isnan(w) && std::isnan(h)) w = vw, h = vh;
        else if (std::isnan(w)) w = h * vw / vh;
        else if (std::isnan(h)) h = w * vh / vw;
      }
    }
    if (w == 0 || h == 0) {
      if (root_) fail("has a width or height of zero; give the drawing its size");
      hidden_ = true;  // an inner <svg> of no size draws nothing
      return;
    }
    Affine2 vb;  // viewBox -> viewport
    if (has_viewbox_) {
      const double vx = viewbox_[0], vy = viewbox_[1], vw = viewbox_[2], vh = viewbox_[3];
      double sx = w / vw, sy = h / vh;
      if (!align_.none) sx = sy = align_.slice ? std::max(sx, sy) : std::min(sx, sy);
      double tx = -vx * sx, ty = -vy * sy;
      if (!align_.none) {
        tx += (w - vw * sx) * align_.fx;
        ty += (h - vh * sy) * align_.fy;
      }
      vb = Affine2{sx, 0, 0, sy, tx, ty};
    }
    if (root_) {
      // px -> metres, y up about the drawing's top edge at height H (0 when the drawing has no height)
      const double W = std::isnan(w) ? 0.0 : w, H = std::isnan(h) ? 0.0 : h;
      ctm_ = Affine2{kMetresPerPx, 0, 0, -kMetresPerPx, 0, H * kMetresPerPx} * vb;
      sh_->out->width = W * kMetresPerPx;
      sh_->out->height = H * kMetresPerPx;
    } else {
      ctm_ = ctm_ * Affine2::translate(x_, y_) * vb;
    }
    if (has_viewbox_) lf_.set_viewport_size(viewbox_[2], viewbox_[3]);
    else if (!std::isnan(w) && !std::isnan(h)) lf_.set_viewport_size(w, h);
  }

  bool is_svg_ = false, viewport_done_ = false;  // is_svg_ is set in the constructors
  double x_ = 0, y_ = 0, width_ = std::nan(""), height_ = std::nan("");
  bool has_viewbox_ = false;
  double viewbox_[4] = {0, 0, 0, 0};  // x y width height
  Align align_;
};

// <path> and the basic shapes (svgpp turns those into path events): the subpaths in user units.
class ShapeContext : public BaseContext {
 public:
  ShapeContext(BaseContext& parent, xmlNode* node) : BaseContext(parent, node) {}

  void path_move_to(double x, double y, tag::coordinate::absolute) {
    finish();
    cur_ = point(x, y);
    start_ = cur_;
    have_point_ = true;
  }
  void path_line_to(double x, double y, tag::coordinate::absolute) {
    Vec2 p = point(x, y);
    open();
    if (p != cur_) segs_.push_back(line_segment(cur_, p));
    cur_ = p;
  }
  void path_cubic_bezier_to(double x1, double y1, double x2, double y2, double x, double y, tag::coordinate::absolute) {
    Vec2 c1 = point(x1, y1), c2 = point(x2, y2), p = point(x, y);
    open();
    if (!(c1 == cur_ && c2 == cur_ && p == cur_)) segs_.push_back(cubic_segment(cur_, c1, c2, p));
    cur_ = p;
  }
  void path_quadratic_bezier_to(double x1, double y1, double x, double y, tag::coordinate::absolute) {
    Vec2 c = point(x1, y1), p = point(x, y);
    open();
    if (!(c == cur_ && p == cur_)) segs_.push_back(quadratic_segment(cur_, c, p));
    cur_ = p;
  }
  void path_elliptical_arc_to(double rx, double ry, double rotation_deg, bool large_arc, bool sweep, double x, double y,
                              tag::coordinate::absolute) {
    Vec2 p = point(x, y);
    for (double v : {rx, ry, rotation_deg})
      if (!std::isfinite(v)) fail("its path data has a number that is not finite; write finite numbers");
    open();
    append_svg_arc(segs_, cur_, rx, ry, rotation_deg * std::numbers::pi / 180.0, large_arc, sweep, p);
    cur_ = p;
  }
  void path_close_subpath() {
    if (open_) {
      if (!meets_start()) segs_.push_back(line_segment(cur_, start_));  // else the curve snaps the rounding gap
      closed_ = true;
      finish();
    }
    cur_ = start_;  // a command after Z starts a new subpath here
  }
  void path_exit() { finish(); }

  void on_exit_element() {
    finish();
    if (hidden() || subpaths_.empty()) return;
    const Affine2 m = ctm();
    if (!(std::abs(m.det()) > 0.0)) return;  // a singular transform draws nothing
    const std::string id = element_id(node_), name = local_name(node_);
    const int line = static_cast<int>(xmlGetLineNo(node_));
    for (size_t k = 0; k < subpaths_.size(); ++k) {
      std::vector<CurveSegment> segs;
      segs.reserve(subpaths_[k].segs.size());
      for (const CurveSegment& g : subpaths_[k].segs) segs.push_back(g.transformed(m));
      // no machine draws a kilometre from its pole: numbers beyond that are a damaged drawing or a wrong unit, and
      // fitting them onto a table would scale them by a factor that rounds to nothing
      auto reach = [](Vec2 q) { return std::max(std::abs(q.x), std::abs(q.y)); };
      for (const CurveSegment& g : segs) {
        const double far = g.kind == CurveSegment::Kind::arc
                               ? std::max({reach(g.center), reach(g.ax), reach(g.ay)})
                               : std::max({reach(g.p[0]), reach(g.p[1]), reach(g.p[2]), reach(g.p[3])});
        if (!(far <= 1e3))
          fail("subpath " + std::to_string(k + 1) + " reaches " + significant(far, 3) +
               " m once transformed into metres (beyond 1 km): check its numbers, its units and the transforms above it");
      }
      std::ostringstream label;
      label << "svg " << describe(node_) << " line " << line;
      if (subpaths_.size() > 1) label << " subpath " << k + 1;
      CurvePtr c;
      try {
        c = make_segment_curve(std::move(segs), subpaths_[k].closed, label.str());
      } catch (const InputError& e) {
        fail("subpath " + std::to_string(k + 1) + ": " + e.message() +
             " once transformed into metres; check its numbers and the transforms above it");
      }
      sh_->out->contours.push_back(SvgContour{std::move(c), id, name, line, k});
    }
  }

 private:
  struct Subpath {
    std::vector<CurveSegment> segs;
    bool closed = false;
  };

  Vec2 point(double x, double y) const {
    if (!std::isfinite(x) || !std::isfinite(y))
      fail("a coordinate is not a finite number; write finite numbers (a percentage needs the <svg>'s viewBox or its "
           "width and height)");
    return {x, y};
  }
  void open() {
    if (!have_point_) fail("its path data draws before its first moveto; start it with M");
    if (!open_) {
      open_ = true;
      start_ = cur_;
    }
  }
  // The current point is the subpath's start, or within rounding of it (1e-9 of its largest coordinate).
  bool meets_start() const {
    double size = std::max({std::abs(start_.x), std::abs(start_.y), std::abs(cur_.x), std::abs(cur_.y)});
    for (const CurveSegment& g : segs_) size = std::max({size, std::abs(g.end().x), std::abs(g.end().y)});
    return norm(cur_ - start_) <= 1e-9 * size;
  }
  void finish() {
    if (open_ && !segs_.empty())  // a subpath that ends where it starts is closed, Z or not
      subpaths_.push_back(Subpath{std::move(segs_), closed_ || meets_start()});
    segs_.clear();
    open_ = false;
    closed_ = false;
  }

  std::vector<Subpath> subpaths_;
  std::vector<CurveSegment> segs_;
  Vec2 cur_, start_;
  bool have_point_ = false, open_ = false, closed_ = false;
};

class UseContext : public BaseContext {
 public:
  UseContext(BaseContext& parent, xmlNode* node) : BaseContext(parent, node) {}
  using BaseContext::set;
  void set(tag::attribute::x, double v) { x_ = v; }
  void set(tag::attribute::y, double v) { y_ = v; }
  void on_exit_element();

 private:
  double x_ = 0, y_ = 0;
};

struct ChildContextFactories {
  template <class ParentContext, class ElementTag, class Enable = void>
  struct apply {
    typedef svgpp::factory::context::on_stack_with_xml_element<BaseContext> type;
  };
};
template <class ParentContext, class ElementTag>
struct ChildContextFactories::apply<ParentContext, ElementTag,
                                    typename boost::enable_if<boost::mpl::has_key<svgpp::traits::shape_elements, ElementTag>>::type> {
  typedef svgpp::factory::context::on_stack_with_xml_element<ShapeContext> type;
};
template <class ParentContext>
struct ChildContextFactories::apply<ParentContext, tag::element::use_, void> {
  typedef svgpp::factory::context::on_stack_with_xml_element<UseContext> type;
};

// An element's content is read unless display="none" hides it (and all it holds).
struct TraversalControl {
  template <class Context>
  static bool proceed_to_element_content(Context const& c) { return !c.hidden(); }
  template <class Context>
  static bool proceed_to_next_child(Context const&) { return true; }
  template <class Context, class XMLElement>
  static bool process_child(Context const&, XMLElement const&) { return true; }
};

typedef boost::mpl::fold<svgpp::traits::shape_elements,
                         boost::mpl::set<tag::element::svg, tag::element::g, tag::element::a, tag::element::switch_,
                                                         tag::element::use_>::type,
                         boost::mpl::insert<boost::mpl::_1, boost::mpl::_2>>::type processed_elements_t;

typedef boost::mpl::fold<
    boost::mpl::protect<boost::mpl::joint_view<svgpp::traits::shapes_attributes_by_element,
                                               svgpp::traits::viewport_attributes>>,
    boost::mpl::set<tag::attribute::transform, tag::attribute::display>::type,
    boost::mpl::insert<boost::mpl::_1, boost::mpl::_2>>::type processed_attributes_t;

typedef svgpp::document_traversal<
    svgpp::processed_elements<processed_elements_t>, svgpp::processed_attributes<processed_attributes_t>,
    svgpp::context_factories<ChildContextFactories>,
    svgpp::length_policy<svgpp::policy::length::forward_to_method<BaseContext>>,
    svgpp::error_policy<ErrorPolicy>,
    svgpp::document_traversal_control_policy<TraversalControl>>
    document_traversal_t;

void UseContext::on_exit_element() {
  if (hidden()) return;
  std::string href = attribute(node_, "href", "http://www.w3.org/1999/xlink");
  if (href.empty()) href = attribute(node_, "href");
  if (href.empty()) fail("has no href; name the element it draws (href=\"#id\")");
  if (href[0] != '#')
    fail("refers to \"" + short_value(href) + "\" outside this file; only references within it (\"#id\") are read");
  const std::string id = href.substr(1);
  auto it = sh_->ids.find(id);
  if (it == sh_->ids.end()) fail("refers to \"#" + short_value(id) + "\", which is not in the file; correct the id");
  const std::string what = local_name(it->second);
  if (what == "symbol" || what == "svg")
    fail("draws a <" + what + ">, which is not read; draw its shapes through a <g> or copy them");
  if (std::find(sh_->use_stack.begin(), sh_->use_stack.end(), id) != sh_->use_stack.end())
    fail("refers to \"#" + short_value(id) + "\", which contains this <use>: a reference to itself");
  if (++sh_->uses > kMaxUses) fail("expands more than 100000 <use> references; flatten the drawing");
  ctm_ = ctm() * Affine2::translate(x_, y_);
  sh_->use_stack.push_back(id);
  document_traversal_t::load_referenced_element<
      svgpp::referencing_element<tag::element::use_>, svgpp::expected_elements<svgpp::traits::reusable_elements>,
      svgpp::processed_elements<processed_elements_t>>::load(it->second, *this);
  sh_->use_stack.pop_back();
}

// ---- libxml2 -------------------------------------------------------------------------------------------------

struct DocFree {
  void operator()(xmlDoc* d) const { xmlFreeDoc(d); }
};
struct CtxtFree {
  void operator()(xmlParserCtxt* c) const { xmlFreeParserCtxt(c); }
};

void collect_ids(xmlNode* n, std::map<std::string, xmlNode*>& ids) {
  for (; n; n = n->next) {
    if (n->type != XML_ELEMENT_NODE) continue;
    std::string id = element_id(n);
    if (!id.empty()) ids.emplace(id, n);  // the first of equal ids, as browsers do
    collect_ids(n->children, ids);
  }
}

std::string at_line(const std::string& place, long line) {
  return line > 0 ? place + ":" + std::to_string(line) : place;
}

}  // namespace

SvgDrawing parse_svg(const std::string& text, const std::string& place) {
  static std::once_flag init;
  std::call_once(init, [] { xmlInitParser(); });
  if (text.size() > static_cast<size_t>(std::numeric_limits<int>::max()))
    throw InputError("the file is too large for an SVG drawing (over 2 GB)", place);
  std::unique_ptr<xmlParserCtxt, CtxtFree> ctxt(xmlNewParserCtxt());
  if (!ctxt) throw std::bad_alloc();
  std::unique_ptr<xmlDoc, DocFree> doc(
      xmlCtxtReadMemory(ctxt.get(), text.data(), static_cast<int>(text.size()), nullptr, nullptr,
                        XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING | XML_PARSE_BIG_LINES));
  if (!doc || !ctxt->wellFormed) {
    const xmlError* e = xmlCtxtGetLastError(ctxt.get());
    std::string why = e && e->message ? e->message : "unreadable";
    while (!why.empty() && (why.back() == '\n' || why.back() == ' ')) why.pop_back();
    why = one_line(why, 120);
    throw InputError("the file is not XML (" + why + "); save the drawing as SVG", at_line(place, e ? e->line : 0));
  }
  xmlNode* root = xmlDocGetRootElement(doc.get());
  if (!root || local_name(root) != "svg" || !root->ns ||
      std::string(reinterpret_cast<const char*>(root->ns->href)) != "http://www.w3.org/2000/svg")
    throw InputError(std::string("the root element is ") + (root ? describe(root) : "missing") +
                         ", not an SVG <svg xmlns=\"http://www.w3.org/2000/svg\">; save the drawing as SVG",
                     at_line(place, root ? xmlGetLineNo(root) : 0));

  SvgDrawing out;
  Shared sh;
  sh.out = &out;
  collect_ids(root, sh.ids);
  try {
    BaseContext context(sh, root);
    document_traversal_t::load_document(root, context);
  } catch (const Fault& f) {
    xmlNode* n = f.node ? f.node : root;
    throw InputError(describe(n) + ": " + f.message, at_line(place, xmlGetLineNo(n)));
  } catch (const svgpp::exception_base& e) {
    throw InputError(std::string("the drawing cannot be read: ") + e.what(), place);
  }
  if (out.contours.empty())
    throw InputError("the drawing has no drawable geometry (no visible path, rect, circle, ellipse, line, polyline or polygon); "
                     "convert text and images to paths",
                     place);
  return out;
}

SvgDrawing read_svg(const std::string& path) {
  std::ifstream in = open_input_file(path, "cannot open the SVG drawing");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw DeviceError("cannot read the SVG drawing", path);
  return parse_svg(ss.str(), path);
}

}  // namespace polarcam
