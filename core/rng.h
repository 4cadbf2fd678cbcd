#pragma once
// Random numbers. Every random decision in Sylva flows from an explicit seed; per-pixel-sample and
// per-tree streams are derived by hashing (seed, ids) so results never depend on thread count or
// scheduling (docs/design.md §4).

#include "core/hash.h"  // mix64, hash_ids: seeds of the random streams
#include "core/math.h"  // Vec2, Vec3

#include <cstdint>

namespace sylva {

// PCG32 (O'Neill 2014, pcg32_random_r: XSH-RR output on a 64-bit LCG).
class Pcg32 {
 public:
  Pcg32() = default;
  explicit Pcg32(uint64_t seed, uint64_t stream = 0x853c49e6748fea9bull) { reseed(seed, stream); }

  void reseed(uint64_t seed, uint64_t stream = 0x853c49e6748fea9bull) {
    state_ = 0u;
    inc_ = (stream << 1u) | 1u;
    next_u32();
    state_ += seed;
    next_u32();
  }

  uint32_t next_u32() {
    const uint64_t old = state_;
    state_ = old * 6364136223846793005ull + inc_;
    const uint32_t xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
    const uint32_t rot = static_cast<uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
  }

  // Uniform in [0, 1): the top 24 bits, so the result is exactly representable and never 1.
  float uniform() { return static_cast<float>(next_u32() >> 8) * 0x1p-24f; }
  double uniform_double() {
    const uint64_t hi = next_u32(), lo = next_u32();
    return static_cast<double>(((hi << 32) | lo) >> 11) * 0x1p-53;
  }
  // Uniform in [lo, hi).
  float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }
  // Uniform in [-1, 1): the papers' "±V" variations.
  float symmetric() { return 2.0f * uniform() - 1.0f; }
  // Uniform integer in [0, n), n > 0 (Lemire's unbiased method would be overkill here: n is small).
  uint32_t below(uint32_t n) { return static_cast<uint32_t>((static_cast<uint64_t>(next_u32()) * n) >> 32); }

 private:
  uint64_t state_ = 0x853c49e6748fea9bull;
  uint64_t inc_ = 0xda3e39cb94b95bdbull;
};

// Several draws in one expression, in a fixed order. C++ leaves the evaluation order of function
// arguments unspecified, so `Vec2(rng.uniform(), rng.uniform())` gives GCC and Clang different
// points, trees and images from the same seed. Every vector draw goes through these helpers instead.
// The order is the one GCC gave the old code — last coordinate first — so every tree, golden image
// and determinism hash recorded before the order was made explicit stays bit-identical.
inline Vec2 uniform2(Pcg32& rng) {
  const float y = rng.uniform();
  const float x = rng.uniform();
  return {x, y};
}
inline Vec3 uniform3(Pcg32& rng) {
  const float z = rng.uniform();
  const Vec2 xy = uniform2(rng);
  return {xy.x, xy.y, z};
}
// Uniform in [-1, 1) per coordinate, drawn in the order of uniform2/uniform3.
inline Vec2 symmetric2(Pcg32& rng) { return 2.0f * uniform2(rng) - 1.0f; }
inline Vec3 symmetric3(Pcg32& rng) { return 2.0f * uniform3(rng) - 1.0f; }

}  // namespace sylva
