#include "pipeline/job_study.hpp"

#include "pipeline/job_tape.hpp"
#include "cam/error.hpp"
#include "pipeline/job_placement.hpp"

namespace polarcam {
namespace {

// Both a step sink for the error meters and a log of the steps (for the magnified staircase).
class Tee final : public StepSink {
 public:
  Tee(ErrorMeters& m, std::vector<uint8_t>& log) : m_(m), log_(log) {}
  void step(int axis, int dir, int64_t t) override {
    m_.step(axis, dir, t);
    log_.push_back(static_cast<uint8_t>(axis | (dir > 0 ? 2 : 0)));
  }

 private:
  ErrorMeters& m_;
  std::vector<uint8_t>& log_;
};

}  // namespace

ChatterStudy study_chatter(const process::ChatterProblem& p, int lobe_count) {
  ChatterStudy c;
  c.problem = p;
  const process::TransferFunction g = process::workpiece_compliance(p.structure);
  c.modes = process::modes(g);
  c.nyquist = process::nyquist_limit(g, p.cut.overlap, p.cut.revolution_period);
  c.simple = process::simple_criterion(g, p.cut.overlap);
  const process::SpeedRange range = process::default_lobe_range(p.cut);
  c.lobes = process::stability_lobes(g, p.cut.overlap, range.n_min, range.n_max, lobe_count);
  return c;
}

JobStudy study_job(const Job& job, const StudyOptions& o, const Progress& progress) {
  JobStudy st;
  const int threads = o.threads > 0 ? o.threads : default_threads();

  if (job_lifts_tool(job))
    throw InputError("the machine lifts its tool between the drawing's " + std::to_string(job.parts.size()) +
                         " contours: the operator's report studies one contour; report on each contour as a job of "
                         "its own",
                     job.file);
  // --- the dynamics at the job's placement first: a time-optimal job's tape follows its schedule
  const PreparedDynamics prep = prepare_dynamics(job);
  st.side = prep.side;
  AnalysisOptions ao;
  st.dyn = analyze_case(job, prep, DynamicsCase{std::nullopt, job.load}, ao, true);
  st.limit = st.dyn.verdict.limit;

  // --- both schedules: the time-optimal one and the best constant speed (a time-optimal job's came with its case)
  try {
    ScheduleStudy ss;
    ss.plan = st.dyn.plan ? *st.dyn.plan : plan_speed(job, prep, job.load, ao);
    if (ss.plan.constant_speed) {
      DynamicsSetup cs;
      cs.machine = &*job.machine.dynamics;
      cs.load = make_load(job.load);
      cs.motion.speed = *ss.plan.constant_speed;
      cs.safety_factor = job.safety_factor;
      try {
        ss.constant = analyze_motion(placed_path(prep), cs, ao);
      } catch (const InputError& e) {
        throw e.in_file(job.file);
      }
    }
    st.schedules = std::move(ss);
  } catch (const InputError& e) {
    if (job.motion.time_optimal) throw;  // its verdict needs the schedule: analyze_case has refused it already
    st.schedules_note = e.what();
  }
  // a time-optimal job's capacity, area error and pole study at one constant speed: the best one that passes
  Job cjob = job;
  if (job.motion.time_optimal) {
    cjob.motion.time_optimal = false;
    if (st.schedules && st.schedules->plan.constant_speed) cjob.motion.speed = *st.schedules->plan.constant_speed;
    st.study_speed = cjob.motion.speed;
  }

  // --- the tape: digitize once, with the error meters and a log of the steps
  st.path = make_job_path(job);
  try {
    const PolarTrack track = job_polar_track(job, *st.path);
    const SpeedProfilePtr prof =
        st.dyn.plan ? st.dyn.plan->schedule.profile : make_job_profile(job, *st.path, track.length());
    ErrorMeters meters;
    meters.reset(*st.path, track, job.machine.grid, job.optimize.segments);
    meters.set_parallel(threads > 1);
    Tee tee(meters, st.staircase.steps);
    const Progress tape_part = progress_part(progress, 0.0, 0.1);
    ProgressSink counted(&tee, tape_part, prof->total_time());
    st.dig = digitize(track, job.machine.grid, job.motion.rule, *prof, progress ? static_cast<StepSink*>(&counted) : &tee);
    st.staircase.n0 = st.dig.start_n;
    st.staircase.m0 = st.dig.start_m;
    st.err = meters.finish(st.dig.start_n, st.dig.start_m);
  } catch (const InputError& e) {
    throw e.in_file(job.file);
  }

  // --- the capacity at the job's placement
  st.cap = job_capacity(cjob, prep, std::nullopt,
                        load_measure(job.load) == LoadMeasure::none ? 0 : o.curve_points);
  report_progress(progress, 0.2);

  // --- the pole study: survey, balanced optimum, least area within the torque limit
  PlacementOptions po = job.optimize;
  po.objective = PoleObjective::area;
  po.pareto = false;
  po.torque_limit = false;
  po.threads = threads;
  if (o.max_evaluations > 0) po.max_evaluations = o.max_evaluations;
  const PoleProblem prob = job_pole_problem(cjob, po, true);
  try {
    // the feasible box of the area searches (the work area alone): the survey's, and the torque-limited search's
    const SearchBox box = feasible_box(prob, search_box(prob), 41, threads);
    st.survey = survey_poles(prob, box, o.map_size, o.map_size, threads, progress_part(progress, 0.2, 0.6));
    st.cands.push_back({"this job", job.placement, job_area(cjob, job.placement),
                        job.motion.time_optimal ? job_dynamics_at(cjob, job.placement) : st.dyn});
    {
      PoleProblem pb = prob;
      pb.objective = PoleObjective::balanced;
      PlacementOptions ob = po;
      ob.objective = PoleObjective::balanced;
      // local, from the survey's three best separated poles of the balanced objective: the survey has mapped its
      // basins (the search from the whole box is `optimize --objective balanced`'s)
      if (po.hold == PoleHold::none)
        ob.local_starts = starts_from(
            survey_points(st.survey), [](const ParetoPoint& x) { return std::isfinite(x.v.torque.balanced); },
            [](const ParetoPoint& x) { return x.v.torque.balanced; }, start_spacing(st.survey), 3);
      if (!ob.local_starts.empty()) {
        ob.box = box;
        if (o.max_evaluations <= 0) ob.max_evaluations = 300;
      }
      const PlacementResult r = optimize_placement(pb, cjob.placement, ob, progress_part(progress, 0.6, 0.78));
      st.cands.push_back({"balanced torque", r.placement, job_area(cjob, r.placement), job_dynamics_at(cjob, r.placement)});
    }
    {
      PoleProblem pl = prob;
      pl.torque_limit = st.limit;
      PlacementOptions ol = po;
      ol.box = box;
      try {
        const PlacementResult r = optimize_placement(pl, job.placement, ol, progress_part(progress, 0.78, 0.96));
        st.limited = r.placement;
        st.cands.push_back({"least area error within the torque limit", r.placement, job_area(cjob, r.placement),
                            job_dynamics_at(cjob, r.placement)});
      } catch (const InputError& e) {
        st.limited_note = e.what();
      }
    }
  } catch (const InputError& e) {
    throw e.in_file(job.file);
  }
  // the front: the survey's non-dominated poles and the candidates
  std::vector<ParetoPoint> pts;
  for (int iy = 0; iy < st.survey.ny; ++iy)
    for (int ix = 0; ix < st.survey.nx; ++ix)
      pts.push_back({st.survey.pole(ix, iy), {}, st.survey.cells[static_cast<size_t>(iy) * st.survey.nx + ix], "survey"});
  std::vector<Vec2> cpoles;
  for (const Candidate& c : st.cands) cpoles.push_back(c.placement.pole());
  const std::vector<PoleValue> cvals = evaluate_poles(prob, cpoles, threads, progress_part(progress, 0.96, 1.0));
  for (size_t i = 0; i < st.cands.size(); ++i) {
    st.cpts.push_back({cpoles[i], st.cands[i].placement, cvals[i], st.cands[i].name});
    pts.push_back(st.cpts.back());
  }
  st.front = non_dominated(pts);

  if (job.chatter) st.chatter = study_chatter(*job.chatter);
  if (job.milling) st.cutting = run_process(job);

  Job at0 = cjob;
  at0.placement = Placement{0.0, 0.0};
  st.contour = segment_points(*make_job_path(at0), 1500);
  return st;
}

}  // namespace polarcam
