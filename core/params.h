#pragma once
// Parameters: a format-neutral table of named values with their source location, so that each
// extensible type (a material, a light, a sensor, a tree model) reads its own parameters — as
// pbrt-v4's `Create(parameters, loc)` and Mitsuba's plugin constructors do — without knowing
// whether they came from a TOML scene, an Arbaro XML file or a test.
//
// File readers (scenes/) build a Params from their document; a type reads what it needs with the
// typed accessors below, which check type and range and report every mistake as
// `file:line: message` (sylva::ParseError). After reading, `check_unused()` rejects keys nobody
// read ("unknown key 'x' in <where> (expected one of ...)"), which catches typos.

#include "core/data_path.h"
#include "core/math.h"
#include "core/spectrum.h"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

// One row of a model's parameter schema: a named parameter read into a field of its parameter
// struct, range-checked (`Params::read_fields`). An absent parameter keeps the field's default.
struct RealField {
  std::string_view name;
  float* value;
  double lo, hi;
};
struct IntField {
  std::string_view name;
  int* value;
  int lo, hi;
};

namespace sylva {

class Params;

// One value: a boolean, an integer, a real, a string, an array of values or a table.
struct ParamValue {
  enum class Kind { Bool, Integer, Real, String, Array, Table };
  Kind kind = Kind::Integer;
  bool boolean = false;
  int64_t integer = 0;
  double real = 0.0;
  std::string string;
  std::vector<ParamValue> array;
  std::shared_ptr<Params> table;
  int line = 0;  // 1-based source line, 0 when unknown
  // Set for a value given on the command line (`--set section.key=value`): messages name it
  // ("--set sun.elevation=abc: ...") instead of a file and line.
  std::shared_ptr<const std::string> origin;

  bool is_number() const { return kind == Kind::Integer || kind == Kind::Real; }
  double number() const { return kind == Kind::Integer ? static_cast<double>(integer) : real; }
};

// Resolves a file name written in a parameter file (relative to that file, then to Sylva's data
// directory: find_named_file, core/data_path.h); `found` is empty when the file is not found, and
// `tried` lists the places looked at, for the message.
using FileResolver = std::function<FileLookup(const std::string&)>;

class Params {
 public:
  // `where` names the table in messages ("[camera]", "material 'bark'"); `line` is its first line.
  Params(std::string file, int line, std::string where, FileResolver resolver = {});

  // Adds a value; a repeated name is an error at the second occurrence.
  void add(std::string name, ParamValue value);

  // A copy named differently in messages (e.g. "material 'bark'" for the table [materials.bark]).
  Params with_where(std::string where) const {
    Params p = *this;
    p.where_ = std::move(where);
    return p;
  }

  const std::string& file() const { return *file_; }
  int line() const { return line_; }
  const std::string& where() const { return where_; }
  bool has(std::string_view name) const { return find(name) != nullptr; }
  // Names in the order they were added.
  std::vector<std::string> names() const;
  // Names not read yet, in order (a reader that takes "everything else" uses these).
  std::vector<std::string> unread_names() const;
  // The raw value (marks it read), nullptr if absent.
  const ParamValue* get(std::string_view name) const;
  int line_of(std::string_view name) const;

  // Typed accessors. Without a fallback the parameter is required. Numbers are checked against
  // [lo, hi]; integers must be whole.
  double number(std::string_view name) const;
  double number(std::string_view name, double fallback, double lo, double hi) const;
  float real(std::string_view name, double fallback, double lo, double hi) const {
    return static_cast<float>(number(name, fallback, lo, hi));
  }
  int64_t integer(std::string_view name, int64_t fallback, int64_t lo, int64_t hi) const;
  // Every row of a schema table (see RealField).
  void read_fields(std::span<const RealField> reals, std::span<const IntField> ints) const;
  bool boolean(std::string_view name, bool fallback) const;
  std::string string(std::string_view name) const;
  std::string string(std::string_view name, const std::string& fallback) const;
  std::vector<double> numbers(std::string_view name) const;
  std::vector<std::string> strings(std::string_view name) const;
  Vec2 vec2(std::string_view name, Vec2 fallback) const;
  Vec3 vec3(std::string_view name, Vec3 fallback) const;
  // A table-valued parameter (nullptr if absent) and an array of tables (empty if absent).
  const Params* table(std::string_view name) const;
  std::vector<const Params*> tables(std::string_view name) const;
  // A spectrum: a number (constant), a built-in name (astm-g173-direct, astm-g173-diffuse,
  // astm-g173-global), { file, column [, scale] } or { lambda_nm, value [, scale] }.
  DenseSpectrum spectrum(std::string_view name, Extrapolate outside) const;
  std::optional<DenseSpectrum> optional_spectrum(std::string_view name, Extrapolate outside) const;
  // A file named by a parameter, resolved by the reader's FileResolver; an error if not found.
  std::filesystem::path file_path(std::string_view name) const;

  // Errors at a parameter's line (or the table's when absent).
  [[noreturn]] void fail(std::string_view name, const std::string& what) const;
  [[noreturn]] void fail(const std::string& what) const;
  [[noreturn]] void fail_at(const ParamValue& value, const std::string& what) const;
  // Rejects parameters that were never read: "unknown key 'x' in <where> (expected one of ...)".
  void check_unused() const;
  // Rejects names outside `allowed` without reading anything.
  void check_keys(std::initializer_list<std::string_view> allowed) const;

 private:
  struct Entry {
    std::string name;
    ParamValue value;
    mutable bool read = false;
  };
  const Entry* find(std::string_view name) const;
  const ParamValue& require(std::string_view name) const;
  double checked_number(std::string_view name, const ParamValue& v, double lo, double hi, bool whole) const;
  DenseSpectrum spectrum_of(const ParamValue& v, Extrapolate outside) const;

  std::shared_ptr<const std::string> file_;
  int line_ = 0;
  std::string where_;
  FileResolver resolver_;
  std::vector<Entry> entries_;
  mutable std::vector<std::string> queried_;  // names asked for, for the "expected one of" list
};

}  // namespace sylva
