// Haze (render/media/haze.h): closed-form optical depth against quadrature, free-flight sampling
// against Beer–Lambert transmittance (homogeneous and exponential, several wavelengths), and the
// Henyey–Greenstein sampler's χ².

#include "core/error.h"
#include "core/rng.h"
#include "core/statistics.h"
#include "render/media/haze.h"
#include "tests/support/chi2_directions.h"

#include <gtest/gtest.h>

#include <cmath>

namespace sylva {
namespace {

HazeDesc homogeneous(float sigma, float top) {
  HazeDesc h;
  h.enabled = true;
  h.extinction_550 = sigma;
  h.top = top;
  return h;
}

HazeDesc exponential(float sigma, float z0, float scale_height) {
  HazeDesc h;
  h.enabled = true;
  h.profile = HazeProfile::Exponential;
  h.extinction_550 = sigma;
  h.base_height = z0;
  h.scale_height = scale_height;
  return h;
}

// τ₀ by the midpoint rule over the extinction profile.
double quadrature_depth(const Haze& haze, const Vec3& o, const Vec3& d, double s0, double s1) {
  constexpr int n = 200000;
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const double s = s0 + (i + 0.5) * (s1 - s0) / n;
    sum += haze.extinction_550(o.z + s * d.z);
  }
  return sum * (s1 - s0) / n;
}

TEST(Haze, OpticalDepthIsTheIntegralOfExtinction) {
  const Haze flat(homogeneous(0.02f, 30.0f));
  const Haze falling(exponential(0.05f, 2.0f, 40.0f));
  const Vec3 o(1, 2, 5);
  for (const Vec3& d : {Vec3(0, 0, 1), Vec3(0, 0, -1), glm::normalize(Vec3(1, 0, 0.3f)),
                        glm::normalize(Vec3(0, 1, -0.2f)), Vec3(1, 0, 0)})
    for (const Haze* h : {&flat, &falling})
      for (const double len : {1.0, 25.0, 120.0}) {
        const double closed = h->optical_depth(o, d, 3.0, 3.0 + len);
        // (The midpoint rule errs by up to σ·step/2 where the ray crosses the top of the layer.)
        EXPECT_NEAR(closed, quadrature_depth(*h, o, d, 3.0, 3.0 + len), 1e-6 * (1 + closed) + 2e-5)
            << d.x << " " << d.y << " " << d.z << " length " << len;
        // The inverse: the distance where the depth from 3 m reaches a part of it.
        if (closed > 0) {
          const double s = h->distance_at_depth(o, d, 3.0, 0.7 * closed);
          ASSERT_LT(s, 3.0 + len);
          EXPECT_NEAR(h->optical_depth(o, d, 3.0, s), 0.7 * closed, 1e-9 * (1 + closed));
        }
      }
  // Above the top of a homogeneous layer nothing; upward through an exponential profile, finite.
  EXPECT_EQ(flat.optical_depth(Vec3(0, 0, 40), Vec3(0, 0, 1), 0, 1e9), 0.0);
  EXPECT_NEAR(falling.optical_depth(Vec3(0, 0, 2), Vec3(0, 0, 1), 0, std::numeric_limits<double>::infinity()),
              0.05 * 40.0, 1e-9);
  EXPECT_TRUE(std::isinf(falling.distance_at_depth(Vec3(0, 0, 2), Vec3(0, 0, 1), 0, 2.5)));
}

TEST(Haze, FreeFlightFollowsBeerLambert) {
  // With albedo 1, E[β·1{the path passes t}] per wavelength must equal exp(−k(λ)·τ₀(t)) when the
  // hero (SampledWavelengths::hero) is each of the carried ones equally often, as the renderer's
  // wavelength sampler makes it; the wavelengths differ, so the MIS weights matter.
  SampledWavelengths wl;
  wl.lambda_nm = SampledSpectrum(Vec4(420.0f, 550.0f, 700.0f, 900.0f));
  struct Case {
    HazeDesc desc;
    Vec3 o, d;
    float t;
  };
  const Case cases[] = {
      {homogeneous(0.03f, 100.0f), Vec3(0, 0, 1), glm::normalize(Vec3(1, 0, 0.1f)), 40.0f},
      {exponential(0.08f, 0.0f, 15.0f), Vec3(0, 0, 1), glm::normalize(Vec3(0.3f, 1, 0.4f)), 30.0f},
      {exponential(0.02f, 10.0f, 8.0f), Vec3(0, 0, 20), glm::normalize(Vec3(1, 0, -0.5f)), 35.0f},
  };
  int index = 0;
  for (const Case& c : cases) {
    HazeDesc desc = c.desc;
    desc.albedo = 1.0f;
    const Haze haze(desc);
    const SampledSpectrum expected = haze.transmittance(c.o, c.d, c.t, wl);
    Pcg32 rng(91 + index++);
    constexpr int n = 200000;
    SampledSpectrum sum(0.0f), sum2(0.0f);
    for (int i = 0; i < n; ++i) {
      SampledWavelengths hero = wl;
      hero.hero = i % kLambdaCount;
      SampledSpectrum beta(1.0f), ratio(1.0f);
      const float s = haze.sample_scattering(c.o, c.d, c.t, hero, rng.uniform(), beta, ratio);
      EXPECT_NEAR(average(ratio), 1.0f, 1e-5f);
      if (s < c.t) continue;
      for (int k = 0; k < kLambdaCount; ++k) {
        const float b = beta[k];
        sum[k] += b;
        sum2[k] += b * b;
      }
    }
    for (int k = 0; k < kLambdaCount; ++k) {
      const double mean = sum[k] / n, se = std::sqrt(std::max(0.0, sum2[k] / n - mean * mean) / n);
      EXPECT_LT(std::abs(mean - expected[k]), 4.5 * se + 1e-6)
          << "case " << index << " λ " << wl.lambda_nm[k] << ": " << mean << " vs " << expected[k] << " ± " << se;
      EXPECT_GT(expected[k], 0.05f);
      EXPECT_LT(expected[k], 0.95f);
    }
  }
}

TEST(Haze, HenyeyGreensteinChi2) {
  const double alpha = sidak_alpha(0.01, 4);
  const Vec3 a = glm::normalize(Vec3(0.3f, -0.5f, 0.8f));
  int index = 0;
  for (const float g : {-0.6f, 0.0f, 0.4f, 0.85f}) {
    Pcg32 rng(300 + index++);
    const auto r = test::chi2_directions(
        {}, [&](int) { return sample_henyey_greenstein(a, g, Vec2(rng.uniform(), rng.uniform())); },
        [&](const Vec3& d) { return henyey_greenstein(glm::dot(a, d), g); });
    EXPECT_GT(r.p_value, alpha) << "g " << g << " chi2 " << r.statistic << " dof " << r.dof;
  }
}

TEST(Haze, RejectsBadParameters) {
  HazeDesc h = homogeneous(0.01f, 10.0f);
  h.albedo = 1.5f;
  EXPECT_THROW(Haze{h}, Error);
  h = homogeneous(0.01f, std::numeric_limits<float>::infinity());
  EXPECT_THROW(Haze{h}, Error);
  h = exponential(0.01f, 0.0f, 10.0f);
  h.g = 1.0f;
  EXPECT_THROW(Haze{h}, Error);
}

}  // namespace
}  // namespace sylva
