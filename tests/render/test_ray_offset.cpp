// offset_ray_origin (Wächter & Binder, Ray Tracing Gems ch. 6) runs the three coordinates in one
// SSE register: it must give the scalar method's bits, far from the origin (p's bits moved by
// 256·n ulps), near it (|p| < 1/32: p + n/65 536), on either side of zero and at signed zeros.
#include "core/rng.h"
#include "render/integrator.h"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>

namespace sylva {
namespace {

float scalar_offset(float p, float n) {
  const int of = static_cast<int>(256.0f * n);
  const float moved = std::bit_cast<float>(std::bit_cast<int32_t>(p) + (p < 0 ? -of : of));
  return std::abs(p) < 1.0f / 32.0f ? p + (1.0f / 65536.0f) * n : moved;
}

TEST(RayOffset, GivesTheScalarMethodsBits) {
  Pcg32 rng(5);
  int near = 0, far = 0;
  for (int trial = 0; trial < 100000; ++trial) {
    Vec3 p, n = glm::normalize(Vec3(rng.symmetric(), rng.symmetric(), rng.symmetric()) + Vec3(1e-6f));
    for (int i = 0; i < 3; ++i) {
      // Magnitudes from 1e-4 to 1e4 m, a few exact zeros of either sign.
      const float magnitude = std::pow(10.0f, rng.uniform(-4.0f, 4.0f));
      p[i] = trial % 97 == 0 ? (i == 0 ? 0.0f : -0.0f) : rng.symmetric() * magnitude;
      (std::abs(p[i]) < 1.0f / 32.0f ? near : far) += 1;
    }
    const Vec3 q = offset_ray_origin(p, n);
    for (int i = 0; i < 3; ++i)
      ASSERT_EQ(std::bit_cast<uint32_t>(q[i]), std::bit_cast<uint32_t>(scalar_offset(p[i], n[i])))
          << "p " << p[i] << " n " << n[i];
  }
  EXPECT_GT(near, 10000);
  EXPECT_GT(far, 10000);
}

}  // namespace
}  // namespace sylva
