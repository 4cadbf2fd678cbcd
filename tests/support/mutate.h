#pragma once
// Mutated copies of a text for the parsers' robustness tests: truncation, three characters
// replaced by `junk`, or a run of up to 30 characters erased, chosen by trial % 3. Deterministic
// for a given generator state.

#include "core/rng.h"

#include <string>
#include <string_view>

namespace sylva {

inline std::string mutate_text(const std::string& base, int trial, Pcg32& rng, std::string_view junk) {
  std::string text = base;
  const auto at = [&] { return rng.below(static_cast<uint32_t>(text.size())); };
  switch (trial % 3) {
    case 0:
      text.resize(at());
      break;
    case 1:
      for (int k = 0; k < 3; ++k) text[at()] = junk[rng.below(static_cast<uint32_t>(junk.size()))];
      break;
    default:
      text.erase(at(), 1 + rng.below(30));
  }
  return text;
}

}  // namespace sylva
