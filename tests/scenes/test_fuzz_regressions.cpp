// Replays every input in tests/data/fuzz/<target>/ (crashers and hangs the fuzz targets or issue 16
// found, tests/data/fuzz/README.md) through the fuzz targets' own code (fuzz/fuzz_inputs.h): each
// must be accepted or refused with a sylva::Error, within a time limit.

#include "fuzz/fuzz_inputs.h"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>

namespace sylva {
namespace {

namespace fs = std::filesystem;

std::string bytes_of(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(FuzzRegressions, EveryKeptInputIsAcceptedOrRefusedInTime) {
  const fs::path source = SYLVA_SOURCE_DIR;
  const std::map<std::string, std::function<std::string(std::string_view)>> targets{
      {"scene", [&](std::string_view b) { return fuzz::scene_input(b, source); }},
      {"species", [&](std::string_view b) { return fuzz::species_input(b, source); }},
      {"obj", fuzz::obj_input},
      {"ply", fuzz::ply_input},
      {"checkpoint", fuzz::checkpoint_input},
      {"exr", fuzz::exr_input},
  };
  int replayed = 0;
  for (const auto& [name, run] : targets) {
    const fs::path dir = source / "tests/data/fuzz" / name;
    if (!fs::is_directory(dir)) continue;
    for (const auto& entry : fs::directory_iterator(dir)) {
      const auto start = std::chrono::steady_clock::now();
      std::string message;
      EXPECT_NO_THROW(message = run(bytes_of(entry.path()))) << entry.path();
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      EXPECT_LT(seconds, 30.0) << entry.path();
      std::printf("[fuzz regression] %s/%s: %.2f s, %s\n", name.c_str(), entry.path().filename().c_str(), seconds,
                  message.empty() ? "accepted" : message.substr(0, 100).c_str());
      ++replayed;
    }
  }
  EXPECT_GE(replayed, 1);
}

}  // namespace
}  // namespace sylva
