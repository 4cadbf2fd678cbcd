#include "core/data_path.h"

#include "core/error.h"

#include <cstdlib>

namespace sylva {

std::filesystem::path data_dir() {
  if (const char* env = std::getenv("SYLVA_DATA"); env != nullptr && *env != '\0') return env;
  return SYLVA_DATA_DIR;
}

std::filesystem::path data_file(std::string_view relative) {
  std::filesystem::path p = data_dir() / relative;
  if (!std::filesystem::exists(p))
    throw Error("missing data file " + p.string() + " (set SYLVA_DATA to Sylva's data/ directory)");
  return p;
}

}  // namespace sylva
