// 3-D fBm (geometry/solids/fbm.h): range, the proven Lipschitz bound, and the Hurst exponent as the
// slope of the structure function (equivalently of the power spectrum, f^−(1+2H)).

#include "core/rng.h"
#include "geometry/solids/fbm.h"

#include <gtest/gtest.h>

#include <cmath>

namespace sylva {
namespace {

TEST(Fbm, StaysInRangeAndIsDeterministic) {
  const FbmParams p{0.5f, 2.0f, 6, 1.0f, 3};
  Pcg32 rng(1);
  for (int i = 0; i < 10000; ++i) {
    const Vec3 x(rng.uniform(-50, 50), rng.uniform(-50, 50), rng.uniform(-50, 50));
    const float v = fbm(p, x);
    ASSERT_GE(v, -1.0f);
    ASSERT_LE(v, 1.0f);
    ASSERT_EQ(v, fbm(p, x));
  }
}

TEST(Fbm, LipschitzBoundHoldsAndIsNotVacuous) {
  for (const float hurst : {0.2f, 0.5f, 0.9f}) {
    const FbmParams p{hurst, 2.0f, 5, 1.5f, 9};
    const float L = fbm_lipschitz(p);
    Pcg32 rng(2);
    float worst = 0.0f;
    for (int i = 0; i < 200000; ++i) {
      const Vec3 x(rng.uniform(-10, 10), rng.uniform(-10, 10), rng.uniform(-10, 10));
      const float r = std::pow(10.0f, rng.uniform(-3.0f, 0.0f));
      const Vec3 y = x + r * glm::normalize(Vec3(rng.symmetric(), rng.symmetric(), rng.symmetric()) + 1e-6f);
      const float q = std::abs(fbm(p, x) - fbm(p, y)) / glm::length(y - x);
      worst = std::max(worst, q);
    }
    EXPECT_LE(worst, L * 1.001f) << "H = " << hurst;
    EXPECT_GT(worst, 0.2f * L) << "H = " << hurst;  // the bound is within a small factor of the truth
  }
}

// Structure function S(δ) = <(F(x + δ e) − F(x))²> ∝ δ^(2H) for wavelengths between the finest and
// the coarsest octave.
double structure_slope(float hurst) {
  const FbmParams p{hurst, 2.0f, 10, 64.0f, 5};
  Pcg32 rng(7);
  std::vector<double> logd, logs;
  for (double delta = 0.5; delta <= 8.0; delta *= 2.0) {
    double s = 0.0;
    const int n = 40000;
    for (int i = 0; i < n; ++i) {
      const Vec3 x(rng.uniform(-500, 500), rng.uniform(-500, 500), rng.uniform(-500, 500));
      const float a = fbm(p, x), b = fbm(p, x + Vec3(static_cast<float>(delta), 0, 0));
      s += (a - b) * (a - b);
    }
    logd.push_back(std::log(delta));
    logs.push_back(std::log(s / n));
  }
  double md = 0, ms = 0;
  for (size_t i = 0; i < logd.size(); ++i) {
    md += logd[i];
    ms += logs[i];
  }
  md /= static_cast<double>(logd.size());
  ms /= static_cast<double>(logd.size());
  double num = 0, den = 0;
  for (size_t i = 0; i < logd.size(); ++i) {
    num += (logd[i] - md) * (logs[i] - ms);
    den += (logd[i] - md) * (logd[i] - md);
  }
  return num / den;
}

TEST(Fbm, StructureFunctionSlopeIsTwiceHurst) {
  for (const float hurst : {0.3f, 0.5f, 0.8f})
    EXPECT_NEAR(structure_slope(hurst), 2.0 * hurst, 0.15) << "H = " << hurst;
}

}  // namespace
}  // namespace sylva
