#include "job/pattern.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "cam/error.hpp"

namespace polarcam {

bool is_pattern_file(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".thr" || ext == ".svg" || ext == ".dxf" || ext == ".csv";
}

Job load_job_or_pattern(const std::string& path, const PatternOptions& o) {
  if (is_pattern_file(path)) throw InputError("pattern files are not read yet", path);
  if (!o.machine_file.empty()) throw InputError("--machine applies to pattern files; a job names its machine in [machine]", "--machine");
  Job job = load_job(path);
  if (o.speed) {
    if (!(*o.speed > 0.0)) throw InputError("must be a positive speed", "--speed");
    job.motion.speed = *o.speed;
    job.motion.table.clear();
    job.provenance["motion"]["speed_mps"] = *o.speed;
  }
  return job;
}

}  // namespace polarcam
