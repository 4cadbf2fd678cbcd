#pragma once
// The temporaries of atomic writes (core/atomic_file.h) left in a directory; after any write,
// successful or failed, there must be none.

#include "core/atomic_file.h"

#include <filesystem>
#include <string>
#include <vector>

namespace sylva::test {

inline std::vector<std::string> atomic_temporaries_in(const std::filesystem::path& dir) {
  std::vector<std::string> found;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.starts_with(kAtomicTempPrefix)) found.push_back(name);
  }
  return found;
}

}  // namespace sylva::test
