#include "scenes/placement_list.h"

#include "core/error.h"
#include "core/input_file.h"

#include <fmt/core.h>

#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace sylva {

namespace {

enum Column { kX, kY, kZ, kSpecies, kSeed, kScale, kHeading, kColumnCount };
constexpr std::array<std::string_view, kColumnCount> kColumnNames = {"x",    "y",     "z",      "species",
                                                                     "seed", "scale", "heading"};

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

// Splits `line` at commas into `fields` (views into `line`), trimmed.
void split(std::string_view line, std::vector<std::string_view>& fields) {
  fields.clear();
  size_t start = 0;
  while (true) {
    const size_t comma = line.find(',', start);
    fields.push_back(
        trim(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
    if (comma == std::string_view::npos) return;
    start = comma + 1;
  }
}

}  // namespace

void for_each_placement_row(const std::filesystem::path& file, float max_coordinate_m,
                            const std::function<void(const PlacementRow&, int line)>& row) {
  require_regular_file(file, "placement list");
  if (std::filesystem::file_size(file) > kMaxPlacementFileBytes)
    throw Error(fmt::format("{}: the placement list is larger than {} GiB (docs/limits.md)", file.string(),
                            kMaxPlacementFileBytes >> 30));
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> in(std::fopen(file.c_str(), "rb"), &std::fclose);
  if (!in) throw Error(fmt::format("{}: cannot open the placement list", file.string()));
  std::array<int, kColumnCount> column{};
  column.fill(-1);
  bool have_header = false;
  std::vector<std::string_view> fields;
  std::string line;
  std::vector<char> buffer(1 << 16);
  int line_number = 0;
  size_t columns = 0;
  const auto fail = [&](const std::string& what) { throw ParseError(file, line_number, what); };
  const auto parse_float = [&](std::string_view text, Column c, float lo, float hi) {
    float v = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(v))
      fail(fmt::format("{}: expected a number, not '{}'", kColumnNames[c], text));
    if (!(v >= lo && v <= hi)) fail(fmt::format("{} = {} is outside [{:g}, {:g}]", kColumnNames[c], text, lo, hi));
    return v;
  };
  // Lines are read in blocks; a line longer than the block grows `line`.
  bool eof = false;
  while (!eof) {
    line.clear();
    while (true) {
      if (std::fgets(buffer.data(), static_cast<int>(buffer.size()), in.get()) == nullptr) {
        if (std::ferror(in.get())) fail("read error");
        eof = true;
        break;
      }
      const size_t n = std::char_traits<char>::length(buffer.data());
      line.append(buffer.data(), n);
      if (n > 0 && buffer[n - 1] == '\n') break;
    }
    if (eof && line.empty()) break;
    ++line_number;
    if (line.find('\0') != std::string::npos) fail("a placement list is text (found a NUL byte)");
    const std::string_view text = trim(std::string_view(line).substr(0, line.find_first_of("\n")));
    if (text.empty() || text.front() == '#') continue;
    split(text, fields);
    if (!have_header) {
      for (size_t i = 0; i < fields.size(); ++i) {
        int c = -1;
        for (int k = 0; k < kColumnCount; ++k)
          if (fields[i] == kColumnNames[static_cast<size_t>(k)]) c = k;
        if (c < 0)
          fail(
              fmt::format("unknown column '{}' in the header (expected x, y, species, seed, scale, heading and "
                          "optionally z)",
                          fields[i]));
        if (column[static_cast<size_t>(c)] >= 0) fail(fmt::format("column '{}' is named twice", fields[i]));
        column[static_cast<size_t>(c)] = static_cast<int>(i);
      }
      for (int k = 0; k < kColumnCount; ++k)
        if (k != kZ && column[static_cast<size_t>(k)] < 0)
          fail(
              fmt::format("the header needs a column '{}' (columns: x, y, species, seed, scale, heading, "
                          "optional z)",
                          kColumnNames[static_cast<size_t>(k)]));
      columns = fields.size();
      have_header = true;
      continue;
    }
    if (fields.size() != columns)
      fail(fmt::format("expected {} fields as in the header, found {}", columns, fields.size()));
    const auto field = [&](Column c) { return fields[static_cast<size_t>(column[c])]; };
    PlacementRow r;
    const float m = max_coordinate_m;
    r.x = parse_float(field(kX), kX, -m, m);
    r.y = parse_float(field(kY), kY, -m, m);
    if (column[kZ] >= 0) r.z = parse_float(field(kZ), kZ, -m, m);
    r.species = field(kSpecies);
    if (r.species.empty()) fail("species: expected a species name");
    const std::string_view seed = field(kSeed);
    const auto [end, ec] = std::from_chars(seed.data(), seed.data() + seed.size(), r.seed);
    if (ec != std::errc() || end != seed.data() + seed.size() || r.seed > uint64_t{INT64_MAX})
      fail(fmt::format("seed: expected a whole number from 0 to {}, not '{}'", INT64_MAX, seed));
    r.scale = parse_float(field(kScale), kScale, 0.0f, 1e4f);
    if (!(r.scale > 0)) fail(fmt::format("scale = {} must be positive", field(kScale)));
    r.heading_deg = parse_float(field(kHeading), kHeading, -3600.0f, 3600.0f);
    row(r, line_number);
  }
  if (!have_header) throw ParseError(file, std::max(line_number, 1), "the placement list has no header line");
}

}  // namespace sylva
