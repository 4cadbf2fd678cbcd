#pragma once
// Locating the tables Sylva ships in data/ (spectra, sensor responses, colour matching, OCIO config).

#include <filesystem>
#include <string_view>

namespace sylva {

// The data directory: $SYLVA_DATA if set, else the directory configured at build time.
std::filesystem::path data_dir();

// data_dir() / relative; throws sylva::Error naming the path if the file does not exist.
std::filesystem::path data_file(std::string_view relative);

}  // namespace sylva
