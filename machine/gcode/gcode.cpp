#include "machine/gcode/gcode.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <ostream>
#include <sstream>

#include "cam/error.hpp"

namespace polarcam {
namespace {

constexpr double kSplitRatio = 1.009 / 0.991;  // g_end / g_start of one move: +-0.9 % about the centre
constexpr double kBound = 0.01;                // the speed bound after rounding
constexpr int kMaxSplit = 24;                  // further halvings of a move that rounding pushes over the bound
constexpr double kResolutionQuanta = 20.0;     // a move this many last-decimal units long is not split again

std::string fixed(double v, int decimals) {
  char buf[64];
  auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, decimals);
  std::string s(buf, r.ptr);
  if (s[0] == '-' && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);
  return s;
}

double parse(const std::string& s) {
  double v = 0;
  std::from_chars(s.data(), s.data() + s.size(), v);
  return v;
}

std::string comment_text(const std::string& c) {
  std::string o;
  for (char ch : c)
    if (ch != '(' && ch != ')' && static_cast<unsigned char>(ch) >= 0x20 && static_cast<unsigned char>(ch) < 0x7f) o += ch;
  if (o.size() > 70) o.resize(70);
  return o;
}

bool is_axis(const std::string& a) { return a.size() == 1 && std::string("XYZABCUVW").find(a[0]) != std::string::npos; }

// A printed axis position: its text and the value the text reads back as.
struct Coord {
  std::string text;
  double value = 0;
};

class Writer {
 public:
  Writer(std::ostream& out, const GcodeSpec& s, double V) : out_(out), s_(s), V_(V) {
    quantum_ = std::pow(10.0, -s.decimals);
  }

  void line(const std::string& l) {
    out_ << l << '\n';
    ++st_.lines;
  }

  // The rapid move to the start (or, with the tool up, to the next contour).
  void start(const ThetaRho& v, const std::string& comment = "to the start") {
    Coord x, y;
    axes(v, x, y);
    line("G0 " + s_.theta_axis + x.text + " " + s_.rho_axis + y.text + " (" + comment + ")");
    x_ = x, y_ = y;
  }

  // The moves of one theta-rho segment.
  void segment(const ThetaRho& a, const ThetaRho& b) {
    if (a.rho == 0.0 && b.rho == 0.0) {
      centre_turn(b);
      return;
    }
    if (s_.feed_mode == FeedMode::axis) {
      axis_move(b);
      return;
    }
    // n moves of equal ratio of g = sqrt(drho^2 + rho^2 dtheta^2) (per unit of the segment's fraction)
    const double dth = b.theta - a.theta, drho = b.rho - a.rho;
    const double ga = std::hypot(drho, a.rho * dth), gb = std::hypot(drho, b.rho * dth);
    const double ratio = std::max(ga, gb) / std::min(ga, gb);
    int n = 1;
    if (ratio > kSplitRatio && drho != 0.0 && dth != 0.0)
      n = static_cast<int>(std::ceil(std::log(ratio) / std::log(kSplitRatio) - 1e-9));
    ThetaRho prev = a;
    for (int k = 1; k <= n; ++k) {
      ThetaRho next = b;
      if (k < n) {
        const double g = ga * std::pow(gb / ga, static_cast<double>(k) / n);
        const double rho = std::sqrt(std::max(0.0, g * g - drho * drho)) / std::abs(dth);
        const double f = std::clamp((rho - a.rho) / drho, 0.0, 1.0);
        next = {a.theta + f * dth, a.rho + f * drho};
      }
      timed_move(prev, next, 0);
      prev = next;
    }
  }

  // The ball speed of the segments that follow (a speed schedule: one per segment).
  void set_speed(double V) { V_ = V; }

  GcodeStats& stats() { return st_; }

 private:
  void axes(const ThetaRho& v, Coord& x, Coord& y) const {
    x.text = fixed(s_.theta_units_per_rad * v.theta, s_.decimals);
    y.text = fixed(s_.rho_units_per_radius * v.rho / s_.table_radius + s_.coupling * v.theta, s_.decimals);
    x.value = parse(x.text);
    y.value = parse(y.text);
  }
  // The ball's place at printed axis positions.
  ThetaRho ball(double x, double y) const {
    const double th = x / s_.theta_units_per_rad;
    return {th, (y - s_.coupling * th) / s_.rho_units_per_radius * s_.table_radius};
  }

  std::string words(const Coord& x, const Coord& y, const std::string& f) const {
    return "G1 " + s_.theta_axis + x.text + " " + s_.rho_axis + y.text + " F" + f;
  }

