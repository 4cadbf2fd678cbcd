#include "scenes/toml_reader.h"

#include <fmt/core.h>

#include <cmath>

namespace sylva {

namespace {
int line_of(const toml::node& n) { return static_cast<int>(n.source().begin.line); }

ParamValue to_value(const toml::node& n, const std::string& file, const std::string& where,
                    const FileResolver& resolver);

std::shared_ptr<Params> to_table(const toml::table& t, const std::string& file, const std::string& where,
                                 const FileResolver& resolver) {
  auto params = std::make_shared<Params>(file, line_of(t), where, resolver);
  for (const auto& [key, node] : t) {
    // A nested table is named [key] in messages, a table in an array [[key]].
    const std::string k(key.str());
    const std::string child = node.is_array() ? "[[" + k + "]]" : "[" + k + "]";
    params->add(k, to_value(node, file, child, resolver));
  }
  return params;
}

ParamValue to_value(const toml::node& n, const std::string& file, const std::string& where,
                    const FileResolver& resolver) {
  ParamValue v;
  v.line = line_of(n);
  if (const auto* b = n.as_boolean()) {
    v.kind = ParamValue::Kind::Bool;
    v.boolean = b->get();
  } else if (const auto* i = n.as_integer()) {
    v.kind = ParamValue::Kind::Integer;
    v.integer = i->get();
  } else if (const auto* f = n.as_floating_point()) {
    v.kind = ParamValue::Kind::Real;
    v.real = f->get();
  } else if (const auto* s = n.as_string()) {
    v.kind = ParamValue::Kind::String;
    v.string = s->get();
  } else if (const auto* a = n.as_array()) {
    v.kind = ParamValue::Kind::Array;
    for (const toml::node& e : *a) v.array.push_back(to_value(e, file, where, resolver));
  } else if (const auto* t = n.as_table()) {
    v.kind = ParamValue::Kind::Table;
    v.table = to_table(*t, file, where, resolver);
  } else {
    throw ParseError(file, v.line, "dates and times are not Sylva parameter values");
  }
  return v;
}

}  // namespace

Params TomlReader::to_params(const toml::table& t, const std::string& where, const FileResolver& resolver) const {
  return *to_table(t, file_, where, resolver);
}

toml::table TomlReader::parse(std::string_view text) const {
  try {
    return toml::parse(text, file_);
  } catch (const toml::parse_error& e) {
    throw ParseError(file_, static_cast<int>(e.source().begin.line), std::string(e.description()));
  }
}

void TomlReader::fail(const toml::node& at, const std::string& what) const {
  throw ParseError(file_, line_of(at), what);
}
void TomlReader::fail_line(int line, const std::string& what) const { throw ParseError(file_, line, what); }

void TomlReader::check_keys(const toml::table& t, std::initializer_list<std::string_view> allowed,
                            std::string_view where) const {
  for (const auto& [key, node] : t) {
    bool ok = false;
    for (std::string_view a : allowed) ok = ok || key.str() == a;
    if (!ok) {
      std::string list;
      for (std::string_view a : allowed) list += fmt::format("{}{}", list.empty() ? "" : ", ", a);
      fail(node, fmt::format("unknown key '{}' in {} (expected one of: {})", key.str(), where, list));
    }
  }
}

const toml::node& TomlReader::require(const toml::table& t, std::string_view key) const {
  const toml::node* n = t.get(key);
  if (!n) fail(t, fmt::format("missing key '{}'", key));
  return *n;
}

const toml::table* TomlReader::table(const toml::table& t, std::string_view key) const {
  const toml::node* n = t.get(key);
  if (!n) return nullptr;
  if (!n->is_table()) fail(*n, fmt::format("'{}' must be a table", key));
  return n->as_table();
}

const toml::array* TomlReader::array(const toml::table& t, std::string_view key) const {
  const toml::node* n = t.get(key);
  if (!n) return nullptr;
  if (!n->is_array()) fail(*n, fmt::format("'{}' must be an array (use [[{}]] for a list of tables)", key, key));
  return n->as_array();
}

std::string TomlReader::string(const toml::table& t, std::string_view key) const {
  const toml::node& n = require(t, key);
  if (!n.is_string()) fail(n, fmt::format("'{}' must be a string", key));
  return std::string(n.as_string()->get());
}

std::string TomlReader::string(const toml::table& t, std::string_view key, const std::string& fallback) const {
  return t.contains(key) ? string(t, key) : fallback;
}

bool TomlReader::boolean(const toml::table& t, std::string_view key, bool fallback) const {
  const toml::node* n = t.get(key);
  if (!n) return fallback;
  if (!n->is_boolean()) fail(*n, fmt::format("'{}' must be true or false", key));
  return n->as_boolean()->get();
}

double TomlReader::number(const toml::table& t, std::string_view key) const {
  const toml::node& n = require(t, key);
  if (!n.is_number()) fail(n, fmt::format("'{}' must be a number", key));
  const double v = *n.value<double>();
  if (!std::isfinite(v)) fail(n, fmt::format("'{}' must be finite", key));
  return v;
}

double TomlReader::number(const toml::table& t, std::string_view key, double fallback) const {
  return t.contains(key) ? number(t, key) : fallback;
}

float TomlReader::number_in(const toml::table& t, std::string_view key, double fallback, double lo, double hi) const {
  const double v = number(t, key, fallback);
  if (v < lo || v > hi) fail(*t.get(key), fmt::format("'{}' must lie in [{}, {}], not {}", key, lo, hi, v));
  return static_cast<float>(v);
}

int64_t TomlReader::integer(const toml::table& t, std::string_view key, int64_t fallback, int64_t lo,
                            int64_t hi) const {
  const toml::node* n = t.get(key);
  if (!n) return fallback;
  if (!n->is_integer()) fail(*n, fmt::format("'{}' must be an integer", key));
  const int64_t v = n->as_integer()->get();
  if (v < lo || v > hi) fail(*n, fmt::format("'{}' must lie in [{}, {}], not {}", key, lo, hi, v));
  return v;
}

std::vector<double> TomlReader::numbers(const toml::table& t, std::string_view key) const {
  const toml::node& n = require(t, key);
  const toml::array* a = n.as_array();
  if (!a) fail(n, fmt::format("'{}' must be an array of numbers", key));
  std::vector<double> out;
  for (const toml::node& e : *a) {
    if (!e.is_number()) fail(e, fmt::format("'{}' must contain only numbers", key));
    out.push_back(*e.value<double>());
  }
  return out;
}

std::vector<std::string> TomlReader::strings(const toml::table& t, std::string_view key) const {
  const toml::node& n = require(t, key);
  const toml::array* a = n.as_array();
  if (!a) fail(n, fmt::format("'{}' must be an array of strings", key));
  std::vector<std::string> out;
  for (const toml::node& e : *a) {
    if (!e.is_string()) fail(e, fmt::format("'{}' must contain only strings", key));
    out.emplace_back(e.as_string()->get());
  }
  return out;
}

Vec2 TomlReader::vec2(const toml::table& t, std::string_view key, Vec2 fallback) const {
  if (!t.contains(key)) return fallback;
  const std::vector<double> v = numbers(t, key);
  if (v.size() != 2) fail(*t.get(key), fmt::format("'{}' must be an array of 2 numbers", key));
  return {static_cast<float>(v[0]), static_cast<float>(v[1])};
}

Vec3 TomlReader::vec3(const toml::table& t, std::string_view key, Vec3 fallback) const {
  if (!t.contains(key)) return fallback;
  const std::vector<double> v = numbers(t, key);
  if (v.size() != 3) fail(*t.get(key), fmt::format("'{}' must be an array of 3 numbers", key));
  for (double x : v)
    if (!std::isfinite(x)) fail(*t.get(key), fmt::format("'{}' must be finite", key));
  return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])};
}

}  // namespace sylva
