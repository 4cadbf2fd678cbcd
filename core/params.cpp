#include "core/params.h"

#include "core/error.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace sylva {

namespace {

std::string format_number(double v) { return fmt::format("{}", v); }

const char* kind_name(ParamValue::Kind k) {
  switch (k) {
    case ParamValue::Kind::Bool:
      return "a boolean";
    case ParamValue::Kind::Integer:
      return "an integer";
    case ParamValue::Kind::Real:
      return "a number";
    case ParamValue::Kind::String:
      return "a string";
    case ParamValue::Kind::Array:
      return "an array";
    case ParamValue::Kind::Table:
      return "a table";
  }
  return "a value";
}

}  // namespace

Params::Params(std::string file, int line, std::string where, FileResolver resolver)
    : file_(std::make_shared<const std::string>(std::move(file))),
      line_(line),
      where_(std::move(where)),
      resolver_(std::move(resolver)) {}

void Params::add(std::string name, ParamValue value) {
  if (const Entry* e = find(name))
    throw ParseError(*file_, value.line,
                     fmt::format("parameter '{}' given twice (first on line {})", name, e->value.line));
  entries_.push_back(Entry{std::move(name), std::move(value)});
}

const Params::Entry* Params::find(std::string_view name) const {
  for (const Entry& e : entries_)
    if (e.name == name) return &e;
  return nullptr;
}

std::vector<std::string> Params::names() const {
  std::vector<std::string> out;
  for (const Entry& e : entries_) out.push_back(e.name);
  return out;
}

std::vector<std::string> Params::unread_names() const {
  std::vector<std::string> out;
  for (const Entry& e : entries_)
    if (!e.read) out.push_back(e.name);
  return out;
}

const ParamValue* Params::get(std::string_view name) const {
  if (std::find(queried_.begin(), queried_.end(), name) == queried_.end()) queried_.emplace_back(name);
  const Entry* e = find(name);
  if (!e) return nullptr;
  e->read = true;
  return &e->value;
}

int Params::line_of(std::string_view name) const {
  const Entry* e = find(name);
  return e ? e->value.line : line_;
}

void Params::fail(std::string_view name, const std::string& what) const {
  if (const Entry* e = find(name)) fail_at(e->value, what);
  throw ParseError(*file_, line_, what);
}
void Params::fail(const std::string& what) const { throw ParseError(*file_, line_, what); }
void Params::fail_at(const ParamValue& value, const std::string& what) const {
  if (value.origin) throw ParseError(*value.origin, ParseError::kNoLine, what);
  throw ParseError(*file_, value.line, what);
}

const ParamValue& Params::require(std::string_view name) const {
  const ParamValue* v = get(name);
  if (!v) fail(fmt::format("missing key '{}' in {}", name, where_));
  return *v;
}

double Params::checked_number(std::string_view name, const ParamValue& v, double lo, double hi, bool whole) const {
  if (!v.is_number()) fail_at(v, fmt::format("'{}' must be a number, not {}", name, kind_name(v.kind)));
  const double x = v.number();
  if (!std::isfinite(x)) fail_at(v, fmt::format("'{}' must be finite", name));
  if (whole && x != std::floor(x)) fail_at(v, fmt::format("'{}' must be an integer, not {}", name, format_number(x)));
  if (x < lo || x > hi)
    fail_at(v, fmt::format("'{}' must lie in [{}, {}], not {}", name, format_number(lo), format_number(hi),
                           format_number(x)));
  return x;
}

double Params::number(std::string_view name) const {
  const double inf = std::numeric_limits<double>::infinity();
  return checked_number(name, require(name), -inf, inf, false);
}

double Params::number(std::string_view name, double fallback, double lo, double hi) const {
  const ParamValue* v = get(name);
  return v ? checked_number(name, *v, lo, hi, false) : fallback;
}