  // The duration (min) the axis limits allow for a move, and which axes bind at `t_min`.
  double limit_minutes(double dx, double dy) const {
    return std::max(std::abs(dx) / s_.theta_max_feed, std::abs(dy) / s_.rho_max_feed);
  }
  std::string limit_axes(double dx, double dy, double t_min) const {
    std::string a;
    if (std::abs(dx) / s_.theta_max_feed >= t_min * (1 - 1e-12)) a = s_.theta_axis;
    if (std::abs(dy) / s_.rho_max_feed >= t_min * (1 - 1e-12)) a += (a.empty() ? "" : " ") + s_.rho_axis;
    return a;
  }

  // F as printed: to the nearest last decimal, or down to it where the nearest would exceed `max_f` (the axis
  // limits); InputError when it would print as 0.
  std::string feed_text(double f, double max_f) const {
    std::string t = fixed(f, s_.decimals);
    if (parse(t) > max_f) t = fixed(std::floor(std::min(f, max_f) / quantum_) * quantum_, s_.decimals);
    if (!(parse(t) > 0.0))
      throw InputError("a move's F " + fixed(f, 12) + " rounds to 0 at " + std::to_string(s_.decimals) +
                           " decimals: give more decimals",
                       "decimals");
    return t;
  }

  void emit(const Coord& x, const Coord& y, const std::string& f, double minutes, const std::string& comment) {
    line(words(x, y, f) + (comment.empty() ? "" : " (" + comment + ")"));
    ++st_.g1;
    st_.duration_s += 60.0 * minutes;
    x_ = x, y_ = y;
  }

  // The ball speeds at the two ends of the move from the current position to (x, y) lasting `minutes`.
  void end_speeds(const Coord& x, const Coord& y, double minutes, double& va, double& vb) const {
    const ThetaRho a = ball(x_.value, y_.value), b = ball(x.value, y.value);
    const double dth = b.theta - a.theta, drho = b.rho - a.rho, T = 60.0 * minutes;
    va = std::hypot(drho, a.rho * dth) / T;
    vb = std::hypot(drho, b.rho * dth) / T;
  }

  void record_speeds(double va, double vb, bool limited) {
    if (!have_speed_) st_.ball_speed_min_mps = std::min(va, vb);
    have_speed_ = true;
    st_.ball_speed_min_mps = std::min({st_.ball_speed_min_mps, va, vb});
    st_.ball_speed_max_mps = std::max({st_.ball_speed_max_mps, va, vb});
    if (!limited) {
      const double e = 100.0 * std::max(std::abs(va / V_ - 1.0), std::abs(vb / V_ - 1.0));
      st_.max_speed_error_pct = std::max(st_.max_speed_error_pct, e);
    }
  }

  void centre_turn(const ThetaRho& b) {
    Coord x, y;
    axes(b, x, y);
    if (x.text == x_.text && y.text == y_.text) return;
    const double dx = x.value - x_.value, dy = y.value - y_.value;
    std::string f;
    double minutes;
    std::string comment = "ball at the centre";
    if (s_.feed_mode == FeedMode::inverse_time) {
      const double t = limit_minutes(dx, dy);
      f = feed_text(1.0 / t, 1.0 / t);
      minutes = 1.0 / parse(f);
      comment = "axis limit: " + limit_axes(dx, dy, t) + ", " + comment;
    } else {
      const double dist = std::hypot(dx, dy);
      const double feed = std::min(s_.axis_feed, dist / limit_minutes(dx, dy));
      f = feed_text(feed, dist / limit_minutes(dx, dy));
      minutes = dist / parse(f);
      if (feed < s_.axis_feed) comment = "axis limit: " + limit_axes(dx, dy, dist / feed) + ", " + comment;
    }
    if (comment.find("limit") != std::string::npos) ++st_.limited;
    ++st_.centre_turns;
    emit(x, y, f, minutes, comment);
  }

  void axis_move(const ThetaRho& b) {
    Coord x, y;
    axes(b, x, y);
    if (x.text == x_.text && y.text == y_.text) return;
    const double dx = x.value - x_.value, dy = y.value - y_.value, dist = std::hypot(dx, dy);
    const double feed = std::min(s_.axis_feed, dist / limit_minutes(dx, dy));
    const std::string f = feed_text(feed, dist / limit_minutes(dx, dy));
    const double minutes = dist / parse(f);
    const bool limited = feed < s_.axis_feed;
    double va, vb;
    end_speeds(x, y, minutes, va, vb);
    record_speeds(va, vb, limited);
    if (limited) ++st_.limited;
    emit(x, y, f, minutes, limited ? "axis limit: " + limit_axes(dx, dy, dist / feed) : "");
  }

