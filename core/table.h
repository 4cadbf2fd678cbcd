#pragma once
// Reading the numeric text tables in data/: '#' comment lines, one header row, then rows of numbers
// separated by commas, tabs or spaces. A blank field is NaN ("not defined at that wavelength").

#include <filesystem>
#include <string>
#include <vector>

namespace sylva {

struct Table {
  std::filesystem::path file;
  std::vector<std::string> header;           // empty when the file has no header row
  std::vector<std::vector<double>> columns;  // columns[c][row]

  // Index of the named column; throws ParseError naming the file and the columns it has.
  size_t column(const std::string& name) const;
  size_t rows() const { return columns.empty() ? 0 : columns[0].size(); }
};

// Throws ParseError(file:line: ...) for a malformed row, sylva::Error for an unreadable file.
// `has_header` false for files that are all numbers (e.g. PROSPECT tables). Columns named in
// `text_columns` may hold text; they are read as NaN.
Table read_table(const std::filesystem::path& file, bool has_header = true,
                 const std::vector<std::string>& text_columns = {});

}  // namespace sylva
