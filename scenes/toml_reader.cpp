#include "scenes/toml_reader.h"

#include <fmt/core.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <optional>

namespace sylva {

namespace {
int line_of(const toml::node& n) { return static_cast<int>(n.source().begin.line); }

// The override a node came from ("--set PATH=VALUE"), or null for a node of the file.
std::shared_ptr<const std::string> override_of(const toml::node& n) {
  const toml::source_path_ptr& path = n.source().path;
  if (path && path->starts_with(kOverridePrefix)) return path;
  return nullptr;
}

ParamValue to_value(const toml::node& n, const std::string& file, const std::string& where,
                    const FileResolver& resolver);

std::shared_ptr<Params> to_table(const toml::table& t, const std::string& file, const std::string& where,
                                 const FileResolver& resolver) {
  const std::shared_ptr<const std::string> origin = override_of(t);
  auto params = origin ? std::make_shared<Params>(*origin, ParseError::kNoLine, where, resolver)
                       : std::make_shared<Params>(file, line_of(t), where, resolver);
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
  v.origin = override_of(n);
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

// A bare TOML key (letters, digits, '_' and '-'), as an override's path must use.
bool is_bare_key(std::string_view key) {
  return !key.empty() && std::all_of(key.begin(), key.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
  });
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// Merges `from` into `into`: a table (not an inline one, which is a value) merges into a table of
// the same name; anything else replaces the key's value.
void merge_tables(toml::table& into, toml::table&& from) {
  for (auto&& [key, node] : from) {
    toml::table* sub = node.as_table();
    toml::table* existing = into[key].as_table();
    if (sub != nullptr && !sub->is_inline() && existing != nullptr && !existing->is_inline())
      merge_tables(*existing, std::move(*sub));
    else
      into.insert_or_assign(key, std::move(node));
  }
}

// "a.b = VALUE" parsed as its own document, with `origin` as every node's source.
toml::table parse_override(std::string_view keys, std::string_view value, const std::string& origin) {
  try {
    return toml::parse(fmt::format("{} = {}", keys, value), origin);
  } catch (const toml::parse_error& e) {
    // A bare word (ACES, cie-clear) is a string; anything else that does not parse is a mistake.
    const bool bare_word = !value.empty() && value.find_first_of("[]{}\"'\n=#") == std::string_view::npos;
    if (!bare_word)
      throw ParseError(origin, ParseError::kNoLine,
                       fmt::format("'{}' is not a TOML value ({})", value, e.description()));
    return toml::parse(fmt::format("{} = \"{}\"", keys, value), origin);
  }
}

// One component of an override's path: a key, optionally indexed (`trees[1]`), or a quoted name.
struct PathPart {
  std::string key;
  std::optional<size_t> index;
  bool quoted = false;  // "a name" (selects an entry of a list of tables by its `name`)
};

// Splits PATH at the dots outside double quotes; `fail` reports a malformed component.
template <typename Fail>
std::vector<PathPart> split_path(std::string_view path, const Fail& fail) {
  std::vector<PathPart> parts;
  size_t start = 0;
  while (start <= path.size()) {
    PathPart part;
    size_t end = 0;
    if (start < path.size() && path[start] == '"') {
      const size_t close = path.find('"', start + 1);
      if (close == std::string_view::npos) fail(fmt::format("unterminated quote in '{}'", path));
      part.key = std::string(path.substr(start + 1, close - start - 1));
      part.quoted = true;
      end = close + 1;
      if (end < path.size() && path[end] != '.') fail(fmt::format("expected '.' after the quoted name in '{}'", path));
    } else {
      end = std::min(path.find('.', start), path.size());
      std::string_view text = path.substr(start, end - start);
      if (const size_t open = text.find('['); open != std::string_view::npos) {
        size_t i = 0;
        const std::string_view digits = text.substr(open + 1, text.size() - open - 2);
        const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), i);
        if (text.back() != ']' || digits.empty() || ec != std::errc() || ptr != digits.data() + digits.size())
          fail(fmt::format("'{}' is not KEY or KEY[INDEX]", text));
        part.index = i;
        text = text.substr(0, open);
      }
      if (!is_bare_key(text))
        fail(fmt::format("'{}' is not a key (letters, digits, '_' and '-', joined by dots)", path));
      part.key = std::string(text);
    }
    parts.push_back(std::move(part));
    start = end + 1;
  }
  return parts;
}

// The entry of the list of tables [[list]] whose `name` is `name` (exactly one).
template <typename Fail>
toml::table* entry_named(toml::array& list, std::string_view list_name, const std::string& name, const Fail& fail) {
  toml::table* found = nullptr;
  std::string names;
  size_t count = 0;
  for (toml::node& e : list) {
    const toml::value<std::string>* n = e.as_table()->get_as<std::string>("name");
    if (n == nullptr) continue;
    names += fmt::format("{}'{}'", names.empty() ? "" : ", ", n->get());
    if (n->get() == name) {
      found = e.as_table();
      ++count;
    }
  }
  if (count == 0)
    fail(fmt::format("no [[{}]] entry has name = '{}' (names: {})", list_name, name, names.empty() ? "none" : names));
  if (count > 1)
    fail(fmt::format("{} [[{}]] entries have name = '{}': index one instead ({}[0], ...)", count, list_name, name,
                     list_name));
  return found;
}

void apply_override(toml::table& document, const std::string& text) {
  const std::string origin = std::string(kOverridePrefix) + text;
  const auto fail = [&](const std::string& what) { throw ParseError(origin, ParseError::kNoLine, what); };
  if (text.find_first_of("\r\n") != std::string::npos) fail("an override is one line");
  const size_t eq = text.find('=');
  if (eq == std::string::npos) fail("expected SECTION.KEY=VALUE, e.g. sun.elevation=10");
  const std::string_view value = trim(std::string_view(text).substr(eq + 1));
  const std::vector<PathPart> parts = split_path(trim(std::string_view(text).substr(0, eq)), fail);
  // Lists of tables are entered by index (`trees[1]`) or by an entry's name (`targets.vehicle`,
  // `targets."grey vehicle"`); the keys after the last one are parsed with the value as a document
  // of their own and merged into the table reached.
  toml::table* table = &document;
  std::vector<std::string> keys;
  const auto enter_keys = [&](const std::string& list) {
    for (const std::string& key : keys) {
      table = (*table)[key].as_table();
      if (table == nullptr) fail(fmt::format("there is no table '{}' holding [[{}]]", key, list));
    }
    keys.clear();
  };
  for (size_t i = 0; i < parts.size(); ++i) {
    const PathPart& part = parts[i];
    const bool last = i + 1 == parts.size();
    toml::table* holder = table;
    for (const std::string& key : keys) holder = holder ? (*holder)[key].as_table() : nullptr;
    toml::array* list = holder ? (*holder)[part.key].as_array() : nullptr;
    const bool by_name = !part.index && !part.quoted && !last && list != nullptr && list->is_array_of_tables();
    if (part.quoted) fail(fmt::format("a quoted name must follow a list of tables, as in targets.\"{}\"", part.key));
    if (!part.index && !by_name) {
      keys.push_back(part.key);
      continue;
    }
    enter_keys(part.key);
    if (last)
      fail(fmt::format("give a key of {}[{}], e.g. {}[{}].name=...", part.key, *part.index, part.key, *part.index));
    if (list == nullptr || !list->is_array_of_tables())
      fail(fmt::format("there is no list of tables [[{}]] to index", part.key));
    if (by_name) {
      table = entry_named(*list, part.key, parts[++i].key, fail);
      if (i + 1 == parts.size()) fail(fmt::format("give a key of the [[{}]] entry, e.g. .name=...", part.key));
      continue;
    }
    if (*part.index >= list->size())
      fail(fmt::format("[[{}]] has {} entr{} (indices from 0)", part.key, list->size(),
                       list->size() == 1 ? "y" : "ies"));
    table = list->get(*part.index)->as_table();
  }
  if (keys.empty()) fail("expected SECTION.KEY=VALUE, e.g. sun.elevation=10");
  std::string dotted;
  for (const std::string& key : keys) dotted += (dotted.empty() ? "" : ".") + key;
  merge_tables(*table, parse_override(dotted, value, origin));
}

}  // namespace

void apply_overrides(toml::table& document, const std::vector<std::string>& overrides) {
  for (const std::string& text : overrides) apply_override(document, text);
}

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
