// core/simd.h gives GLM's bits: each helper against the GLM expression it replaces, on random
// inputs over many magnitudes (where a different order of operations would round differently).
#include "core/rng.h"
#include "core/simd.h"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>

namespace sylva {
namespace {

// A float of random sign and mantissa, exponent in [-20, 20): sums of such differ in their last bits
// unless added in the same order.
float random_float(Pcg32& rng) {
  return (rng.uniform() < 0.5f ? -1.0f : 1.0f) *
         std::ldexp(1.0f + rng.uniform(), static_cast<int>(rng.uniform() * 40) - 20);
}
Vec3 random_vec3(Pcg32& rng) { return {random_float(rng), random_float(rng), random_float(rng)}; }
Mat4 random_affine(Pcg32& rng) {
  Mat4 m(1.0f);
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 3; ++r) m[c][r] = random_float(rng);
  return m;
}

void expect_same_bits(const Vec3& a, const Vec3& b) {
  for (int i = 0; i < 3; ++i) EXPECT_EQ(std::bit_cast<uint32_t>(a[i]), std::bit_cast<uint32_t>(b[i])) << i;
}

TEST(Simd, HelpersGiveGlmsBits) {
  Pcg32 rng(11);
  int order_matters = 0;  // inputs where another order of the same sums would round differently
  for (int trial = 0; trial < 20000; ++trial) {
    const Vec3 a = random_vec3(rng), b = random_vec3(rng);
    const Mat4 m = random_affine(rng);
    expect_same_bits(simd::store(simd::load(a)), a);
    expect_same_bits(simd::store(simd::cross(simd::load(a), simd::load(b))), glm::cross(a, b));
    EXPECT_EQ(std::bit_cast<uint32_t>(simd::dot(simd::load(a), simd::load(b))),
              std::bit_cast<uint32_t>(glm::dot(a, b)));
    expect_same_bits(simd::store(simd::transform(simd::linear_part(m), simd::load(a))), Mat3(m) * a);
    expect_same_bits(simd::store(simd::transform_point(m, simd::load(a))), Vec3(m * Vec4(a, 1.0f)));
    order_matters += (a.x * b.x + a.y * b.y) + a.z * b.z != a.x * b.x + (a.y * b.y + a.z * b.z);
  }
  EXPECT_GT(order_matters, 1000);  // the inputs do tell the orders apart
}

}  // namespace
}  // namespace sylva
