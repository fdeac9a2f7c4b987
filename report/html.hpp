#pragma once
// Self-contained HTML reports: one file, images inline (PNG data URIs), no scripts, no network, a print
// stylesheet. Used by the operator report and the comparison report.
#include <string>
#include <string_view>
#include <vector>

#include "report/plot.hpp"

namespace polarcam::html {

std::string escape(std::string_view s);
std::string base64(std::string_view bytes);

class Report {
 public:
  explicit Report(std::string title);
  void heading(int level, const std::string& text, const std::string& id = "");
  void paragraph(const std::string& text);                 // escaped
  void raw(const std::string& html);                       // trusted markup
  void table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows,
             const std::string& caption = "");
  void figure(const plot::Figure& f, const std::string& caption, const std::string& alt);
  // A banner: ok = green GO, otherwise red NO-GO.
  void verdict(bool ok, const std::string& headline, const std::string& detail);
  std::string str() const;
  void save(const std::string& path) const;  // all or nothing

 private:
  std::string title_, body_;
};

}  // namespace polarcam::html
