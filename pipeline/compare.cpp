// The polar machine against a Cartesian one (docs/compare.md). One file of over 500 lines on purpose: each
// attribute of Table 3.1 is measured by its own routine over the same pair of tapes and the same verdict rules.
#include "pipeline/compare.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "cam/format.hpp"
#include "pipeline/job_tape.hpp"
#include "io/output.hpp"
#include "pipeline/tape_metrics.hpp"
#include "cam/error.hpp"
#include "cam/scaled.hpp"
#include "digitizer/tape.hpp"
#include "machine/cartesian/cartesian_track.hpp"
#include "metrics/node_box.hpp"
#include "io/temp_files.hpp"

namespace polarcam {
namespace {

// A temporary tape, removed when it goes out of scope (or by an interrupt: io/temp_files.hpp).
class TempTape {
 public:
  explicit TempTape(const char* tag) : file_(name(tag)) {}
  const std::string& path() const { return file_.path(); }

 private:
  static std::string name(const char* tag) {
    static int counter = 0;
    return (std::filesystem::temp_directory_path() /
            ("polarcam-compare-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + "-" + tag + ".tape"))
        .string();
  }
  TempFile file_;
};

class FanOut final : public StepSink {
 public:
  explicit FanOut(std::vector<StepSink*> s) : s_(std::move(s)) {}
  void step(int axis, int dir, int64_t t) override {
    for (StepSink* s : s_) s->step(axis, dir, t);
  }

 private:
  std::vector<StepSink*> s_;
};

// Every step of a tape, with its time in nanoseconds, into `sink`; returns the start node.
void replay(const std::string& tape, StepSink& sink, int64_t start[2]) {
  TapeReader rd(tape);
  const TapeHeader& h = rd.header();
  start[0] = h.start[0];
  start[1] = h.start[1];
  StepRecord r;
  uint64_t ticks = 0;
  while (rd.next(r)) {
    ticks += r.interval;
    const int64_t t = h.tick_ps == 1000 ? static_cast<int64_t>(ticks)
                                        : std::llround(static_cast<double>(ticks) * static_cast<double>(h.tick_ps) * 1e-3);
    sink.step(r.axis, r.dir, t);
  }
}

std::string fmt(double v, int prec = 4) { return cli::significant(v, prec); }
std::string fixed(double v, int dec) {
  std::ostringstream os;
  os.setf(std::ios::fixed);
  os.precision(dec);
  os << v;
  return os.str();
}
std::string mm(double m, int prec = 4) { return fmt(m * 1e3, prec) + " mm"; }
std::string mmps(double v, int prec = 4) { return fmt(v * 1e3, prec) + " mm/s"; }

// The staircase's runs inside a window, in the contour frame: a sink that follows the nodes.
class WindowCollector final : public StepSink {
 public:
  WindowCollector(bool polar, double res0, double res1, Vec2 offset, const int64_t start[2], const DetailWindow& w)
      : polar_(polar), res_{res0, res1}, off_(offset), node_{start[0], start[1]}, w_(w) {
    add(at(static_cast<double>(node_[0]), static_cast<double>(node_[1])));
  }
  void step(int axis, int dir, int64_t) override {
    const double n = static_cast<double>(node_[0]), m = static_cast<double>(node_[1]);
    node_[axis & 1] += dir;
    if (polar_ && axis == 1) {  // an arc: a few points along it
      for (int k = 1; k < 4; ++k) add(at(n, m + dir * k / 4.0));
    }
    add(at(static_cast<double>(node_[0]), static_cast<double>(node_[1])));
  }
  std::vector<std::vector<Vec2>> runs;

 private:
  Vec2 at(double a, double b) const {
    if (!polar_) return Vec2{a * res_[0], b * res_[1]} + off_;
    const double r = a * res_[0], t = b * res_[1];
    return Vec2{r * std::cos(t), r * std::sin(t)} + off_;
  }
  bool inside(Vec2 p) const {
    const double h = w_.half * 1.2;
    return std::abs(p.x - w_.center.x) <= h && std::abs(p.y - w_.center.y) <= h;
  }
  void add(Vec2 p) {
    const bool in = inside(p);
    if (in && !was_in_) {
      runs.emplace_back();
      if (have_prev_) runs.back().push_back(prev_);  // from just outside, so the run reaches the frame
    }
    if (in || was_in_) runs.back().push_back(p);
    was_in_ = in;
    prev_ = p;
    have_prev_ = true;
  }
  bool polar_;
  double res_[2];
  Vec2 off_;
  int64_t node_[2];
  DetailWindow w_;
  bool was_in_ = false, have_prev_ = false;
  Vec2 prev_;
};

// The runs of a curve inside a window, sampled finely.
std::vector<std::vector<Vec2>> curve_in_window(const Curve& c, double length, const DetailWindow& w) {
  std::vector<std::vector<Vec2>> runs;
  const double step = w.half / 400.0;
  const double n = std::clamp(length / step, 2000.0, 4e6);
  const int N = static_cast<int>(n);
  const double h = w.half * 1.2;
  bool was_in = false;
  Vec2 prev;
  for (int i = 0; i <= N; ++i) {
    const double u = c.u_begin() + (c.u_end() - c.u_begin()) * i / N;
    const Vec2 p = c.eval(u, 0).p;
    const bool in = std::abs(p.x - w.center.x) <= h && std::abs(p.y - w.center.y) <= h;
    if (in && !was_in) {
      runs.emplace_back();
      if (i > 0) runs.back().push_back(prev);
    }
    if (in || was_in) runs.back().push_back(p);
    was_in = in;
    prev = p;
  }
  return runs;
}

// ------------------------------------------------------------------------------------------- the polar machine

void polar_side(const Job& job, const CompareOptions& opt, Comparison& c, const TempTape& tape, const Progress& progress) {
  MachineSide& s = c.polar;
  s.name = "polar";
  s.method = to_string(job.motion.rule);
  s.axis[0] = "r";
  s.axis[1] = "theta";
  const Grid& g = job.machine.grid;
  s.grid = "ΔR = " + mm(g.dr) + ", Δθ = " + fmt(g.dtheta, 6) + " rad" +
           (g.steps_per_rev ? " (" + std::to_string(g.steps_per_rev) + " steps/rev)" : std::string()) +
           ", pole at C = " + mm(job.placement.C) + ", β = " + fmt(job.placement.beta) + " rad from the contour pole";
  const Vec2 pole = job.placement.pole();  // O - O1: machine frame -> contour frame
  c.polar_pole = pole;

  DigitizedJob d;
  {
    TapeHeader h = tape_header_for(job);
    TapeWriter w(tape.path(), h);
    d = digitize_job(job, &w, progress_part(progress, 0.0, 0.3));
    complete_header(h, d.result);
    w.finish(h);
  }
  s.steps[0] = d.result.radial.steps();
  s.steps[1] = d.result.angular.steps();
  s.duration_s = d.result.duration_s;
  s.path_length_m = d.result.path_length_m;
  s.tape_bytes = std::filesystem::file_size(tape.path());

  const PolarTapeMetrics pm = polar_tape_metrics(job, tape.path(), 0, progress_part(progress, 0.3, 0.8));
  s.area_m2 = pm.m.area.area_m2;
  s.deviation_m = pm.m.deviation_max_m;
  s.deviation_at = pm.m.deviation_at + pole;
  s.resolution_worst_m = pm.m.deviation_eq41_m;
  const double rmax = path_ranges(d).r_max;
  s.resolution_where = rmax * g.dtheta > g.dr
                           ? "r Δθ at the path's largest radius, r = " + mm(rmax, 5)
                           : "ΔR (the path stays within r = ΔR / Δθ, where r Δθ <= ΔR)";

  const double V = job.motion.nominal_speed();
  if (opt.figures) s.trace.emplace(600, s.duration_s);
  s.speed = measure_tape_speed(tape.path(), V, 1.0, opt.figures ? &*s.trace : nullptr);

  // speed scaling: the same tape, every interval divided by K (Sec. 3.6)
  SpeedScalingFact& sp = s.speed_scaling;
  sp.factor = opt.speed_scale.value();
  sp.without_reprocessing = true;
  sp.how = "the same tape played with every interval divided by " + to_string(opt.speed_scale);
  sp.speed = measure_tape_speed(tape.path(), sp.factor * V, sp.factor);

  // size scaling: the radial indices scaled by P/Q (Sec. 3.7), measured against the tool path scaled about the pole
  const double k = opt.size_scale.value();
  SizeScalingFact sz;
  sz.factor = k;
  sz.axes = "r";
  const CurvePtr scaled = scale_curve(d.path, k);
  PolarTrack strack;
  bool have_track = true;
  try {
    strack = PolarTrack::build(*scaled);
  } catch (const InputError& e) {
    have_track = false;
    sz.note = e.what();
  }
  PolarAreaMeter em;  // the area alone: the deviation of a scaled tape adds nothing the area does not show
  if (have_track) em.reset(strack, g);
  int64_t start[2];
  {
    TapeReader rd(tape.path());
    start[0] = rd.header().start[0];
    start[1] = rd.header().start[1];
  }
  NodeBox box(true, g.dr, g.dtheta, scaled_radial_index(start[0], opt.size_scale), start[1]);
  FanOut scaled_out(have_track ? std::vector<StepSink*>{&em, &box} : std::vector<StepSink*>{&box});
  ScaledAxisSink scaler(scaled_out, kAxisRadial, opt.size_scale, start[0]);
  StepRateMeter rates;
  FanOut all({&rates, &scaler});
  replay(tape.path(), all, start);
  for (int a = 0; a < 2; ++a) s.rates[a] = rates.axis(a);
  if (have_track) try {
      const AreaErrorResult sm = em.finish(scaled_radial_index(start[0], opt.size_scale), start[1]);
      sz.measured = true;
      sz.area_m2 = sm.area_m2;
    } catch (const InputError& e) {
      sz.note = e.what();  // the scaled staircase could not be measured against the scaled path
    }
  sz.size = box.size();
  s.size_scaling.push_back(sz);
}

// --------------------------------------------------------------------------------------- the Cartesian machine

void cartesian_side(const Job& job, const CompareOptions& opt, Comparison& c, const CartesianTrack& track,
                    const TempTape& tape, const Progress& progress) {
  MachineSide& s = c.cartesian;
  s.name = "cartesian";
  s.method = to_string(opt.method);
  s.axis[0] = "x";
  s.axis[1] = "y";
  const double blu = job.cartesian.resolution, hz = cartesian_interrupt_rate(job, opt.rate);
  c.interrupt_rate = hz;
  s.grid = "BLU = " + mm(blu) + " on x and y, origin at the contour pole";
  if (opt.method == CartesianMethod::dda)
    s.grid += "; lines and arcs within " + mm(job.cartesian.tolerance) + ", DDAs clocked at " + fmt(hz, 6) + " Hz";
  else
    s.grid += "; exact step times";

  CartesianRun run;
  {
    TapeHeader h = cartesian_tape_header(job, opt.method, hz);
    TapeWriter w(tape.path(), h);
    run = run_cartesian_job(job, opt.method, hz, &w);
    complete_cartesian_header(h, run.result);
    w.finish(h);
  }
  const CartesianResult& r = run.result;
  s.steps[0] = r.axis[0].steps();
  s.steps[1] = r.axis[1].steps();
  s.duration_s = r.duration_s;
  s.path_length_m = r.path_length_m;
  s.tape_bytes = std::filesystem::file_size(tape.path());

  report_progress(progress, 0.3);
  const CartesianTapeMetrics cm = cartesian_tape_metrics(job, tape.path(), progress_part(progress, 0.3, 0.8));
  s.area_m2 = cm.m.area.area_m2;
  s.deviation_m = cm.m.deviation_max_m;
  s.deviation_at = cm.m.deviation_at;
  s.resolution_worst_m = blu;
  s.resolution_where = "the BLU, the same everywhere";

  const double V = job.motion.nominal_speed();
  if (opt.figures) s.trace.emplace(600, s.duration_s);
  s.speed = measure_tape_speed(tape.path(), V, 1.0, opt.figures ? &*s.trace : nullptr);

  SpeedScalingFact& sp = s.speed_scaling;
  sp.factor = opt.speed_scale.value();
  if (opt.method == CartesianMethod::exact) {
    sp.without_reprocessing = true;
    sp.how = "the same tape played with every interval divided by " + to_string(opt.speed_scale);
    sp.speed = measure_tape_speed(tape.path(), sp.factor * V, sp.factor);
  } else {
    // the control interpolates in real time: a new speed is a new feed word in every block, computed again
    sp.without_reprocessing = false;
    sp.how = "the feed words of every block recomputed for " + to_string(opt.speed_scale) +
             " V and the program interpolated again";
    Job faster = job;
    faster.motion.speed = sp.factor * job.motion.speed;
    try {
      const CartesianRun again = run_cartesian_job_to_tape(faster, CartesianMethod::dda, hz, "");
      sp.speed = again.speed;
    } catch (const InputError& e) {
      sp.possible = false;
      sp.note = e.what();
      const std::string prefix = job.file + ": ";
      if (sp.note.rfind(prefix, 0) == 0) sp.note = sp.note.substr(prefix.size());
    }
  }

  // size scaling: x alone (one axis, as the polar machine does with r), and x and y together
  const Ratio q = opt.size_scale;
  const double k = q.value();
  int64_t start[2];
  {
    TapeReader rd(tape.path());
    start[0] = rd.header().start[0];
    start[1] = rd.header().start[1];
  }
  const int64_t sx = scaled_radial_index(start[0], q), sy = scaled_radial_index(start[1], q);
  NodeBox box_x(false, blu, blu, sx, start[1]);
  ScaledAxisSink only_x(box_x, kAxisX, q, start[0]);

  const CurvePtr scaled = scale_curve(run.path, k);
  CartesianTrack strack;
  std::string why_not;
  try {
    strack = CartesianTrack::build(*scaled);
  } catch (const InputError& e) {
    why_not = e.what();
  }
  CartesianAreaMeter em;
  if (why_not.empty()) em.reset(strack, blu);
  NodeBox box_xy(false, blu, blu, sx, sy);
  FanOut both_out(why_not.empty() ? std::vector<StepSink*>{&em, &box_xy} : std::vector<StepSink*>{&box_xy});
  ScaledAxisSink scale_y(both_out, kAxisY, q, start[1]);
  ScaledAxisSink scale_x(scale_y, kAxisX, q, start[0]);
  StepRateMeter rates;
  FanOut all({&rates, &only_x, &scale_x});
  replay(tape.path(), all, start);
  for (int a = 0; a < 2; ++a) s.rates[a] = rates.axis(a);

  const CartesianTrack::Bounds b = track.bounds();
  const Vec2 wanted{k * (b.x1 - b.x0), k * (b.y1 - b.y0)};
  SizeScalingFact one;
  one.factor = k;
  one.axes = "x";
  one.size = box_x.size();
  one.wanted = wanted;
  s.size_scaling.push_back(one);
  SizeScalingFact two;
  two.factor = k;
  two.axes = "x and y";
  two.size = box_xy.size();
  two.wanted = wanted;
  two.note = why_not;
  if (why_not.empty()) try {
      const CartesianAreaResult sm = em.finish(sx, sy);
      two.measured = true;
      two.area_m2 = sm.area_m2;
    } catch (const InputError& e) {
      two.note = e.what();
    }
  s.size_scaling.push_back(two);
  c.polar.size_scaling.front().wanted = wanted;  // translation does not change a bounding box
}

// What the report draws: the tool path, and both staircases near each machine's largest deviation.
void figure_data(const Job& job, Comparison& c, const Curve& path, double length, const TempTape& polar_tape,
                 const TempTape& cart_tape) {
  const double blu = job.cartesian.resolution;
  const double hw = std::max(15.0 * blu, 4.0 * c.polar.resolution_worst_m);
  c.windows[0] = {c.polar.deviation_at, hw, "at the polar machine's largest deviation"};
  c.windows[1] = {c.cartesian.deviation_at, hw, "at the Cartesian machine's largest deviation"};
  for (int wi = 0; wi < 2; ++wi) {
    int64_t st[2];
    {
      TapeReader rd(polar_tape.path());
      st[0] = rd.header().start[0], st[1] = rd.header().start[1];
    }
    WindowCollector wp(true, job.machine.grid.dr, job.machine.grid.dtheta, c.polar_pole, st, c.windows[wi]);
    replay(polar_tape.path(), wp, st);
    c.polar.detail[wi] = std::move(wp.runs);
    {
      TapeReader rd(cart_tape.path());
      st[0] = rd.header().start[0], st[1] = rd.header().start[1];
    }
    WindowCollector wq(false, blu, blu, Vec2{}, st, c.windows[wi]);
    replay(cart_tape.path(), wq, st);
    c.cartesian.detail[wi] = std::move(wq.runs);
    c.contour_in[wi] = curve_in_window(path, length, c.windows[wi]);
  }
  c.outline.clear();
  const int N = 4000;
  for (int i = 0; i <= N; ++i) c.outline.push_back(path.eval(path.u_begin() + (path.u_end() - path.u_begin()) * i / N, 0).p);
}

// ---------------------------------------------------------------------------------------------------- verdicts

// Which is smaller, with ties within `rel` of the larger or below `floor`.
std::string smaller(double p, double q, double rel, double floor) {
  const double d = std::abs(p - q);
  if (d <= rel * std::max(std::abs(p), std::abs(q)) || d <= floor) return "tie";
  return p < q ? "polar" : "cartesian";
}

std::string machine_name(const std::string& w, const Comparison& c) {
  if (w == "polar") return "the polar machine";
  return c.cartesian.method == "dda" ? "the Cartesian DDA machine" : "the Cartesian machine";
}

void add_verdicts(Comparison& c) {
  const MachineSide& P = c.polar;
  const MachineSide& Q = c.cartesian;
  const double V = c.nominal_speed;
  auto cap = [](std::string s) {
    if (!s.empty()) s[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(s[0])));
    return s;
  };
  auto pct = [&](double dv) { return polarcam::share(dv / V); };
  std::vector<AttributeVerdict>& out = c.verdicts;

  {  // Table 3.1: contouring speed
    AttributeVerdict v{"Contouring speed", "", "", "", ""};
    auto val = [&](const MachineSide& s) {
      return fmt(s.speed.min_mps * 1e3, 4) + " to " + fmt(s.speed.max_mps * 1e3, 4) + " mm/s, RMS deviation " +
             fmt(s.speed.rms_dev_mps * 1e3, 3) + " mm/s (" + pct(s.speed.rms_dev_mps) + " of " + fmt(V * 1e3, 4) + " mm/s)";
    };
    v.polar = val(P);
    v.cartesian = val(Q);
    v.winner = smaller(P.speed.rms_dev_mps, Q.speed.rms_dev_mps, 0.1, 1e-3 * V);
    if (v.winner == "tie")
      v.why = "Both hold the programmed " + mmps(V) + " equally well: their RMS deviations differ by less than 0.1 % "
              "of it, or by less than a tenth.";
    else {
      const MachineSide& w = v.winner == "polar" ? P : Q;
      const MachineSide& l = v.winner == "polar" ? Q : P;
      v.why = cap(machine_name(v.winner, c)) + " holds the speed steadier: its steps come at " +
              mmps(w.speed.min_mps) + " to " + mmps(w.speed.max_mps) + ", where " +
              machine_name(v.winner == "polar" ? "cartesian" : "polar", c) + "'s swing between " + mmps(l.speed.min_mps) +
              " and " + mmps(l.speed.max_mps) + ".";
    }
    out.push_back(v);
  }
  {
    AttributeVerdict v{"Contouring time", fixed(P.duration_s, 3) + " s", fixed(Q.duration_s, 3) + " s", "", ""};
    v.winner = smaller(P.duration_s, Q.duration_s, 0.01, 1e-3);
    const double ideal = c.path_length_m / V;
    if (v.winner == "tie")
      v.why = "The same to within 1 %: the path at " + mmps(V) + " takes " + fixed(ideal, 3) + " s.";
    else
      v.why = cap(machine_name(v.winner, c)) + " finishes " + fixed(std::abs(P.duration_s - Q.duration_s), 3) +
              " s sooner (the path at " + mmps(V) + " takes " + fixed(ideal, 3) + " s).";
    out.push_back(v);
  }
  {
    AttributeVerdict v{"Area error", fmt(P.area_m2 * 1e6, 4) + " mm²", fmt(Q.area_m2 * 1e6, 4) + " mm²", "", ""};
    v.winner = smaller(P.area_m2, Q.area_m2, 0.01, 0.0);
    if (v.winner == "tie")
      v.why = "Both machines' paths enclose the same area with the contour, to within 1 %.";
    else {
      const double a = std::min(P.area_m2, Q.area_m2), b = std::max(P.area_m2, Q.area_m2);
      v.why = cap(machine_name(v.winner, c)) + " follows the contour more closely on average: " +
              (a > 0 ? fmt(b / a, 3) + " times" : "far") + " less area between its path and the contour.";
    }
    out.push_back(v);
  }
  {
    AttributeVerdict v{"Largest deviation", mm(P.deviation_m), mm(Q.deviation_m), "", ""};
    v.winner = smaller(P.deviation_m, Q.deviation_m, 0.01, 0.0);
    if (v.winner == "tie")
      v.why = "Both stray at most " + mm(std::max(P.deviation_m, Q.deviation_m)) + " from the contour.";
    else {
      const MachineSide& l = v.winner == "polar" ? Q : P;
      v.why = "The worst point of " + machine_name(v.winner == "polar" ? "cartesian" : "polar", c) + " is " +
              mm(l.deviation_m) + " off the contour, at (" + fixed(l.deviation_at.x * 1e3, 2) + ", " +
              fixed(l.deviation_at.y * 1e3, 2) + ") mm; " + machine_name(v.winner, c) + " stays within " +
              mm(v.winner == "polar" ? P.deviation_m : Q.deviation_m) + ".";
    }
    out.push_back(v);
  }
  {  // Table 3.1: accuracy
    AttributeVerdict v{"Resolution at the worst point", mm(P.resolution_worst_m) + " (" + P.resolution_where + ")",
              mm(Q.resolution_worst_m) + " (" + Q.resolution_where + ")", "", ""};
    v.winner = smaller(P.resolution_worst_m, Q.resolution_worst_m, 0.01, 0.0);
    if (v.winner == "cartesian")
      v.why = "The polar machine's angular step grows with the radius: at the far end of this path one angular step "
              "moves the tool " + mm(P.resolution_worst_m) + ", against the Cartesian BLU of " + mm(Q.resolution_worst_m) + ".";
    else if (v.winner == "polar")
      v.why = "This path stays close enough to the pole that one angular step moves the tool less than the Cartesian BLU.";
    else
      v.why = "The same: one step of either machine moves the tool about " + mm(Q.resolution_worst_m) + ".";
    out.push_back(v);
  }
  {
    auto val = [&](const MachineSide& s) {
      const int a = s.rates[0].max_rate_hz >= s.rates[1].max_rate_hz ? 0 : 1;
      return fmt(s.max_step_rate_hz(), 5) + " Hz (" + s.axis[a] + ")";
    };
    AttributeVerdict v{"Highest step rate", val(P), val(Q), "", ""};
    v.winner = smaller(P.max_step_rate_hz(), Q.max_step_rate_hz(), 0.01, 1.0);
    if (v.winner == "tie")
      v.why = "The drives of both machines must step at about the same highest rate.";
    else
      v.why = cap(machine_name(v.winner, c)) + " asks less of its drives: its fastest axis steps at " +
              fmt(std::min(P.max_step_rate_hz(), Q.max_step_rate_hz()), 5) + " Hz against " +
              fmt(std::max(P.max_step_rate_hz(), Q.max_step_rate_hz()), 5) + " Hz.";
    out.push_back(v);
  }
  {
    AttributeVerdict v{"Tape size", cli::thousands(P.tape_bytes) + " bytes", cli::thousands(Q.tape_bytes) + " bytes", "", ""};
    v.winner = smaller(static_cast<double>(P.tape_bytes), static_cast<double>(Q.tape_bytes), 0.01, 0.0);
    v.why = v.winner == "tie" ? "About the same size."
                              : cap(machine_name(v.winner, c)) + "'s tape is smaller (" +
                                    fmt(static_cast<double>(std::max(P.tape_bytes, Q.tape_bytes)) /
                                            static_cast<double>(std::min(P.tape_bytes, Q.tape_bytes)), 3) +
                                    " times): it has fewer steps to store.";
    out.push_back(v);
  }
  {  // Table 3.1: contouring speed scaling
    auto val = [&](const MachineSide& s) {
      const SpeedScalingFact& f = s.speed_scaling;
      std::string t = f.without_reprocessing ? "yes: " : "no: ";
      t += f.how;
      if (!f.possible)
        t += "; not possible: " + f.note;
      else
        t += "; measured " + fmt(f.speed.mean_mps * 1e3, 4) + " mm/s mean, RMS deviation " + pct(f.speed.rms_dev_mps / f.factor) +
             " of " + fmt(f.factor * V * 1e3, 4) + " mm/s";
      return t;
    };
    AttributeVerdict v{"Speed scaling without reprocessing (x" + fmt(P.speed_scaling.factor, 4) + ")", val(P), val(Q), "", ""};
    const bool p = P.speed_scaling.without_reprocessing, q = Q.speed_scaling.without_reprocessing && Q.speed_scaling.possible;
    v.winner = p == q ? "tie" : (p ? "polar" : "cartesian");
    if (v.winner == "tie")
      v.why = "Both are pulse tapes with exact times: played faster, either runs at the scaled speed with nothing "
              "recomputed. The thesis's advantage here comes from the timed pulse tape, not from the polar axes.";
    else
      v.why = "The polar tape runs " + fmt(P.speed_scaling.factor, 4) +
              " times faster by playing it faster; the DDA control must recompute every block's feed word" +
              std::string(Q.speed_scaling.possible ? "." : ", and at this interrupt rate cannot run that fast at all.");
    out.push_back(v);
  }
  {  // Table 3.1: size scaling
    const SizeScalingFact& ps = P.size_scaling.front();
    const SizeScalingFact& q1 = Q.size_scaling[0];
    const SizeScalingFact& q2 = Q.size_scaling[1];
    auto box = [](Vec2 b) { return fixed(b.x * 1e3, 2) + " x " + fixed(b.y * 1e3, 2) + " mm"; };
    std::string pv = "yes: radial indices x" + fmt(ps.factor, 4) + " give " + box(ps.size) + " (wanted " + box(ps.wanted) + ")";
    if (ps.measured) pv += ", area error " + fmt(ps.area_m2 * 1e6, 4) + " mm² against the scaled contour";
    std::string qv = "no: x indices alone x" + fmt(q1.factor, 4) + " give " + box(q1.size) + "; x and y together give " +
                     box(q2.size);
    if (q2.measured) qv += ", area error " + fmt(q2.area_m2 * 1e6, 4) + " mm²";
    AttributeVerdict v{"Size scaling by one axis (x" + fmt(ps.factor, 4) + ")", pv, qv, "polar", ""};
    v.why = "Scaling the polar machine's radial axis alone scales the whole part about the pole; scaling one "
            "Cartesian axis only stretches it (" + box(q1.size) + " instead of " + box(q1.wanted) +
            "): both axes must be scaled.";
    out.push_back(v);
  }
}

}  // namespace

Comparison compare_job(const Job& job, const CompareOptions& opt, const Progress& progress) {
  if (opt.speed_scale.num <= 0 || opt.speed_scale.den <= 0 || opt.size_scale.num <= 0 || opt.size_scale.den <= 0)
    throw InputError("the scale factors must be above zero");
  if (job.machine.coupling != 0.0)  // the polar tape's radial axis would be the geared motor, not the radius
    throw InputError("the machine's radial motor is coupled to its arm (coupling): the comparison measures an "
                     "uncoupled polar machine; give a machine file without 'coupling'", job.file);
  if (job_lifts_tool(job))
    throw InputError("the machine lifts its tool between the drawing's " + std::to_string(job.parts.size()) +
                         " contours: the comparison measures one contour; compare each contour as a job of its own",
                     job.file);
  Comparison c;
  c.job_file = job.file;
  c.contour = job.contour->name();
  c.nominal_speed = job.motion.nominal_speed();
  const ToolPathPtr cpath = make_cartesian_job_path(job);
  const CartesianTrack track = in_file(job.file, [&] { return CartesianTrack::build(*cpath); });
  c.closed = cpath->closed();
  c.path_length_m = track.length();
  const TempTape polar_tape("polar"), cart_tape("cartesian");
  // progress: each machine's side (its tape, its meters, its scaling facts) is 45 %, the figures the rest
  polar_side(job, opt, c, polar_tape, progress_part(progress, 0.0, 0.45));
  report_progress(progress, 0.45);
  cartesian_side(job, opt, c, track, cart_tape, progress_part(progress, 0.45, 0.9));
  report_progress(progress, 0.9);
  if (opt.figures) figure_data(job, c, *cpath, track.length(), polar_tape, cart_tape);
  add_verdicts(c);
  report_progress(progress, 1.0);
  return c;
}

namespace {

nlohmann::ordered_json side_json(const MachineSide& s, const Comparison& c) {
  nlohmann::ordered_json j;
  j["machine"] = s.name;
  j["method"] = s.method;
  j["grid"] = s.grid;
  j["axes"] = {s.axis[0], s.axis[1]};
  const bool polar = s.name == "polar";
  j[polar ? "steps_radial" : "steps_x"] = s.steps[0];
  j[polar ? "steps_angular" : "steps_y"] = s.steps[1];
  j["steps_total"] = s.steps_total();
  j["duration_s"] = s.duration_s;
  j["path_length_m"] = s.path_length_m;
  j["speed_nominal_mps"] = c.nominal_speed;
  j["speed_min_mps"] = s.speed.min_mps;
  j["speed_max_mps"] = s.speed.max_mps;
  j["speed_mean_mps"] = s.speed.mean_mps;
  j["speed_rms_dev_mps"] = s.speed.rms_dev_mps;
  j["area_error_mm2"] = s.area_m2 * 1e6;
  j["deviation_max_mm"] = s.deviation_m * 1e3;
  j["deviation_at_mm"] = {s.deviation_at.x * 1e3, s.deviation_at.y * 1e3};
  j["max_step_rate_hz"] = s.max_step_rate_hz();
  for (int a = 0; a < 2; ++a) {
    const std::string n = polar ? (a == 0 ? "radial" : "angular") : s.axis[a];
    j["max_step_rate_" + n + "_hz"] = s.rates[a].max_rate_hz;
    j["reversals_" + n] = s.rates[a].reversals;
    j["min_reversal_interval_" + n + "_ns"] = s.rates[a].min_reversal_interval_ns;
  }
  j["tape_bytes"] = s.tape_bytes;
  j["resolution_worst_mm"] = s.resolution_worst_m * 1e3;
  j["resolution_worst_where"] = s.resolution_where;
  const SpeedScalingFact& sp = s.speed_scaling;
  nlohmann::ordered_json js;
  js["factor"] = sp.factor;
  js["without_reprocessing"] = sp.without_reprocessing;
  js["possible"] = sp.possible;
  js["how"] = sp.how;
  if (sp.possible) {
    js["speed_mean_mps"] = sp.speed.mean_mps;
    js["speed_min_mps"] = sp.speed.min_mps;
    js["speed_max_mps"] = sp.speed.max_mps;
    js["speed_rms_dev_mps"] = sp.speed.rms_dev_mps;
  } else {
    js["why_not"] = sp.note;
  }
  j["speed_scaling"] = js;
  nlohmann::ordered_json sz = nlohmann::ordered_json::array();
  for (const SizeScalingFact& f : s.size_scaling) {
    nlohmann::ordered_json x;
    x["factor"] = f.factor;
    x["axes_scaled"] = f.axes;
    x["size_mm"] = {f.size.x * 1e3, f.size.y * 1e3};
    x["wanted_mm"] = {f.wanted.x * 1e3, f.wanted.y * 1e3};
    if (f.measured) {
      x["area_error_mm2"] = f.area_m2 * 1e6;
    } else if (!f.note.empty()) {
      x["not_measured"] = f.note;
    }
    sz.push_back(x);
  }
  j["size_scaling"] = sz;
  return j;
}

}  // namespace

nlohmann::ordered_json to_json(const Comparison& c) {
  nlohmann::ordered_json j;
  j["job"] = c.job_file;
  j["contour"] = c.contour;
  j["closed"] = c.closed;
  j["path_length_m"] = c.path_length_m;
  j["speed_nominal_mps"] = c.nominal_speed;
  if (c.cartesian.method == "dda") j["interrupt_rate_hz"] = c.interrupt_rate;
  j["polar"] = side_json(c.polar, c);
  j["cartesian"] = side_json(c.cartesian, c);
  nlohmann::ordered_json v = nlohmann::ordered_json::array();
  for (const AttributeVerdict& x : c.verdicts) {
    nlohmann::ordered_json a;
    a["attribute"] = x.attribute;
    a["polar"] = x.polar;
    a["cartesian"] = x.cartesian;
    a["winner"] = x.winner;
    a["why"] = x.why;
    v.push_back(a);
  }
  j["verdicts"] = v;
  return j;
}

}  // namespace polarcam
