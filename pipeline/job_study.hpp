#pragma once
// Everything the operator's report shows about a job, computed once by the production pipeline: the tape (digitized
// with the error meters and a log of its steps), the dynamics and the verdict at the job's placement, the capacity,
// and the pole study (survey, balanced-torque optimum, least area error within the torque limit, the Pareto
// front). report/operator_report renders it; nothing here formats text.
#include "io/progress.hpp"
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "digitizer/digitize.hpp"
#include "job/job.hpp"
#include "metrics/error_metrics.hpp"
#include "optimize/pareto.hpp"
#include "pipeline/job_analysis.hpp"
#include "pipeline/job_capacity.hpp"
#include "pipeline/job_process.hpp"
#include "process/stability.hpp"

namespace polarcam {

struct StudyOptions {
  int map_size = 31;        // poles per side of the pole survey
  int max_evaluations = 0;  // budget of each pole search (0: their defaults)
  int curve_points = 12;    // speeds on the capacity curve
  int threads = 0;          // 0: all cores; the results do not depend on it
};

// The tape's nodes as the machine visits them (start node, then one per step).
struct Staircase {
  int64_t n0 = 0, m0 = 0;      // start node
  std::vector<uint8_t> steps;  // axis | (dir > 0 ? 2 : 0) per step
};

// A placement the study compares.
struct Candidate {
  std::string name;
  Placement placement;
  double area = -1.0;  // m^2 (negative: not measured)
  std::optional<CaseResult> dyn;
};

// The two schedules of a job with dynamics (docs/time-optimal.md): the time-optimal one and the best constant speed at
// the job's safety factor, each analysed along the path (their series are what the report plots).
struct ScheduleStudy {
  SpeedPlan plan;                          // the schedule (plan.schedule.check holds its series), the constant speed
  std::optional<TorqueAnalysis> constant;  // the torques at plan.constant_speed (none when no constant speed passes)
};

// The job's chatter structure ([process] chatter, docs/chatter.md): the limits `polarcam chatter` computes and the
// stability lobes over its default spindle speeds (half to twice the cut's).
struct ChatterStudy {
  process::ChatterProblem problem;
  std::vector<process::Mode> modes;
  process::NyquistLimit nyquist;
  process::SimpleLimit simple;
  std::vector<process::LobePoint> lobes;
};
// The same for any structure; `lobe_count` spindle speeds.
ChatterStudy study_chatter(const process::ChatterProblem& p, int lobe_count = 400);

struct JobStudy {
  ToolPathPtr path;              // the tool-centre path in the machine frame
  std::vector<Vec2> contour;     // the tool path in the contour's own frame (placement C = 0), for the pole map
  DigitizeResult dig;            // the tape's summary
  Staircase staircase;           // the tape's steps
  ErrorMetrics err;              // area error, deviation, F1 of the tape
  int side = 1;                  // tool centre left (+1) or right (-1) of the travel
  CaseResult dyn;                // the dynamics and verdict at the job's placement
  JobCapacity cap;               // largest speed and load at the job's placement
  double limit = 1.0;            // the torque-ratio limit, 1 / safety factor
  PoleSurvey survey;             // area error and torque ratios over pole positions
  std::vector<Candidate> cands;  // this job, balanced torque, [least area within the limit]
  std::optional<Placement> limited;  // the least-area placement within the torque limit, when one exists
  std::string limited_note;          // why there is none
  std::vector<ParetoPoint> cpts;     // the candidates as points of the trade-off
  std::vector<ParetoPoint> front;    // the non-dominated survey poles and candidates
  std::optional<ScheduleStudy> schedules;  // both schedules (none when the planner refused the job: schedules_note)
  std::string schedules_note;
  // A time-optimal job: the constant speed at which the capacity and the pole study were computed (the best constant
  // speed at the job's safety factor, or the job's top speed when none passes); their placements are compared at it.
  std::optional<double> study_speed;
  std::optional<ChatterStudy> chatter;  // a job with [process] chatter
  std::optional<ProcessRun> cutting;    // a job with a milling load: the cut along the path (pipeline/job_process)
};

// Throws InputError naming the job file.
// `progress`: the share done (the tape, the dynamics and capacity, the survey, the two searches, in that order).
JobStudy study_job(const Job& job, const StudyOptions& o, const Progress& progress = {});

}  // namespace polarcam