  // One inverse-time move from a to b (a is the current position's ball place before rounding).
  void timed_move(const ThetaRho& a, const ThetaRho& b, int depth) {
    Coord x, y;
    axes(b, x, y);
    if (x.text == x_.text && y.text == y_.text) return;
    const double dx = x.value - x_.value, dy = y.value - y_.value;
    // the duration that centres the ball speed on V, from the printed positions
    const ThetaRho pa = ball(x_.value, y_.value), pb = ball(x.value, y.value);
    const double dth = pb.theta - pa.theta, drho = pb.rho - pa.rho;
    const double ga = std::hypot(drho, pa.rho * dth), gb = std::hypot(drho, pb.rho * dth);
    const double t_ball = (ga + gb) / (2.0 * V_) / 60.0;
    const double t_axes = limit_minutes(dx, dy);
    const double t = std::max(t_ball, t_axes);
    const std::string f = feed_text(1.0 / t, 1.0 / t_axes);
    const double minutes = 1.0 / parse(f);
    double va, vb;
    end_speeds(x, y, minutes, va, vb);
    const bool limited = t_axes > t_ball;
    const double err = std::max(std::abs(va / V_ - 1.0), std::abs(vb / V_ - 1.0));
    std::string comment;
    if (limited) {
      comment = "axis limit: " + limit_axes(dx, dy, t);
    } else if (err > kBound) {
      const double travel = std::max(std::abs(s_.theta_units_per_rad * (b.theta - a.theta)),
                                     std::abs(s_.rho_units_per_radius * (b.rho - a.rho) / s_.table_radius));
      if (depth < kMaxSplit && travel > 2.0 * kResolutionQuanta * quantum_) {
        const ThetaRho m{0.5 * (a.theta + b.theta), 0.5 * (a.rho + b.rho)};
        timed_move(a, m, depth + 1);
        timed_move(m, b, depth + 1);
        return;
      }
      comment = "resolution limit";
    }
    if (!comment.empty()) ++st_.limited;
    record_speeds(va, vb, !comment.empty());
    emit(x, y, f, minutes, comment);
  }

  std::ostream& out_;
  const GcodeSpec& s_;
  double V_;
  double quantum_;
  Coord x_, y_;
  bool have_speed_ = false;
  GcodeStats st_;
};

}  // namespace

void validate(const GcodeSpec& s) {
  auto finite = [](double v) { return std::isfinite(v); };
  if (!is_axis(s.theta_axis)) throw InputError("must be one axis letter: X, Y, Z, A, B, C, U, V or W", "theta_axis");
  if (!is_axis(s.rho_axis)) throw InputError("must be one axis letter: X, Y, Z, A, B, C, U, V or W", "rho_axis");
  if (s.theta_axis == s.rho_axis) throw InputError("must differ from theta_axis", "rho_axis");
  if (!finite(s.theta_units_per_rad) || s.theta_units_per_rad == 0.0)
    throw InputError("must be a number other than 0 (negative reverses the axis)", "theta_units_per_rad");
  if (!finite(s.rho_units_per_radius) || !(s.rho_units_per_radius > 0.0))
    throw InputError("must be a positive number", "rho_units_per_radius");
  if (!finite(s.table_radius) || !(s.table_radius > 0.0)) throw InputError("must be a positive length", "table_radius");
  if (!finite(s.coupling)) throw InputError("must be a finite number", "coupling");
  if (!finite(s.theta_max_feed) || !(s.theta_max_feed > 0.0))
    throw InputError("must be a positive rate in axis units per minute", "theta_max_feed");
  if (!finite(s.rho_max_feed) || !(s.rho_max_feed > 0.0))
    throw InputError("must be a positive rate in axis units per minute", "rho_max_feed");
  if (s.feed_mode == FeedMode::axis && (!finite(s.axis_feed) || !(s.axis_feed > 0.0)))
    throw InputError("the axis feed mode needs a positive feed in axis units per minute", "axis_feed");
  if (s.decimals < 1 || s.decimals > 9) throw InputError("must be a whole number from 1 to 9", "decimals");
  for (const auto& [lines, key] : {std::pair{&s.header, "header"}, std::pair{&s.footer, "footer"},
                                   std::pair{&s.pen_up, "pen_up"}, std::pair{&s.pen_down, "pen_down"}})
    for (const std::string& l : *lines)
      for (char ch : l)
        if (static_cast<unsigned char>(ch) < 0x20 || static_cast<unsigned char>(ch) >= 0x7f)
          throw InputError("a line holds a character that is not printable ASCII (one line per string)", key);
}

