// The inline trigonometry and exponential (core/fast_math.h) against double precision, over a dense
// sweep of each domain the renderer uses, plus the edge values.
#include "core/fast_math.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace sylva {
namespace {

constexpr int kSteps = 2'000'003;  // odd, so the sweeps do not step in round fractions of π

// select() is c ? a : b bit for bit: signed zeros, infinities and NaN payloads included.
TEST(FastMath, SelectPicksTheBitsOfOne) {
  const float values[] = {0.0f,
                          -0.0f,
                          1.5f,
                          -3.25e-38f,
                          std::numeric_limits<float>::infinity(),
                          -std::numeric_limits<float>::infinity(),
                          std::bit_cast<float>(0x7fc00123u),
                          std::numeric_limits<float>::denorm_min()};
  for (float a : values)
    for (float b : values) {
      EXPECT_EQ(std::bit_cast<uint32_t>(select(true, a, b)), std::bit_cast<uint32_t>(a));
      EXPECT_EQ(std::bit_cast<uint32_t>(select(false, a, b)), std::bit_cast<uint32_t>(b));
    }
}

TEST(FastMath, SinCosWithinFewE7) {
  double worst = 0;
  for (int k = 0; k <= kSteps; ++k) {
    const float x = static_cast<float>(-2.0 * M_PI + 4.0 * M_PI * k / kSteps);
    const SinCos sc = sincos_fast(x);
    worst = std::max({worst, std::abs(sc.sin - std::sin(static_cast<double>(x))),
                      std::abs(sc.cos - std::cos(static_cast<double>(x)))});
  }
  EXPECT_LT(worst, 3e-7);
  // Quadrant edges and signs.
  for (const float x : {0.0f, kPi / 2, kPi, 1.5f * kPi, kTwoPi, -kPi / 2, -kPi, 0.25f * kPi, -0.75f * kPi}) {
    const SinCos sc = sincos_fast(x);
    EXPECT_NEAR(sc.sin, std::sin(static_cast<double>(x)), 3e-7) << x;
    EXPECT_NEAR(sc.cos, std::cos(static_cast<double>(x)), 3e-7) << x;
  }
  EXPECT_EQ(sincos_fast(0.0f).sin, 0.0f);
  EXPECT_EQ(sincos_fast(0.0f).cos, 1.0f);
}

TEST(FastMath, Atan2WithinFewE7AllQuadrants) {
  double worst = 0;
  for (int k = 0; k <= kSteps; ++k) {
    const double phi = -M_PI + 2.0 * M_PI * k / kSteps;
    for (const double r : {1.0, 1e-3, 7.5}) {
      const auto x = static_cast<float>(r * std::cos(phi)), y = static_cast<float>(r * std::sin(phi));
      worst = std::max(worst, std::abs(atan2_fast(y, x) - std::atan2(static_cast<double>(y), static_cast<double>(x))));
    }
  }
  EXPECT_LT(worst, 5e-7);
  EXPECT_EQ(atan2_fast(0.0f, 0.0f), 0.0f);
  EXPECT_NEAR(atan2_fast(1.0f, 0.0f), M_PI / 2, 2e-7);
  EXPECT_NEAR(atan2_fast(-1.0f, 0.0f), -M_PI / 2, 2e-7);
  EXPECT_NEAR(atan2_fast(0.0f, -1.0f), M_PI, 3e-7);
  EXPECT_NEAR(atan2_fast(1.0f, 1.0f), M_PI / 4, 2e-7);
}

TEST(FastMath, AcosWithinFewE7) {
  double worst = 0;
  for (int k = 0; k <= kSteps; ++k) {
    const float x = static_cast<float>(-1.0 + 2.0 * k / kSteps);
    worst = std::max(worst, std::abs(acos_fast(x) - std::acos(static_cast<double>(x))));
  }
  EXPECT_LT(worst, 6e-7);  // 4.3·10⁻⁷ near −1, where π − r adds float(π)'s own error
  EXPECT_EQ(acos_fast(1.0f), 0.0f);
  EXPECT_NEAR(acos_fast(-1.0f), M_PI, 3e-7);
  EXPECT_NEAR(acos_fast(0.0f), M_PI / 2, 2e-7);
  EXPECT_EQ(acos_fast(1.5f), 0.0f);  // clamped
}

TEST(FastMath, ExpWithinFewE7Relative) {
  double worst = 0;
  for (int k = 0; k <= kSteps; ++k) {
    const float x = static_cast<float>(-87.0 + 175.0 * k / kSteps);
    const double e = std::exp(static_cast<double>(x));
    worst = std::max(worst, std::abs(exp_fast(x) - e) / e);
  }
  EXPECT_LT(worst, 5e-7);
  EXPECT_EQ(exp_fast(0.0f), 1.0f);
  EXPECT_EQ(exp_fast(-100.0f), 0.0f);
  EXPECT_EQ(exp_fast(-std::numeric_limits<float>::infinity()), 0.0f);
  EXPECT_TRUE(std::isfinite(exp_fast(88.0f)));
}

}  // namespace
}  // namespace sylva
