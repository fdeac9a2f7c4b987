#include "report/html.hpp"

#include "cam/format.hpp"
#include "io/output.hpp"

namespace polarcam::html {

std::string escape(std::string_view s) { return xml_escape(s); }

std::string base64(std::string_view in) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string o;
  o.reserve((in.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    unsigned v = (static_cast<unsigned char>(in[i]) << 16) | (static_cast<unsigned char>(in[i + 1]) << 8) |
                 static_cast<unsigned char>(in[i + 2]);
    o += t[(v >> 18) & 63];
    o += t[(v >> 12) & 63];
    o += t[(v >> 6) & 63];
    o += t[v & 63];
  }
  if (i < in.size()) {
    unsigned v = static_cast<unsigned char>(in[i]) << 16;
    if (i + 1 < in.size()) v |= static_cast<unsigned char>(in[i + 1]) << 8;
    o += t[(v >> 18) & 63];
    o += t[(v >> 12) & 63];
    o += i + 1 < in.size() ? t[(v >> 6) & 63] : '=';
    o += '=';
  }
  return o;
}

Report::Report(std::string title) : title_(std::move(title)) {}

void Report::heading(int level, const std::string& text, const std::string& id) {
  std::string h = "h" + std::to_string(level < 1 ? 1 : (level > 4 ? 4 : level));
  body_ += "<" + h;
  if (!id.empty()) body_ += " id=\"" + escape(id) + "\"";
  body_ += ">" + escape(text) + "</" + h + ">\n";
}

void Report::paragraph(const std::string& text) { body_ += "<p>" + escape(text) + "</p>\n"; }

void Report::raw(const std::string& html) { body_ += html; }

void Report::table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows,
                   const std::string& caption) {
  body_ += "<table>\n";
  if (!caption.empty()) body_ += "<caption>" + escape(caption) + "</caption>\n";
  body_ += "<thead><tr>";
  for (const auto& h : header) body_ += "<th>" + escape(h) + "</th>";
  body_ += "</tr></thead>\n<tbody>\n";
  for (const auto& r : rows) {
    body_ += "<tr>";
    for (const auto& c : r) body_ += "<td>" + escape(c) + "</td>";
    body_ += "</tr>\n";
  }
  body_ += "</tbody></table>\n";
}

void Report::figure(const plot::Figure& f, const std::string& caption, const std::string& alt) {
  body_ += "<figure><img alt=\"" + escape(alt) + "\" width=\"" + std::to_string(f.width) + "\" src=\"data:image/png;base64," +
           base64(plot::render(f, "png")) + "\"><figcaption>" + escape(caption) + "</figcaption></figure>\n";
}

void Report::verdict(bool ok, const std::string& headline, const std::string& detail) {
  body_ += std::string("<div class=\"verdict ") + (ok ? "go" : "nogo") + "\"><strong>" + escape(headline) +
           "</strong><br>" + escape(detail) + "</div>\n";
}

std::string Report::str() const {
  return "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" + escape(title_) +
         "</title>\n<style>\n"
         "body{font-family:system-ui,-apple-system,'Segoe UI',Roboto,sans-serif;max-width:1100px;margin:2em auto;"
         "padding:0 1em;color:#1b1b1b;line-height:1.45}\n"
         "h1{font-size:1.6em;border-bottom:2px solid #333}h2{font-size:1.25em;margin-top:1.6em;border-bottom:1px solid #bbb}\n"
         "table{border-collapse:collapse;margin:.8em 0}th,td{border:1px solid #bbb;padding:.25em .6em;text-align:left}"
         "th{background:#eee}caption{text-align:left;font-weight:600;padding:.3em 0}\n"
         "figure{margin:1em 0}img{max-width:100%;height:auto;border:1px solid #ddd}figcaption{font-size:.9em;color:#444}\n"
         ".verdict{padding:.8em 1em;margin:1em 0;border-radius:4px;font-size:1.1em}.go{background:#dff3e3;border:2px solid #1e7b34}"
         ".nogo{background:#fbe3e1;border:2px solid #b3261e}\n"
         "@media print{body{margin:0;max-width:none}figure,table,.verdict{page-break-inside:avoid}h2{page-break-after:avoid}}\n"
         "</style>\n</head>\n<body>\n<h1>" +
         escape(title_) + "</h1>\n" + body_ + "</body>\n</html>\n";
}

void Report::save(const std::string& path) const { cli::write_file_atomic(path, str()); }

}  // namespace polarcam::html
