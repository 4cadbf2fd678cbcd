#pragma once
// One input of each fuzz target (fuzz/fuzz_*.cpp), shared with the regression test that replays the
// crashers kept in tests/data/fuzz/<target>/ (tests/scenes/test_fuzz_regressions.cpp). Each function
// returns the sylva::Error message of a clean refusal, or "" if the input was accepted; anything
// else (a crash, another exception, a hang) is a finding. `source_dir` is the repository.

#include "core/error.h"
#include "core/image.h"
#include "geometry/mesh_io_detail.h"
#include "render/film.h"
#include "scenes/scene_file.h"
#include "scenes/species.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <unistd.h>

namespace sylva::fuzz {

inline std::string refusal(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return {};
}

// Scene files; relative paths resolve in data/examples (where the seed scenes' files are found).
inline std::string scene_input(std::string_view bytes, const std::filesystem::path& source_dir) {
  return refusal([&] { parse_scene(std::string(bytes), "fuzz.toml", source_dir / "data/examples"); });
}

// Species files of every format: the first byte picks the extension (species_file_extensions(),
// modulo), the rest is the file. A parsed species is also generated, at quality 0.25 (fewer leaves,
// same stems): generation is where parameters in range can still hang (issue 16's pruning probe).
inline std::string species_input(std::string_view bytes, const std::filesystem::path& source_dir) {
  if (bytes.empty()) return "empty";
  static const std::vector<std::string> extensions = species_file_extensions();
  const std::string ext = extensions[static_cast<unsigned char>(bytes[0]) % extensions.size()];
  return refusal([&] {
    const Species species = parse_species(std::string(bytes.substr(1)), source_dir / ("data/species/fuzz" + ext));
    TreeOptions options;
    options.quality = 0.25f;
    make_species_model(species, 1, options);
  });
}

inline std::string obj_input(std::string_view bytes) {
  return refusal([&] { mesh_io_detail::parse_obj("fuzz.obj", bytes); });
}

inline std::string ply_input(std::string_view bytes) {
  return refusal([&] { mesh_io_detail::parse_ply("fuzz.ply", bytes); });
}

// Checkpoint films (Film::read). The key a checkpoint must match is taken from the input itself
// (after the 8-byte magic and the 8-byte key size), so inputs reach the fields past the key check.
inline std::string checkpoint_input(std::string_view bytes) {
  std::string key;
  if (bytes.size() >= 16) {
    uint64_t key_size = 0;
    std::memcpy(&key_size, bytes.data() + 8, sizeof(key_size));
    key = std::string(bytes.substr(16, static_cast<size_t>(std::min<uint64_t>(key_size, bytes.size() - 16))));
  }
  std::istringstream in{std::string(bytes)};
  return refusal([&] { Film::read(in, key, "fuzz.checkpoint"); });
}

// EXR inputs of `sylva compare` (read_exr). OpenEXR reads files, so the bytes go to a
// per-process scratch file first (in /dev/shm when there is one).
inline std::string exr_input(std::string_view bytes) {
  static const std::filesystem::path file =
      (std::filesystem::is_directory("/dev/shm") ? std::filesystem::path("/dev/shm")
                                                 : std::filesystem::temp_directory_path()) /
      ("sylva_fuzz_" + std::to_string(::getpid()) + ".exr");
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  const std::string message = refusal([&] { read_exr(file); });
  std::filesystem::remove(file);
  return message;
}

}  // namespace sylva::fuzz
