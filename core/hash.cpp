#include "core/hash.h"

#include <fmt/core.h>

#include <cstring>

namespace sylva {

Fnv1a64& Fnv1a64::add(const void* data, size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < bytes; ++i) h_ = (h_ ^ p[i]) * kPrime;
  return *this;
}

uint64_t fnv1a64(std::string_view text) { return Fnv1a64().add(text).value(); }

WordHash64& WordHash64::add(const void* data, size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  size_t i = 0;
  for (; i + 8 <= bytes; i += 8) {
    uint64_t w;
    std::memcpy(&w, p + i, 8);
    h_ = mix64(h_ ^ w);
  }
  uint64_t tail = bytes;
  for (; i < bytes; ++i) tail = (tail << 8) | p[i];
  h_ = mix64(h_ ^ tail);
  return *this;
}

std::string hex64(uint64_t h) { return fmt::format("{:016x}", h); }

}  // namespace sylva
