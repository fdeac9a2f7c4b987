// The "Cutting" section for the constant-force example: its heading, the largest forces against the tool's limits
// as `process` computes them, the schedule's stretches, the figure.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <string>

#include "job/job.hpp"
#include "pipeline/job_process.hpp"
#include "report/cutting_report.hpp"

namespace tu_report_test_cutting_report {  // the test files of a program compile together (unity build)

using namespace polarcam;

TEST(CuttingReport, TheExamplesSection) {
  const Job job = load_job(std::string(POLARCAM_SOURCE_DIR) + "/examples/process/contour_milling.toml");
  const ProcessRun r = run_process(job);
  html::Report rep("milling");
  add_cutting_section(rep, job, r);
  const std::string s = rep.str();
  EXPECT_NE(s.find("id=\"cutting\""), std::string::npos);
  EXPECT_NE(s.find(fmt::format("{:.4g} N", r.max_peak_force_N)), std::string::npos);
  EXPECT_NE(s.find(fmt::format("{:.4g} N", *job.milling->limits.deflection_force_limit_N)), std::string::npos);
  EXPECT_NE(s.find("<td>the nominal force</td>"), std::string::npos);  // in words, not the JSON's identifier
  EXPECT_NE(s.find("<td>the planned entry</td>"), std::string::npos);
  EXPECT_EQ(s.find("nominal_force"), std::string::npos);
  EXPECT_EQ(s.find("EXCEEDED"), std::string::npos);
  EXPECT_NE(s.find("<img"), std::string::npos);
}

}  // namespace tu_report_test_cutting_report
