#pragma once
// One table of a TOML input file (a chatter structure, a simulation, a servo drives file) read key by key: numbers
// in SI units or quantity strings with units (cam/units.hpp), strings, whole numbers. Every error is one line
// naming FILE:LINE and the key (`table.key`) and what to give; finish() refuses every key that was not read.
// Header only: the libraries that include it link toml++ themselves (cam/ does not).
#include <toml++/toml.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <set>
#include <string>

#include "cam/error.hpp"
#include "cam/units.hpp"

namespace polarcam {

// "FILE:LINE" of a node, or FILE when toml++ kept no line.
inline std::string toml_line_of(const std::string& file, const toml::node& n) {
  return n.source().begin.line ? file + ":" + std::to_string(n.source().begin.line) : file;
}

struct TomlTable {
  const toml::table* t;  // null: the table is absent (every key reads as missing)
  std::string file, name;
  std::set<std::string> used;
  // Rewrites a quantity's text before it is parsed (the drives file reads "count" as a pure number); null: as is.
  std::string (*rewrite)(const std::string&) = nullptr;

  std::string where(const std::string& key) const {
    const toml::node* n = t ? t->get(key) : nullptr;
    return (n ? toml_line_of(file, *n) : file) + ": key '" + name + "." + key + "'";
  }
  std::optional<double> get(const std::string& key, const Dim& d) {
    const toml::node* n = t ? t->get(key) : nullptr;
    if (!n) return std::nullopt;
    used.insert(key);
    double v = 0.0;
    if (n->is_integer()) {
      v = static_cast<double>(*n->value<int64_t>());
    } else if (n->is_floating_point()) {
      v = *n->value<double>();
    } else if (auto s = n->value<std::string>()) {
      try {
        v = parse_quantity_as(rewrite ? rewrite(*s) : *s, d);
      } catch (const InputError& e) {
        throw InputError(e.message() + " (expected " + describe(d) + ")", where(key));
      }
    } else {
      throw InputError("must be a number in SI units or a quantity with units (\"0.2 s\")", where(key));
    }
    if (!std::isfinite(v)) throw InputError("must be a finite number", where(key));
    return v;
  }
  double require(const std::string& key, const Dim& d, const char* what) {
    if (auto v = get(key, d)) return *v;
    throw InputError(std::string("missing: give ") + what, file + ": key '" + name + "." + key + "'");
  }
  void set(const std::string& key, const Dim& d, double& out) {
    if (auto v = get(key, d)) out = *v;
  }
  std::optional<std::string> text(const std::string& key) {
    const toml::node* n = t ? t->get(key) : nullptr;
    if (!n) return std::nullopt;
    used.insert(key);
    if (auto s = n->value<std::string>()) return *s;
    throw InputError("must be a string", where(key));
  }
  std::optional<int> integer(const std::string& key) {
    const toml::node* n = t ? t->get(key) : nullptr;
    if (!n) return std::nullopt;
    used.insert(key);
    if (n->is_integer()) {
      const int64_t v = *n->value<int64_t>();
      if (v >= -1000000 && v <= 1000000) return static_cast<int>(v);
    }
    throw InputError("must be a whole number", where(key));
  }
  void finish() const {
    if (!t) return;
    for (const auto& [k, v] : *t)
      if (!used.count(std::string(k.str())))
        throw InputError("unknown key '" + name + "." + std::string(k.str()) + "'", toml_line_of(file, v));
  }
};

}  // namespace polarcam