void Params::read_fields(std::span<const RealField> reals, std::span<const IntField> ints) const {
  for (const RealField& r : reals) *r.value = real(r.name, *r.value, r.lo, r.hi);
  for (const IntField& i : ints) *i.value = static_cast<int>(integer(i.name, *i.value, i.lo, i.hi));
}

int64_t Params::integer(std::string_view name, int64_t fallback, int64_t lo, int64_t hi) const {
  const ParamValue* v = get(name);
  if (!v) return fallback;
  if (v->kind == ParamValue::Kind::Integer) {
    if (v->integer < lo || v->integer > hi)
      fail_at(*v, fmt::format("'{}' must lie in [{}, {}], not {}", name, lo, hi, v->integer));
    return v->integer;
  }
  if (!v->is_number()) fail_at(*v, fmt::format("'{}' must be an integer", name));
  return static_cast<int64_t>(checked_number(name, *v, static_cast<double>(lo), static_cast<double>(hi), true));
}

bool Params::boolean(std::string_view name, bool fallback) const {
  const ParamValue* v = get(name);
  if (!v) return fallback;
  if (v->kind != ParamValue::Kind::Bool) fail_at(*v, fmt::format("'{}' must be true or false", name));
  return v->boolean;
}

std::string Params::string(std::string_view name) const {
  const ParamValue& v = require(name);
  if (v.kind != ParamValue::Kind::String) fail_at(v, fmt::format("'{}' must be a string", name));
  return v.string;
}

std::string Params::string(std::string_view name, const std::string& fallback) const {
  if (has(name)) return string(name);
  get(name);  // recorded as an accepted key for check_unused's message
  return fallback;
}

std::vector<double> Params::numbers(std::string_view name) const {
  const ParamValue& v = require(name);
  if (v.kind != ParamValue::Kind::Array) fail_at(v, fmt::format("'{}' must be an array of numbers", name));
  std::vector<double> out;
  for (const ParamValue& e : v.array) {
    if (!e.is_number()) fail_at(e, fmt::format("'{}' must contain only numbers", name));
    out.push_back(e.number());
  }
  return out;
}

std::vector<std::string> Params::strings(std::string_view name) const {
  const ParamValue& v = require(name);
  if (v.kind != ParamValue::Kind::Array) fail_at(v, fmt::format("'{}' must be an array of strings", name));
  std::vector<std::string> out;
  for (const ParamValue& e : v.array) {
    if (e.kind != ParamValue::Kind::String) fail_at(e, fmt::format("'{}' must contain only strings", name));
    out.push_back(e.string);
  }
  return out;
}

Vec2 Params::vec2(std::string_view name, Vec2 fallback) const {
  if (!get(name)) return fallback;
  const std::vector<double> v = numbers(name);
  if (v.size() != 2) fail(name, fmt::format("'{}' must be an array of 2 numbers", name));
  for (double x : v)
    if (!std::isfinite(x)) fail(name, fmt::format("'{}' must be finite", name));
  return {static_cast<float>(v[0]), static_cast<float>(v[1])};
}

Vec3 Params::vec3(std::string_view name, Vec3 fallback) const {
  if (!get(name)) return fallback;
  const std::vector<double> v = numbers(name);
  if (v.size() != 3) fail(name, fmt::format("'{}' must be an array of 3 numbers", name));
  for (double x : v)
    if (!std::isfinite(x)) fail(name, fmt::format("'{}' must be finite", name));
  return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])};
}

const Params* Params::table(std::string_view name) const {
  const ParamValue* v = get(name);
  if (!v) return nullptr;
  if (v->kind != ParamValue::Kind::Table) fail_at(*v, fmt::format("'{}' must be a table", name));
  return v->table.get();
}