namespace {

GcodeStats write_program(std::ostream& out, const std::vector<std::vector<ThetaRho>>& strokes, const GcodeSpec& spec,
                         double ball_speed_mps, const std::vector<std::string>& comments, bool lift,
                         const std::vector<double>* speeds = nullptr) {
  validate(spec);
  if (!(ball_speed_mps > 0.0) || !std::isfinite(ball_speed_mps)) throw InputError("the ball speed must be positive");
  if (speeds) {
    if (strokes.size() != 1 || speeds->size() + 1 != strokes.front().size())
      throw InputError("a speed schedule needs one speed per segment");
    for (size_t i = 0; i < speeds->size(); ++i)
      if (!((*speeds)[i] > 0.0) || !std::isfinite((*speeds)[i]))
        throw InputError("the ball speed must be positive", "segment " + std::to_string(i + 1));
  }
  if (strokes.empty()) throw InputError("a pattern needs at least two points");
  for (size_t k = 0; k < strokes.size(); ++k) {
    const std::vector<ThetaRho>& v = strokes[k];
    const std::string contour = strokes.size() > 1 ? "contour " + std::to_string(k + 1) + ", " : "";
    if (v.size() < 2) throw InputError(strokes.size() > 1 ? "contour " + std::to_string(k + 1) + " needs at least two points" : "a pattern needs at least two points");
    for (size_t i = 0; i < v.size(); ++i) {
      if (!std::isfinite(v[i].theta) || !std::isfinite(v[i].rho) || v[i].rho < 0.0)
        throw InputError("theta and rho must be finite, rho not negative", contour + "point " + std::to_string(i + 1));
      if (v[i].rho > spec.table_radius * (1.0 + 1e-12))
        throw InputError("lies beyond the table radius (" + fixed(spec.table_radius * 1e3, 3) + " mm)",
                         contour + "point " + std::to_string(i + 1));
    }
  }
  std::ostringstream buf;
  Writer w(buf, spec, ball_speed_mps);
  GcodeStats lifts;
  auto pen = [&](const std::vector<std::string>& lines, size_t& count) {
    for (const std::string& l : lines) w.line(l);
    ++count;
  };
  for (const std::string& c : comments) w.line("(" + comment_text(c) + ")");
  for (const std::string& l : spec.header) w.line(l);
  w.line(spec.feed_mode == FeedMode::inverse_time ? "G93" : "G94");
  for (size_t k = 0; k < strokes.size(); ++k) {
    const std::vector<ThetaRho>& v = strokes[k];
    if (lift) pen(spec.pen_up, lifts.pen_ups);
    w.start(v.front(), k == 0 ? "to the start" : "rapid, tool up, to contour " + std::to_string(k + 1));
    if (k > 0) ++lifts.rapids;
    if (lift) pen(spec.pen_down, lifts.pen_downs);
    for (size_t i = 0; i + 1 < v.size(); ++i) {
      if (speeds) w.set_speed((*speeds)[i]);
      w.segment(v[i], v[i + 1]);
    }
  }
  if (lift) pen(spec.pen_up, lifts.pen_ups);
  w.line("G94");
  for (const std::string& l : spec.footer) w.line(l);
  w.line("M2");
  out << std::move(buf).str();  // the program written at once (all or nothing), its string not copied first
  GcodeStats st = w.stats();
  st.pen_ups = lifts.pen_ups;
  st.pen_downs = lifts.pen_downs;
  st.rapids = lifts.rapids;
  return st;
}

}  // namespace

GcodeStats write_gcode(std::ostream& out, const std::vector<ThetaRho>& v, const GcodeSpec& spec,
                       double ball_speed_mps, const std::vector<std::string>& comments) {
  return write_program(out, {v}, spec, ball_speed_mps, comments, false);
}

GcodeStats write_gcode(std::ostream& out, const std::vector<ThetaRho>& v, const GcodeSpec& spec,
                       const std::vector<double>& segment_speeds, const std::vector<std::string>& comments) {
  double top = 0.0;
  for (double x : segment_speeds) top = std::max(top, x);
  return write_program(out, {v}, spec, top > 0.0 ? top : 1.0, comments, false, &segment_speeds);
}

GcodeStats write_gcode_lifting(std::ostream& out, const std::vector<std::vector<ThetaRho>>& contours,
                               const GcodeSpec& spec, double speed_mps, const std::vector<std::string>& comments) {
  return write_program(out, contours, spec, speed_mps, comments, true);
}

}  // namespace polarcam
