#include "job/job_write.hpp"

#include <cstdio>
#include <filesystem>
#include <sstream>

#include "job/toml_section.hpp"

namespace polarcam {
namespace {

std::string exact(double v, const char* unit) {
  char b[64];
  std::snprintf(b, sizeof b, "%.17g %s", v, unit);
  return b;
}

// A file name in `t[key]` written relative to `from_dir`, made relative to `to_dir`.
void rebase(toml::table* t, const char* key, const std::filesystem::path& from_dir, const std::filesystem::path& to_dir) {
  if (!t) return;
  auto v = t->get(key) ? t->get(key)->value<std::string>() : std::nullopt;
  if (!v) return;
  std::filesystem::path p(*v);
  if (p.is_absolute()) return;
  const std::filesystem::path abs = std::filesystem::absolute(from_dir / p).lexically_normal();
  std::filesystem::path rel = abs.lexically_proximate(std::filesystem::absolute(to_dir).lexically_normal());
  t->insert_or_assign(key, rel.generic_string());
}

// The directory a file name is in: "." for a plain name (whose parent path is empty).
std::filesystem::path directory_of(const std::string& file) {
  const std::filesystem::path d = std::filesystem::path(file).parent_path();
  return d.empty() ? std::filesystem::path(".") : d;
}

}  // namespace

std::string job_with_placement(const std::string& job_path, const Placement& pl, const std::string& out_path,
                               const std::string& note) {
  toml::table root = jobfile::parse_toml_file(job_path);
  const std::filesystem::path from = directory_of(job_path);
  const std::filesystem::path to = directory_of(out_path);
  if (toml::table* m = root["machine"].as_table()) rebase(m, "file", from, to);
  if (toml::table* c = root["contour"].as_table()) rebase(c, "file", from, to);
  toml::table placement;
  placement.insert("C", exact(pl.C, "m"));
  placement.insert("beta", exact(pl.beta, "rad"));
  root.insert_or_assign("placement", std::move(placement));
  std::ostringstream os;
  os << "# " << note << "\n" << root << "\n";
  return os.str();
}

}  // namespace polarcam