std::vector<const Params*> Params::tables(std::string_view name) const {
  const ParamValue* v = get(name);
  std::vector<const Params*> out;
  if (!v) return out;
  if (v->kind != ParamValue::Kind::Array)
    fail_at(*v, fmt::format("'{}' must be an array (use [[{}]] for a list of tables)", name, name));
  for (const ParamValue& e : v->array) {
    if (e.kind != ParamValue::Kind::Table) fail_at(e, fmt::format("expected a table in [[{}]]", name));
    out.push_back(e.table.get());
  }
  return out;
}

std::filesystem::path Params::file_path(std::string_view name) const {
  const std::string rel = string(name);
  FileLookup lookup = resolver_ ? resolver_(rel) : FileLookup{rel, {rel}};
  if (lookup.found.empty() || !std::filesystem::exists(lookup.found)) {
    std::string tried;
    for (const std::filesystem::path& p : lookup.tried) tried += (tried.empty() ? "" : ", ") + p.string();
    fail(name, "file not found: " + rel + (tried.empty() ? "" : " (looked for " + tried + ")"));
  }
  return lookup.found;
}

DenseSpectrum Params::spectrum_of(const ParamValue& v, Extrapolate outside) const {
  if (v.is_number()) return DenseSpectrum::constant(static_cast<float>(v.number()));
  if (v.kind == ParamValue::Kind::String) {
    if (const std::optional<DenseSpectrum> s = named_spectrum(v.string)) return *s;
    fail_at(v, "unknown spectrum '" + v.string +
                   "' (expected a number, astm-g173-direct, astm-g173-diffuse, astm-g173-global, "
                   "{ file, column } or { lambda_nm, value })");
  }
  if (v.kind != ParamValue::Kind::Table)
    fail_at(v, "expected a spectrum: a number, a name, { file, column } or { lambda_nm, value }");
  const Params& t = *v.table;
  if (t.has("file")) {
    t.check_keys({"file", "column", "scale"});
    const std::filesystem::path file = t.file_path("file");
    const std::string column = t.string("column");
    DenseSpectrum s;
    try {
      s = load_spectrum(file, column, outside);
    } catch (const Error& e) {
      t.fail(e.what());
    }
    s *= static_cast<float>(t.number("scale", 1.0, -1e30, 1e30));
    return s;
  }
  t.check_keys({"lambda_nm", "value", "scale"});
  const std::vector<double> l = t.numbers("lambda_nm");
  const std::vector<double> y = t.numbers("value");
  if (l.size() != y.size() || l.empty()) t.fail("lambda_nm and value must be non-empty arrays of equal length");
  for (size_t i = 1; i < l.size(); ++i)
    if (!(l[i] > l[i - 1])) t.fail("lambda_nm", "lambda_nm must increase strictly");
  DenseSpectrum s = DenseSpectrum::from_samples(l, y, outside);
  s *= static_cast<float>(t.number("scale", 1.0, -1e30, 1e30));
  return s;
}

DenseSpectrum Params::spectrum(std::string_view name, Extrapolate outside) const {
  return spectrum_of(require(name), outside);
}

std::optional<DenseSpectrum> Params::optional_spectrum(std::string_view name, Extrapolate outside) const {
  const ParamValue* v = get(name);
  if (!v) return std::nullopt;
  return spectrum_of(*v, outside);
}

void Params::check_keys(std::initializer_list<std::string_view> allowed) const {
  for (const Entry& e : entries_) {
    if (std::find(allowed.begin(), allowed.end(), e.name) != allowed.end()) continue;
    std::string list;
    for (std::string_view a : allowed) list += fmt::format("{}{}", list.empty() ? "" : ", ", a);
    fail_at(e.value, fmt::format("unknown key '{}' in {} (expected one of: {})", e.name, where_, list));
  }
}

void Params::check_unused() const {
  for (const Entry& e : entries_) {
    if (e.read) continue;
    std::string list;
    for (const std::string& a : queried_) list += fmt::format("{}{}", list.empty() ? "" : ", ", a);
    fail_at(e.value, fmt::format("unknown key '{}' in {} (expected one of: {})", e.name, where_, list));
  }
}

}  // namespace sylva
