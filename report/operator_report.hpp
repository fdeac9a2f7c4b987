#pragma once
// The operator's report (`polarcam report JOB.toml -o report.html`, docs/operator-report.md): one self-contained
// HTML page to read before running a job. Sections (with these element ids): verdict, job, workarea, tape,
// accuracy, torque, speed (both schedules: time-optimal and the best constant speed), capacity, pole, tradeoff,
// glossary. Rendering only: every number comes from the job study (pipeline/job_study: digitize, the error meters,
// analyze, the time-optimal schedule, capacity, the pole searches).
#include <string>

#include "job/job.hpp"
#include "pipeline/job_study.hpp"

namespace polarcam::cli {

struct OperatorReport {
  std::string html;
  bool go = false;  // the job's verdict
};

OperatorReport operator_report(const Job& job, const JobStudy& study);

}  // namespace polarcam::cli
