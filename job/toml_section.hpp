#pragma once
// Reading one table of a TOML job or machine file with every key accounted for: getters mark keys as used,
// quantities are parsed with their units, and finish() reports the first key nobody asked for. Every error
// names the file, the line and the key. Only the job-parsing translation units include this (toml++ is big).
#include <toml++/toml.h>

#include <optional>
#include <set>
#include <string>
#include <vector>

#include "cam/units.hpp"
#include "cam/vec2.hpp"

namespace polarcam::jobfile {

class Section {
 public:
  // `table` may be null (the section is absent). `fallback` is an optional table of lower priority (a machine
  // file under a job's [machine]); its keys are looked up when the primary table lacks them.
  Section(const toml::table* table, std::string file, std::string name, const Section* fallback = nullptr);

  bool present() const { return t_ != nullptr || (fb_ && fb_->present()); }
  bool has(const std::string& key) const;
  const std::string& name() const { return name_; }
  const std::string& file() const { return file_; }

  std::optional<double> quantity(const std::string& key, const Dim& d);
  double quantity(const std::string& key, const Dim& d, double default_value);
  double require_quantity(const std::string& key, const Dim& d);
  std::optional<std::string> string(const std::string& key);
  std::string require_string(const std::string& key);
  std::optional<double> number(const std::string& key);   // plain number (integer or float)
  std::optional<int64_t> integer(const std::string& key);
  std::optional<bool> boolean(const std::string& key);
  // ["x", "y"] quantities of length
  std::optional<Vec2> point(const std::string& key);
  Vec2 require_point(const std::string& key);
  // raw access for arrays and subtables (marks the key used)
  const toml::node* node(const std::string& key);
  Section subsection(const std::string& key);

  // Throws for unknown keys (in this table and its fallback).
  void finish() const;

  // "FILE:LINE: key 'section.key'" for messages about a key
  std::string where(const std::string& key) const;
  [[noreturn]] void fail(const std::string& key, const std::string& what) const;
  [[noreturn]] void fail_section(const std::string& what) const;

 private:
  const toml::node* find(const std::string& key, const Section** owner) const;
  double parse_q(const toml::node& n, const std::string& key, const Dim& d) const;
  // The value of `key` when it is exactly a T (fails with `expected` otherwise); nullopt when it is absent.
  template <class T>
  std::optional<T> exact(const std::string& key, const char* expected);

  const toml::table* t_;
  std::string file_, name_;
  const Section* fb_;
  mutable std::set<std::string> used_;
};

// Parses a TOML file; throws InputError "FILE:LINE:COL: message" on syntax errors or an unreadable file.
toml::table parse_toml_file(const std::string& path);

}  // namespace polarcam::jobfile
