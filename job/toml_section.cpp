#include "job/toml_section.hpp"

#include <cmath>
#include <fstream>

#include "cam/error.hpp"
#include "cam/input_file.hpp"

namespace polarcam::jobfile {

Section::Section(const toml::table* table, std::string file, std::string name, const Section* fallback)
    : t_(table), file_(std::move(file)), name_(std::move(name)), fb_(fallback) {}

const toml::node* Section::find(const std::string& key, const Section** owner) const {
  if (t_) {
    if (const toml::node* n = t_->get(key)) {
      used_.insert(key);
      for (const Section* f = fb_; f; f = f->fb_)
        if (f->t_ && f->t_->contains(key)) f->used_.insert(key);  // overridden, not unknown
      if (owner) *owner = this;
      return n;
    }
  }
  if (fb_) return fb_->find(key, owner);
  return nullptr;
}

bool Section::has(const std::string& key) const {
  return (t_ && t_->contains(key)) || (fb_ && fb_->has(key));
}

std::string Section::where(const std::string& key) const {
  const toml::node* n = nullptr;
  const Section* s = this;
  if (t_ && (n = t_->get(key))) {
  } else if (fb_ && fb_->has(key)) {
    return fb_->where(key);
  }
  std::string loc = s->file_;
  if (n && n->source().begin.line) {
    loc += ':';
    loc += std::to_string(n->source().begin.line);
  }
  return loc + ": key '" + (name_.empty() ? key : name_ + "." + key) + "'";
}

void Section::fail(const std::string& key, const std::string& what) const { throw InputError(what, where(key)); }

void Section::fail_section(const std::string& what) const {
  throw InputError("[" + name_ + "]: " + what, file_);
}

double Section::parse_q(const toml::node& n, const std::string& key, const Dim& d) const {
  if (auto s = n.value<std::string>()) {
    try {
      return parse_quantity_as(*s, d);
    } catch (const InputError& e) {
      fail(key, e.what());
    }
  }
  if (n.is_number()) {
    double v = *n.value<double>();
    if (!std::isfinite(v)) fail(key, "must be a finite number");
    if (d == dim::none || d == dim::angle) return v;
    fail(key, "needs a unit: write it as a string such as \"" + std::to_string(v) + " " +
                  (d == dim::length ? "mm" : d == dim::speed ? "mm/s" : "<unit>") + "\" (" + describe(d) + ")");
  }
  fail(key, "expected a quantity string with a unit, e.g. \"7.62 cm\"");
}

std::optional<double> Section::quantity(const std::string& key, const Dim& d) {
  const Section* owner = nullptr;
  const toml::node* n = find(key, &owner);
  if (!n) return std::nullopt;
  return owner->parse_q(*n, key, d);
}

double Section::quantity(const std::string& key, const Dim& d, double default_value) {
  return quantity(key, d).value_or(default_value);
}

double Section::require_quantity(const std::string& key, const Dim& d) {
  auto v = quantity(key, d);
  if (!v) {
    throw InputError("[" + name_ + "]: the key '" + key + "' is missing (" + describe(d) + ")", file_);
  }
  return *v;
}

std::optional<std::string> Section::string(const std::string& key) {
  const Section* owner = nullptr;
  const toml::node* n = find(key, &owner);
  if (!n) return std::nullopt;
  if (auto s = n->value<std::string>()) return *s;
  owner->fail(key, "expected a string");
}

std::string Section::require_string(const std::string& key) {
  auto v = string(key);
  if (!v) throw InputError("[" + name_ + "]: the key '" + key + "' is missing", file_);
  return *v;
}

std::optional<double> Section::number(const std::string& key) {
  const Section* owner = nullptr;
  const toml::node* n = find(key, &owner);
  if (!n) return std::nullopt;
  if (n->is_number()) {
    double v = *n->value<double>();
    if (!std::isfinite(v)) owner->fail(key, "must be a finite number");
    return v;
  }
  if (auto s = n->value<std::string>()) {
    try {
      return parse_quantity_as(*s, dim::none);
    } catch (const InputError& e) {
      owner->fail(key, e.what());
    }
  }
  owner->fail(key, "expected a number");
}

template <class T>
std::optional<T> Section::exact(const std::string& key, const char* expected) {
  const Section* owner = nullptr;
  const toml::node* n = find(key, &owner);
  if (!n) return std::nullopt;
  if (auto v = n->value_exact<T>()) return *v;
  owner->fail(key, expected);
}

std::optional<int64_t> Section::integer(const std::string& key) { return exact<int64_t>(key, "expected a whole number"); }

std::optional<bool> Section::boolean(const std::string& key) { return exact<bool>(key, "expected true or false"); }

std::optional<Vec2> Section::point(const std::string& key) {
  const Section* owner = nullptr;
  const toml::node* n = find(key, &owner);
  if (!n) return std::nullopt;
  const toml::array* a = n->as_array();
  if (!a || a->size() != 2) owner->fail(key, "expected a point [\"x\", \"y\"] of two lengths");
  double xy[2];
  for (size_t i = 0; i < 2; ++i) xy[i] = owner->parse_q(*a->get(i), key, dim::length);
  return Vec2{xy[0], xy[1]};
}

Vec2 Section::require_point(const std::string& key) {
  auto p = point(key);
  if (!p) throw InputError("[" + name_ + "]: the key '" + key + "' is missing (a point [\"x\", \"y\"])", file_);
  return *p;
}

const toml::node* Section::node(const std::string& key) { return find(key, nullptr); }

Section Section::subsection(const std::string& key) {
  const Section* owner = nullptr;
  const toml::node* n = find(key, &owner);
  if (n && !n->is_table()) owner->fail(key, "expected a table");
  return Section(n ? n->as_table() : nullptr, owner ? owner->file_ : file_, name_.empty() ? key : name_ + "." + key);
}

void Section::finish() const {
  if (t_) {
    for (const auto& [k, v] : *t_) {
      std::string key(k.str());
      if (!used_.count(key)) {
        std::string loc = file_;
        if (v.source().begin.line) {
          loc += ':';
          loc += std::to_string(v.source().begin.line);
        }
        throw InputError("unknown key '" + (name_.empty() ? key : name_ + "." + key) + "'", loc);
      }
    }
  }
  if (fb_) fb_->finish();
}

toml::table parse_toml_file(const std::string& path) {
  open_input_file(path, "cannot open the file");  // a probe: toml++ opens the file itself
  try {
    return toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw InputError(std::string(e.description()),
                     path + ":" + std::to_string(b.line) + ":" + std::to_string(b.column));
  }
}

}  // namespace polarcam::jobfile
