#pragma once
// Locating the tables Sylva ships in data/ (spectra, sensor responses, colour matching, OCIO config,
// species, example scenes) and the files scene and species files name.

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace sylva {

// The data directory, the first of:
// 1. $SYLVA_DATA_DIR (or the older name $SYLVA_DATA), when set and not empty;
// 2. an installed tree beside the executable: <prefix>/share/sylva/data for <prefix>/bin/sylva;
// 3. the source tree's data/ the build was configured from (a binary in its build tree);
// 4. the install directory configured at build time (<CMAKE_INSTALL_PREFIX>/share/sylva/data).
// 2–4 count only where the directory holds Sylva's tables; when none does, 3 is returned.
std::filesystem::path data_dir();

// data_dir() / relative; throws sylva::Error naming the path if the file does not exist.
std::filesystem::path data_file(std::string_view relative);

// Where a file named in a scene or species file was found, and every place looked at in order.
struct FileLookup {
  std::filesystem::path found;  // empty when the file is in none of `tried`
  std::vector<std::filesystem::path> tried;
};

// Finds a file named in a parameter file: an absolute name as it is; a relative one against
// `base_dir` (the naming file's folder; skipped when empty), then data_dir(), then
// data_dir()/examples — so an example scene copied anywhere still finds `../species/x.toml`.
FileLookup find_named_file(const std::filesystem::path& base_dir, const std::string& name);

}  // namespace sylva
