#pragma once
// Rendering the servo feed drives' contour error (machine/servo, docs/feed-drives.md): the JSON and text of
// `polarcam servo`, the series as CSV, the figure of the path and of the contour error. Nothing here computes a
// number of the analysis.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "machine/servo/contour.hpp"
#include "report/plot.hpp"

namespace polarcam {

struct ServoAnalysis {
  std::string input;        // what was run: "path diamond", "tape FILE", "job FILE"
  std::string drives_file;
  servo::Drives drives;
  servo::ContourResult result;
  std::vector<servo::CornerSpline> corners;  // a test path's blended corners (--corner)
  // the reference is a tape's staircase of steps (a tape, or a job digitized): its length, and the s of the
  // contour error, are along the steps, longer than the contour they follow
  bool staircase = false;
};

// One JSON object: input, drives, axes (following error at steady speed, its speed and stretch, the largest
// current), the contour error (largest and where, at steady speed), the tolerance and the intervals out of it.
nlohmann::ordered_json servo_json(const ServoAnalysis& a);
std::string servo_text(const ServoAnalysis& a);
// t_s, reference and actual positions of both axes (mm, or rad for theta), the tool point's contour error (mm).
std::string servo_csv(const ServoAnalysis& a);
// Two panels: the reference and actual tool paths (mm, the actual's deviation from the path magnified so that
// the largest is 1/20 of the drawing), and the contour error against time with the tolerance band.
plot::Figure servo_figure(const ServoAnalysis& a);
// `polarcam servo --report-model`: each axis's velocity loop, filter, discrete model, following error per speed,
// yield per cutting torque and current-sensor bandwidth (servo::model_report).
nlohmann::ordered_json servo_model_json(const servo::Drives& d, const servo::ModelReport r[2]);
std::string servo_model_text(const servo::Drives& d, const servo::ModelReport r[2]);

}  // namespace polarcam
