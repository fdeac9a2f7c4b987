// Exports of a job (pipeline/job_export): a theta-rho pattern drawn about the machine pole keeps its own vertices;
// the [gcode] table read from the machine file.
#include <gtest/gtest.h>

#include <sstream>

#include "cam/thr_file.hpp"
#include "job/job.hpp"
#include "pipeline/job_export.hpp"

namespace tu_pipeline_test_job_export {  // the test files of a program compile together (unity build)

using namespace polarcam;

namespace {

const std::string kJob = std::string(POLARCAM_SOURCE_DIR) + "/tests/data/cli/sand_limacon.toml";

}  // namespace

TEST(JobExport, MachineFileGcodeTable) {
  const Job job = load_job(kJob);
  ASSERT_TRUE(job.machine.gcode.has_value());
  const GcodeSpec& g = *job.machine.gcode;
  EXPECT_EQ(g.theta_axis, "X");
  EXPECT_EQ(g.rho_axis, "Y");
  EXPECT_EQ(g.rho_units_per_radius, 200.0);
  EXPECT_EQ(g.coupling, 2.0);
  EXPECT_EQ(g.theta_max_feed, 120.0);
  EXPECT_EQ(g.rho_max_feed, 3000.0);
  EXPECT_EQ(g.axis_feed, 200.0);
  EXPECT_DOUBLE_EQ(g.table_radius, 0.2);  // r_max, as no table_radius is given
  EXPECT_EQ(g.feed_mode, FeedMode::inverse_time);
}

TEST(JobExport, ThetaRhoPatternKeepsItsVertices) {
  // the job's contour replaced by a pattern about the machine pole, as a pattern file becomes a job
  Job job = load_job(kJob);
  const std::vector<ThetaRho> v{{0.0, 0.0}, {3.0, 0.05}, {9.5, 0.19}, {9.5, 0.02}, {1.0, 0.1}};
  job.contour = make_theta_rho_path(v, "pattern");
  job.placement = {};
  ExportOptions o;
  o.format = ExportFormat::thr;
  const ExportResult r = export_job(job, o);
  std::istringstream in(r.content);
  const ThrPattern p = parse_thr(in, "export");
  ASSERT_EQ(p.vertices.size(), v.size());
  for (size_t k = 0; k < v.size(); ++k) {
    EXPECT_EQ(p.vertices[k].theta, v[k].theta);
    EXPECT_DOUBLE_EQ(p.vertices[k].rho, v[k].rho / 0.2);
  }
  // moved off the pole it is a path like any other: approximated, more vertices
  job.placement.C = 0.005;
  EXPECT_GT(export_job(job, o).vertices, v.size());
}

}  // namespace tu_pipeline_test_job_export
