// The turbid leaf medium's phase function (render/materials/leaf_medium.h): it integrates to the
// leaf albedo ρ + τ, its limits are the closed forms (2ρ/3π backwards, 2τ/3π forwards), and the
// sampler of the physical process (leaf normal ∝ |n·a|, bi-Lambertian scattering) has the claimed
// density (χ²).

#include "core/rng.h"
#include "render/materials/leaf_medium.h"
#include "tests/support/chi2_directions.h"

#include <gtest/gtest.h>

namespace sylva {
namespace {

const double kMediumAlpha = sidak_alpha(0.01, 2);

Vec3 dir(float theta, float phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

TEST(LeafMedium, PhaseIntegratesToAlbedo) {
  const LeafPhase phase =
      make_leaf_phase(SampledSpectrum(Vec4(0.1f, 0.3f, 0.45f, 0.0f)), SampledSpectrum(Vec4(0.05f, 0.2f, 0.5f, 0.7f)));
  const Vec3 a = glm::normalize(Vec3(0.3f, -0.2f, 0.9f));
  glm::dvec4 sum(0.0);
  double pdf_sum = 0.0;
  const int n = 800;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      const float z = -1.0f + 2.0f * (i + 0.5f) / n, phi = kTwoPi * (j + 0.5f) / (2 * n);
      const Vec3 b = dir(std::acos(z), phi);
      const float w = (2.0f / n) * (kTwoPi / (2 * n));
      sum += glm::dvec4(eval_leaf_phase(phase, a, b).block(0)) * static_cast<double>(w);
      pdf_sum += leaf_phase_pdf(phase, a, b) * w;
    }
  const SampledSpectrum albedo = phase.reflect + phase.transmit;
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(sum[k], albedo[k], 1e-3);
  EXPECT_NEAR(pdf_sum, 1.0, 2e-3);
  // Limits: backwards only reflection, forwards only transmission.
  const SampledSpectrum back = eval_leaf_phase(phase, a, -a), forward = eval_leaf_phase(phase, a, a);
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(back[k], 2.0f * phase.reflect[k] / (3.0f * kPi), 1e-4f);
    EXPECT_NEAR(forward[k], 2.0f * phase.transmit[k] / (3.0f * kPi), 1e-4f);
  }
}

TEST(LeafMedium, SamplerMatchesPdf) {
  for (const float rho : {0.45f, 0.1f}) {
    const LeafPhase phase = make_leaf_phase(SampledSpectrum(rho), SampledSpectrum(0.4f));
    const Vec3 a = glm::normalize(Vec3(0.5f, 0.1f, -0.8f));
    Pcg32 rng(3);
    const Chi2Result r = test::chi2_directions(
        test::DirectionChi2{},
        [&](int) {
          LeafPhaseSample s;
          const Vec2 u1(rng.uniform(), rng.uniform()), u2(rng.uniform(), rng.uniform());
          if (!sample_leaf_phase(phase, a, u1, u2, rng.uniform(), &s)) return Vec3(0.0f);
          EXPECT_NEAR(s.pdf, leaf_phase_pdf(phase, a, s.direction), 1e-4f * s.pdf + 1e-6f);
          return s.direction;
        },
        [&](const Vec3& b) { return static_cast<double>(leaf_phase_pdf(phase, a, b)); });
    EXPECT_GT(r.p_value, kMediumAlpha) << "chi2 " << r.statistic << " rho " << rho;
  }
}

}  // namespace
}  // namespace sylva
