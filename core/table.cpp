#include "core/table.h"

#include "core/error.h"
#include "core/input_file.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

namespace sylva {

namespace {

std::vector<std::string_view> split_fields(std::string_view line) {
  const char* seps = line.find(',') != std::string_view::npos    ? ","
                     : line.find('\t') != std::string_view::npos ? "\t"
                                                                 : " ";
  std::vector<std::string_view> fields;
  size_t start = 0;
  while (true) {
    size_t end = line.find_first_of(seps, start);
    std::string_view f = line.substr(start, end == std::string_view::npos ? end : end - start);
    while (!f.empty() && (f.front() == ' ' || f.front() == '\r')) f.remove_prefix(1);
    while (!f.empty() && (f.back() == ' ' || f.back() == '\r')) f.remove_suffix(1);
    if (!(seps[0] == ' ' && f.empty())) fields.push_back(f);
    if (end == std::string_view::npos) break;
    start = end + 1;
  }
  return fields;
}

bool parse_number(std::string_view s, double& out) {
  if (s.empty()) {
    out = std::numeric_limits<double>::quiet_NaN();
    return true;
  }
  if (s.front() == '+') s.remove_prefix(1);
  auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && ptr == s.data() + s.size();
}

}  // namespace

size_t Table::column(const std::string& name) const {
  for (size_t i = 0; i < header.size(); ++i)
    if (header[i] == name) return i;
  std::string have;
  for (const auto& h : header) have += (have.empty() ? "" : ", ") + h;
  throw ParseError(file, 0, "no column '" + name + "' (columns: " + have + ")");
}

Table read_table(const std::filesystem::path& file, bool has_header, const std::vector<std::string>& text_columns) {
  std::istringstream in(read_input_file(file, kMaxTableFileBytes, "table"));
  Table t;
  t.file = file;
  std::string line;
  int line_no = 0;
  bool header_done = !has_header;
  std::vector<bool> is_text;
  while (std::getline(in, line)) {
    ++line_no;
    std::string_view sv(line);
    while (!sv.empty() && (sv.back() == '\r' || sv.back() == ' ')) sv.remove_suffix(1);
    if (sv.empty() || sv.front() == '#') continue;
    auto fields = split_fields(sv);
    if (!header_done) {
      t.header.assign(fields.begin(), fields.end());
      t.columns.resize(fields.size());
      for (const auto& name : t.header)
        is_text.push_back(std::find(text_columns.begin(), text_columns.end(), name) != text_columns.end());
      header_done = true;
      continue;
    }
    if (t.columns.empty()) t.columns.resize(fields.size());
    if (fields.size() != t.columns.size())
      throw ParseError(
          file, line_no,
          "expected " + std::to_string(t.columns.size()) + " fields, found " + std::to_string(fields.size()));
    for (size_t c = 0; c < fields.size(); ++c) {
      double v = 0;
      if (c < is_text.size() && is_text[c])
        v = std::numeric_limits<double>::quiet_NaN();
      else if (!parse_number(fields[c], v))
        throw ParseError(file, line_no, "expected a number, found '" + std::string(fields[c]) + "'");
      t.columns[c].push_back(v);
    }
  }
  if (t.rows() == 0) throw ParseError(file, line_no, "expected at least one row of numbers");
  return t;
}

}  // namespace sylva
