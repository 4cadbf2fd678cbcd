#include "core/data_path.h"

#include "core/error.h"

#include <cstdlib>
#include <system_error>

namespace sylva {

namespace {

// A file every data directory holds: a directory without it is not Sylva's data.
constexpr const char* kDataMarker = "cie1931_2deg_cmf_1nm.csv";

bool holds_data(const std::filesystem::path& dir) {
  std::error_code ec;
  return !dir.empty() && std::filesystem::is_regular_file(dir / kDataMarker, ec);
}

// The data directory when no environment variable names one (found once per process).
std::filesystem::path built_in_data_dir() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const std::filesystem::path beside = exe.parent_path().parent_path() / "share" / "sylva" / "data";
    if (holds_data(beside)) return beside;
  }
  if (holds_data(SYLVA_SOURCE_DATA_DIR)) return SYLVA_SOURCE_DATA_DIR;
  if (holds_data(SYLVA_INSTALL_DATA_DIR)) return SYLVA_INSTALL_DATA_DIR;
  return SYLVA_SOURCE_DATA_DIR;
}

}  // namespace

std::filesystem::path data_dir() {
  for (const char* name : {"SYLVA_DATA_DIR", "SYLVA_DATA"})
    if (const char* env = std::getenv(name); env != nullptr && *env != '\0') return env;
  static const std::filesystem::path built_in = built_in_data_dir();
  return built_in;
}

std::filesystem::path data_file(std::string_view relative) {
  std::filesystem::path p = data_dir() / relative;
  if (!std::filesystem::exists(p))
    throw Error("missing data file " + p.string() + " (set SYLVA_DATA_DIR to Sylva's data/ directory)");
  return p;
}

FileLookup find_named_file(const std::filesystem::path& base_dir, const std::string& name) {
  FileLookup lookup;
  const std::filesystem::path p(name);
  if (p.is_absolute()) {
    lookup.tried.push_back(p);
  } else {
    if (!base_dir.empty()) lookup.tried.push_back(base_dir / p);
    const std::filesystem::path data = data_dir();
    lookup.tried.push_back((data / p).lexically_normal());
    lookup.tried.push_back((data / "examples" / p).lexically_normal());
  }
  for (const std::filesystem::path& candidate : lookup.tried) {
    std::error_code ec;
    if (std::filesystem::exists(candidate, ec)) {
      lookup.found = candidate;
      break;
    }
  }
  return lookup;
}

}  // namespace sylva
