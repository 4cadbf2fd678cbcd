#pragma once
// Typed access to a parsed TOML document with `file:line: what was expected` errors, shared by the
// scene and species parsers. Every accessor checks type and range and names the key it read.

#include "core/error.h"
#include "core/math.h"
#include "core/params.h"

#include <toml++/toml.h>

#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

namespace sylva {

// Command-line overrides of a parsed document (`--set PATH=VALUE`, repeatable), applied before any
// section reads it, so every key a file can set can be overridden. PATH is dotted keys, each
// optionally indexed into a list of tables from 0 (`trees[1].seed`); VALUE is a TOML value
// (`10`, `[0,-30,2]`, `"ACES"`), and a bare word that is not one is taken as a string
// (`output.view=ACES`). A value replaces the key's; tables are merged. Values and tables that come
// from an override keep it as their source, so a mistake in one is reported naming it, as a
// mistake in the file is at its line ("--set sun.elevaton=10: unknown key 'elevaton' in [sun] ...").
// A malformed override throws ParseError naming it.
inline constexpr std::string_view kOverridePrefix = "--set ";
void apply_overrides(toml::table& document, const std::vector<std::string>& overrides);

class TomlReader {
 public:
  explicit TomlReader(std::string file) : file_(std::move(file)) {}

  // Parses `text`; syntax errors become ParseError with the line toml++ reports.
  toml::table parse(std::string_view text) const;

  [[noreturn]] void fail(const toml::node& at, const std::string& what) const;
  [[noreturn]] void fail_line(int line, const std::string& what) const;
  const std::string& file() const { return file_; }

  // The table as format-neutral Params (nested tables and arrays included), for types that read
  // their own parameters; `where` names it in messages, `resolver` finds the files it names.
  Params to_params(const toml::table& t, const std::string& where, const FileResolver& resolver = {}) const;

  // Rejects keys not in `allowed` (catches typos): "unknown key 'x' in <where> (expected one of ...)".
  void check_keys(const toml::table& t, std::initializer_list<std::string_view> allowed, std::string_view where) const;

  const toml::table* table(const toml::table& t, std::string_view key) const;  // nullptr if absent
  const toml::array* array(const toml::table& t, std::string_view key) const;  // nullptr if absent

  std::string string(const toml::table& t, std::string_view key) const;  // required
  std::string string(const toml::table& t, std::string_view key, const std::string& fallback) const;
  bool boolean(const toml::table& t, std::string_view key, bool fallback) const;
  double number(const toml::table& t, std::string_view key) const;  // required
  double number(const toml::table& t, std::string_view key, double fallback) const;
  float number_in(const toml::table& t, std::string_view key, double fallback, double lo, double hi) const;
  int64_t integer(const toml::table& t, std::string_view key, int64_t fallback, int64_t lo, int64_t hi) const;
  std::vector<double> numbers(const toml::table& t, std::string_view key) const;       // required array
  std::vector<std::string> strings(const toml::table& t, std::string_view key) const;  // required array
  Vec2 vec2(const toml::table& t, std::string_view key, Vec2 fallback) const;
  Vec3 vec3(const toml::table& t, std::string_view key, Vec3 fallback) const;

 private:
  const toml::node& require(const toml::table& t, std::string_view key) const;
  std::string file_;
};

}  // namespace sylva
